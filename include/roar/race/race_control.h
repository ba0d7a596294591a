#pragma once
// The rules of a race, without ROS: lap and sector timing per car (LapTimer), incidents (barrier and car
// contacts, leaving the track limits) with a time penalty or a ROAR-style respawn at the last waypoint
// passed (the clock keeps running), standings with the gap to the leader, and the end of the race.
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "roar/race/lap_timer.h"
#include "roar/track/track.h"
#include "roar/vehicle/car_size.h"

namespace roar::race {

enum class IncidentRule { kIgnore, kPenalty, kRespawn };

struct RaceRules {
  int laps = 3;
  IncidentRule collision = IncidentRule::kPenalty;
  double collision_penalty = 5.0;  // s per contact with a barrier or another car
  IncidentRule track_limits = IncidentRule::kPenalty;
  double track_limits_penalty = 5.0;  // s per excursion
  // The car has left the track when base_link is this far beyond the road edge (half the car's width:
  // all four wheels are off).
  double track_limits_margin = 0.93;  // m
  double contact_merge = 0.5;         // s: contacts closer together than this are one incident
  double overtake_hysteresis = 3.0;   // m one car must be ahead of the other for a change of order to count
  double car_length = vehicle::kDefaultCarLength;  // m, for judging who was at fault in a contact between cars
  // A car is in traffic while another car (of any lap) is on the road ahead of it within a car's length
  // plus this many seconds at its speed.
  double traffic_gap = 1.0;  // s
  // A car whose driver is lost (stopped by the simulator) waits this long for it; a driver back in time
  // costs the car the time it stood, one that is not retires it, as of when it was lost.
  double driver_grace = 30.0;  // s
};

struct Incident {
  double time = 0.0;  // s, simulated
  std::string kind;   // "barrier", "car <name>" or "track limits"
  // A contact between cars, once both cars' motion is known (RaceControl::updateMotion): the car at fault
  // (empty: a racing incident, nobody) and how they met ("from behind", "alongside"). Only the car at
  // fault is penalised; before motion is known, both are.
  std::string at_fault;
  std::string contact;
  double penalty = 0.0;  // s added to the car's race time
  bool respawn = false;  // the car is to be put back on the track at respawn_pose
  track::TrackPose respawn_pose;
};

struct CarRecord {
  CarRecord(std::string car, LapTimer lap_timer) : name(std::move(car)), timer(std::move(lap_timer)) {}
  std::string name;
  LapTimer timer;
  std::vector<Incident> incidents;
  double penalties = 0.0;  // s
  int barrier_contacts = 0, car_contacts = 0, track_limit_violations = 0;
  bool finished = false;
  double finish_time = 0.0;      // s when the last lap was completed
  std::string retired;           // why the car left the race before finishing ("driver lost"); empty: it did not
  double retire_time = 0.0;      // s
  double driver_lost_at = -1.0;  // s when its driver was lost; negative: its driver answers
  double last_time = 0.0;
  double last_contact = -1e9;
  bool off_track = false;
  std::vector<double> passage;      // s at which the car first covered each 10 m since its first crossing
  double time_in_traffic = 0.0;     // s in traffic (RaceRules::traffic_gap) since the start
  std::vector<double> lap_traffic;  // s in traffic in each completed lap
  double traffic_this_lap = 0.0;    // s in traffic in the lap under way
  // (time, distance covered) over the last seconds: where the car was when another car's position of the
  // same moment is judged (odometry of different cars arrives in any order).
  std::deque<std::pair<double, double>> recent;
  bool motion_known = false;  // position, yaw and velocity below are set (updateMotion)
  Eigen::Vector2d position = Eigen::Vector2d::Zero(), velocity = Eigen::Vector2d::Zero();
  double yaw = 0.0;
};

// One car getting by another on the road: the passer's distance since the start line goes from behind the
// other's to ahead of it (by more than RaceRules::overtake_hysteresis, so that cars side by side do not
// swap back and forth).
struct Overtake {
  double time = 0.0;  // s, simulated
  std::string passer;
  std::string passed;
  int lap = 0;     // the passer's lap (1 = the first)
  double s = 0.0;  // m along the track's centre line where it happened
};

struct Standing {
  std::string name;
  int position = 0;          // 1 = leading
  double gap_to_leader = 0;  // s (penalties included once the race is run)
};

class RaceControl {
 public:
  // Throws std::invalid_argument for no cars, a repeated name or non-positive laps.
  RaceControl(const track::Track& track, RaceRules rules, const std::vector<std::string>& cars);

  // The car's position (map frame, z the height: LapTimer::update) at a simulated time; returns the lap it
  // completed, if any. An incident (track limits) is appended to `incident` when given.
  std::optional<LapRecord> updatePosition(const std::string& car, double time, const Eigen::Vector3d& position,
                                          std::optional<Incident>* incident = nullptr);
  // The car's heading (rad) and velocity (m/s, map frame) with its position: what a contact between cars
  // is judged by (race/contact_fault.h).
  void updateMotion(const std::string& car, const Eigen::Vector2d& position, double yaw,
                    const Eigen::Vector2d& velocity);
  // A contact reported by the simulator; returns the incident it makes, if it makes one.
  std::optional<Incident> updateContact(const std::string& car, double time, const std::string& other);

  // The car is out of the race (its driver died, say): it is no longer waited for, and is classified
  // behind every car still running, by distance covered. A finished car cannot retire.
  void retire(const std::string& car, double time, const std::string& reason);
  // The car's driver stopped answering at `time` / answers again. A car whose driver stays lost for
  // rules().driver_grace is retired "driver lost" by retireLostDrivers (race_control_test).
  void driverLost(const std::string& car, double time);
  void driverBack(const std::string& car);
  // The cars retired now, at simulated time `now`.
  std::vector<std::string> retireLostDrivers(double now);
  bool anyFinisher() const;
  bool finished() const;  // every car has completed its laps or retired
  std::vector<Standing> standings() const;
  const CarRecord& car(const std::string& name) const;
  const std::map<std::string, CarRecord>& cars() const { return cars_; }
  // s from the start signal to the car's finish (or its last position), penalties included.
  double raceTime(const std::string& name) const;
  // Time lost in traffic: over the laps after the first (the start is traffic for everyone), each lap
  // with time in traffic against the car's best lap without any; NaN while it has no such clean lap.
  double timeLostInTraffic(const std::string& name) const;
  // Every pass so far, in order (lapping a car is not counted as a pass).
  const std::vector<Overtake>& overtakes() const { return overtakes_; }
  const RaceRules& rules() const { return rules_; }
  const track::Track& track() const { return track_; }

 private:
  CarRecord& record(const std::string& name);
  void detectOvertakes(const std::string& name, double time);
  // Whether another car was on the road just ahead of `car` at `time` (when it had covered `covered` m
  // at `speed` m/s).
  bool inTraffic(const CarRecord& car, double time, double covered, double speed) const;
  static std::optional<double> distanceAt(const CarRecord& car, double time);
  Incident makeIncident(CarRecord& car, double time, const std::string& kind, IncidentRule rule, double penalty);

  const track::Track& track_;
  RaceRules rules_;
  std::map<std::string, CarRecord> cars_;
  std::vector<Overtake> overtakes_;
  double start_time_ = std::numeric_limits<double>::quiet_NaN();
  std::map<std::pair<std::string, std::string>, int> order_;  // +1: first ahead of second, -1: behind
};

// results.yaml (per car: laps, sectors, incidents, penalties, total time), laps.csv (car, lap, lap time,
// sector times) and sectors.csv (car, lap, sector, time) in `dir`, created if missing. `run`, when not
// empty, names the run the results are of (race_control: the ROS launch's run_id), so that a reader of a
// folder that several races wrote to can tell whose results it holds.
// `status` in results.yaml: every car finished (or retired), the time limit ran out, the map changed under
// the race, or the simulator died (aborted).
// kAborted: the simulator died under the race.
// kRunning: the results so far, written after every lap so that a race_control killed mid-race loses none.
enum class RaceOutcome { kFinished, kTimedOut, kInterrupted, kAborted, kRunning };
const char* outcomeName(RaceOutcome outcome);
// The outcome as race_control's summary says it: "finished", "timed out", "aborted", ...
const char* outcomeWords(RaceOutcome outcome);

// What race_control saw when its loop stopped.
struct RaceEnd {
  bool complete = false;        // every car finished its laps or retired (RaceControl::finished)
  bool any_finisher = false;    // a car finished its laps (RaceControl::anyFinisher)
  bool out_of_time = false;     // the simulated time limit passed before the race was complete
  bool simulator_lost = false;  // the simulator fell silent and stopped answering
};
struct RaceVerdict {
  RaceOutcome outcome = RaceOutcome::kAborted;
  std::string reason;  // why a complete race is no result; empty otherwise
};
// Finished when complete with a finisher; a complete race every car retired from (drivers lost, the
// controller killed), a lost simulator, or a run shut down before the end and its time limit is aborted;
// otherwise timed out. race_control_test RaceEndsAreJudgedAsRaceControlReportsThem.
RaceVerdict judgeRaceEnd(const RaceEnd& end);

// A car's line in race_control's summary: position, laps (and retirement), best lap, gap, penalties,
// contacts, track limits, time in traffic and what it cost. race_control_test StandingLineSaysTheCarsRace.
std::string standingLine(const RaceControl& race, const Standing& standing);
// How far the race's recorder got: a recorder killed mid-race leaves a bag short of the finish (and
// unindexed, .active), which results.yaml then says.
struct RecordingState {
  double recorded_until = 0.0;  // s: the last simulated time the recorder reported written
  bool complete = false;        // it reached the finish
};
// results.yaml, laps.csv and sectors.csv in `dir`, each written beside and renamed into place, so a reader
// (or a kill mid-write) sees the previous whole file or the new one (race_control_test).
void writeResults(const std::string& dir, const RaceControl& race, RaceOutcome outcome, const std::string& run = "",
                  const std::optional<RecordingState>& recording = std::nullopt);

}  // namespace roar::race

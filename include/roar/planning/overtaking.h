#pragma once
// Wheel-to-wheel racing on the racing line: each tick, a car's window ahead is chosen among candidate
// trajectories that leave the racing line sideways (a smooth lateral shift, clamped inside the road) or
// stay on it, each with the speed profile of its own path and the car's limits. Every other car is
// predicted along the racing line at its speed, keeping its lateral place; a candidate is kept only while
// the predicted gap to every car alongside or ahead stays above the cars' size plus a margin over the
// horizon. The one that gets furthest in the horizon wins; a pass once committed keeps its side until it
// is complete (the passed car behind), or aborts to following when its side closes. A car that has
// another alongside holds its lateral place instead of moving back onto the line into it (racecraft:
// leave a car's width).
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "roar/planning/trajectory.h"
#include "roar/planning/vehicle_limits.h"
#include "roar/track/track.h"
#include "roar/vehicle/slipstream.h"

namespace roar::planning {

// Another car as the planner sees it, in the racing line's terms.
struct TrafficCar {
  std::string name;
  double s = 0.0;        // m along the racing line
  double lateral = 0.0;  // m left of the racing line
  double speed = 0.0;    // m/s
  // Its recent speed as a share of the racing line's where it was (smoothed over a second or so); 0:
  // unknown, the share of this moment is taken. How fast it is predicted to go on.
  double line_share = 0.0;
  double lateral_speed = 0.0;  // m/s leftwards across the racing line (smoothed); 0: unknown or none
  bool lapping = false;        // a lap or more ahead of the car planned for in the race (a blue flag for it)
  // m/s the car has been seen held to whatever the line's speed (a pace car, a scripted car): it is
  // predicted no faster. 0: none seen.
  double held_speed = 0.0;
  // m/s leftwards across the racing line this moment (its velocity's, not smoothed): a car turning across
  // is seen moving before its place has. NaN: unknown, lateral_speed is taken.
  double lateral_velocity = std::numeric_limits<double>::quiet_NaN();
};

struct OvertakeOptions {
  double car_length = vehicle::kDefaultCarLength;  // m, every car's (bumper to bumper)
  double car_width = vehicle::kDefaultCarWidth;    // m
  double lateral_margin = 0.9;       // m of air kept beside another car (to start a move; half of it to go on with one)
  double longitudinal_margin = 1.5;  // m kept to the car ahead or behind when beside it in the plan
  // m kept inside the road edge (beyond half the car's width): the controller's error on a moving line
  double edge_margin = 1.0;
  double horizon = 6.0;  // s over which other cars are predicted and candidates compared
  // s over which a lateral move is made (and undone) at the car's speed: 2.5 s asks about 2.8 m/s^2 of
  // sideways acceleration for a 3 m move; 1.5 s asked 7.7, all the grip, and cars ran wide at Monza.
  double shift_time = 2.5;
  double min_shift_length = 20.0;  // m, at least
  double min_gain = 4.0;           // m further in the horizon a pass must get than following
  double follow_gap = 12.0;        // m, centre to centre, kept behind a car followed
  double sample_step = 2.0;        // m between the points checked against other cars
  // A pass is considered only for a car ahead within this many seconds at the car's speed (plus a car's
  // length), and given up when the car passed gets half as far again away: a car far ahead is caught on
  // the racing line, not on a line beside it.
  double engage_time = 2.0;     // s
  double min_pass_speed = 8.0;  // m/s the car must be doing to start a pass (not from the grid)
  int abort_plans = 3;          // plans in a row a committed pass must look blocked or not worth it to be given up
  double stall_time = 3.0;      // s a committed pass may go without gaining a metre on the car before it is given up
  double plan_period = 0.05;    // s between plans (the odometry's period)
  int retry_plans = 60;         // plans (ticks) after an aborted pass before another on the same car
  // s ahead within which a conflict predicted for a pass drawn level with the car it passes gives the pass
  // up; one predicted later is left to the plans to come, which can still drop back from it (at the
  // horizon, 6 s, every conflict counts: passes level at 38 m/s were given up for a 2 cm squeeze 5.8 s on).
  double abort_time = 3.0;
  // The guard under every plan: a car ahead in the plan's path (laterally within the cars' width plus
  // guard_lateral) is followed at least a car's length plus longitudinal_margin plus guard_time at speed behind.
  // 0.15 s, not 0.25: at 0.25 a car 5% faster sat 20 m behind on a straight, too far back to draw alongside
  // within the horizon; 0.15 gets the fields nearer pace order with no contact (doc/traffic_history.md).
  double guard_lateral = 0.4;  // m
  double guard_time = 0.15;    // s
  // The guard holds the car to the speed of the car ahead from where it would come within the gap of that
  // car as it is predicted to go on, not from the gap behind where it is now (which, at speed, kept a car
  // 5% faster tens of metres further back than the gap, never closing up). Off by default: it sorts fields
  // nearer pace order at the cost of contacts (doc/traffic_history.md).
  bool guard_predicted = false;
  double max_pass_offset = 5.0;  // m from the racing line a pass may go
  // Share of the plan's grip a path off the racing line is planned with where it moves across the line (a
  // steady offset is a line of its own, on all the grip).
  // 0.8 held the passer back while pulling out behind a slow car (doc/traffic_history.md: 0.92 and 0.95
  // complete more passes at more speed; at 0.97-1.0 cars spin or leave the road at Roar Sprint).
  double offline_grip = 0.92;
  // Share of the plan's grip a car still moving sideways after a move (back onto the line from a pass, say)
  // is planned with for the next 2 s at its speed, on the line or in a lane it holds. At offline_grip (0.92)
  // a car that crossed the line at 2 m/s at 60 m/s into a braking curve slid off the road, 1 race in 16 of
  // Roar Speedway's pace-car field (doc/traffic_history.md).
  double settle_grip = 0.85;
  // s over which a car without a plan to go by is predicted to go on moving sideways as it is.
  double lateral_lookahead = 1.0;
  // m a car may be off its own last plan (sideways) for that plan to be taken as its prediction.
  double plan_trust = 0.75;
  double rejoin_time = 0.5;
  // Blue flags: a car about to be lapped (a car a lap up within this many seconds behind, at its speed)
  // moves aside, to the side with more room, and keeps its pace until it has been lapped. Off by default:
  // see README, Racing stack (a lapped car rejoining behind the car that lapped it in a slow corner touched it once).
  bool blue_flags = false;
  double blue_flag_time = 3.0;  // s at speed behind within which a car a lap up is let by
  // Defending: a car on its line at racing speed, with another closing from behind and pulling out to
  // pass, makes one move across to cover that side (at most defend_shift, only while the move keeps clear
  // of everyone, and held at most defend_hold); no second move while that car stays near, and once it is
  // alongside the defender holds its place (leaving it a car's width). Off by default: it makes passes
  // harder (doc/traffic_history.md).
  bool defend = false;
  double defend_time = 1.0;                         // s at speed behind within which a car is defended against
  double defend_shift = vehicle::kDefaultCarWidth;  // m at most the defensive move goes across (a car's width)
  double defend_hold = 4.0;  // s at most a defensive move is held before the car goes back to its line
  // The wake model the simulator applies (sim/slipstream.h): a car close behind the car it would pass
  // plans the pass with the speed the tow gives it on the straight, and pulls out with it (the slingshot).
  vehicle::SlipstreamOptions slipstream;
  // Keep each plan's predictions of the cars around it for predictions() (rviz): off, they cost nothing.
  bool keep_predictions = false;
};

// Another car as a car's plan predicted it: where it would be, from the moment of the plan on, every
// `step` seconds over the horizon (map frame). What rviz shows of a car's view of the cars around it.
struct PredictedPath {
  std::string name;
  double step = 0.5;  // s
  std::vector<Eigen::Vector2d> positions;
};

enum class RaceMode { kRacingLine, kFollow, kPass, kHold, kYield, kDefend };
const char* raceModeName(RaceMode mode);

struct RaceDecision {
  RaceMode mode = RaceMode::kRacingLine;
  int side = 0;           // kPass: +1 left of the car passed, -1 right; kYield, kDefend: the side moved to
  std::string other;      // the car followed, passed, let by or defended against
  double offset = 0.0;    // m left of the racing line the plan goes to
  double progress = 0.0;  // m the plan gets in the horizon
  // The lateral move under way: from `ramp_from` metres at line s `ramp_s`, reaching `offset` a
  // shift_length later. Kept from tick to tick, so that the move is made rather than restarted.
  double ramp_s = 0.0;
  double ramp_from = 0.0;
  // m/s the car had where the move began: the move takes shift_time at that speed (0: the racing line's).
  double ramp_speed = 0.0;
};

// The decision in words, for logs and rviz: "pass pace on the left", "follow rival", "racing line", ...
std::string describe(const RaceDecision& decision);

class OvertakePlanner {
 public:
  // line: the closed racing trajectory every car follows; track: its road (for the edges).
  OvertakePlanner(const track::Track& track, Trajectory line, const VehicleLimits& limits, OvertakeOptions options);

  // The window (behind .. ahead metres around s) for `car` at (s, lateral, speed) on the racing line,
  // with the others of `traffic` (the car itself may be in it; it is skipped by name), driven at `pace`
  // (the share of the line's speeds the car is planned at).
  Trajectory plan(const std::string& car, double s, double lateral, double speed,
                  const std::vector<TrafficCar>& traffic, double behind, double ahead, double pace = 1.0);
  // What the last plan for `car` chose.
  RaceDecision decision(const std::string& car) const;
  // What the last plan for `car` predicted of the cars near it (alongside or ahead in its window); empty
  // unless OvertakeOptions::keep_predictions.
  std::vector<PredictedPath> predictions(const std::string& car) const;
  const Trajectory& line() const { return line_; }

  // Room from the racing line to the left and right road edges at line s (m, both positive when inside).
  double roomLeft(double s) const;
  double roomRight(double s) const;
  // The share of the lap from which a lane runs beside a car on the racing line, on the side `side`
  // (+1 left, -1 right), for at least `run` metres on: room for a passer (its width and air from the
  // car, its edge margin from the road's edge), where it could stay alongside that far. A pass gaining a
  // fraction f of its speed on the car needs about 2 (car_length + longitudinal_margin) / f metres.
  double laneShare(int side, double run) const;
  // Metres on from line s (up to `longest`) over which a pass under way has room beside a car `beside`
  // metres towards the side `side` of the racing line (its lateral place times side).
  double laneRun(int side, double s, double beside, double longest) const;

  // The racing line's window moved sideways: `from` metres before line s `ramp_s`, `to` a shift_length
  // after, a smooth step between (clamped inside the road); its speeds planned afresh for the new path.
  // back_s: where (window s) the move is undone again, back onto the racing line (infinite: never).
  // drag_share: of the free-air drag the speeds are planned with (below 1: in a car's slipstream).
  // for_pass: planned as a pass is, more cautiously (the edge margin kept at apexes, the curvature of the
  // moved points differenced); otherwise exactly, and a path moved by nothing is the racing line.
  // settle_s: up to this line s the path is planned on settle_grip wherever it is (a car still moving
  // sideways from a move it has just made). ramp_speed: m/s the car had at ramp_s, the move made in
  // shift_time at that speed where it is below the racing line's there (0: at the line's).
  Trajectory shifted(const Trajectory& window, double ramp_s, double from, double to,
                     double back_s = std::numeric_limits<double>::infinity(), double drag_share = 1.0,
                     bool for_pass = false, double settle_s = -std::numeric_limits<double>::infinity(),
                     double ramp_speed = 0.0) const;

 private:
  struct Candidate {
    Trajectory window;
    RaceDecision decision;
    bool clear = true;
  };
  // m, centre to centre, within which two cars are level (a car's length and the longitudinal margin).
  double levelDistance() const { return options_.car_length + options_.longitudinal_margin; }
  // m of road a lane beside a car on the racing line needs from the line to the edge: the passer's width
  // and margin_share of the air from the car, half its own width and its edge margin.
  double laneNeed(double margin_share) const;
  // The window moved as a decision's move goes (from ramp_from at ramp_s to offset, at ramp_speed), planned
  // as any move but a pass is, in free air (settle_s as above).
  Trajectory shifted(const Trajectory& window, const RaceDecision& move,
                     double settle_s = -std::numeric_limits<double>::infinity()) const;
  // The window's speeds as a car in a slipstream (drag_share of its drag) can drive them: higher where the
  // engine, not the grip, sets them. Never lower (braking points are the free-air ones).
  Trajectory towed(const Trajectory& window, double drag_share) const;
  // Another car's predicted motion over the horizon: metres ahead of the planning car's s every
  // kPredictionStep seconds. It keeps the share of the racing line's speed it has now (a slow car stays
  // slow, one braking for a corner speeds up out of it) and its lateral place.
  // Its lateral place is taken from its own last plan where it has one (a car moving over is seen moving
  // over), otherwise kept.
  struct Prediction {
    std::vector<double> ahead;
    double lateral = 0.0;
    double lateral_speed = 0.0;        // m/s, kept for lateral_lookahead when it has no plan to go by
    const Trajectory* plan = nullptr;  // its last window, if it is one of ours
    double s = 0.0;                    // its line s now
    double at(double t) const;
  };
  // Metres left of the racing line the predicted car is `t` seconds on.
  double lateralAt(const Prediction& p, double t) const;
  Prediction predict(const TrafficCar& other, double s0) const;
  // Where (window s) a car driving `plan` is first clear ahead of `leader`; infinite when not in the horizon.
  double passCompleteAt(const Trajectory& plan, double s0, double v0, const Prediction& leader) const;
  // Whether a car driving `plan` from speed v0 at s0 draws alongside `leader` (its nose past the other's
  // tail) within the horizon.
  bool drawsAlongside(const Trajectory& plan, double s0, double v0, const Prediction& leader) const;
  // predicted: the plan's predictions of `others`, in the same order. clear_pass: the window is a pass found
  // clear of every car's prediction.
  void guard(Trajectory* window, double s, double speed, const std::vector<TrafficCar>& others,
             const std::vector<Prediction>& predicted, bool clear_pass = false) const;
  // A car's last window sampled at line s (m left of the racing line), or its lateral place now.
  double plannedLateral(const TrafficCar& car, double s) const;
  // The car's last window while it is where that window has it (within plan_trust); else none.
  const Trajectory* trustedPlan(const TrafficCar& car) const;
  double plannedLateral(const Trajectory* plan, double now, double s) const;
  // Drives a plan from speed v0 at s0 as far as the horizon: visit(point index, t, s, v) at each point
  // passed, until it returns false. Returns the s reached.
  using MotionVisitor = std::function<bool(std::size_t, double, double, double)>;
  double driveAlong(const Trajectory& plan, double s0, double v0, const MotionVisitor& visit) const;
  // Whether a plan, driven from speed v0 at s0, keeps clear of every car alongside or ahead over the
  // horizon (by lateral_margin beside them, scaled by margin_share; conflicts only up to `within` seconds
  // on); sets its progress over the whole horizon.
  bool clearOf(const Trajectory& plan, double s0, double v0, const std::vector<Prediction>& others, double* progress,
               double margin_share = 1.0, double within = std::numeric_limits<double>::infinity()) const;

  Trajectory line_;
  VehicleLimits limits_;
  OvertakeOptions options_;
  std::vector<double> room_s_, room_left_, room_right_;
  std::map<std::string, RaceDecision> decisions_;
  struct Abort {
    std::string other;  // the car a pass on was given up
    int plans_left = 0;
  };
  std::map<std::string, Abort> aborts_;
  std::map<std::string, double> holds_;   // the lateral place (m) a car holds while another is alongside
  std::map<std::string, double> settle_;  // line s up to which a car moving sideways is planned on settle_grip
  struct Headway {
    std::string other;      // the car being passed
    double best_gap = 0.0;  // m, the nearest the pass has come to it
    double stalled = 0.0;   // s since it last came a metre nearer
  };
  std::map<std::string, Headway> headways_;
  std::map<std::string, std::pair<std::string, int>> yields_;  // the car letting another by: which, and on which side
  struct Defence {
    std::string against;  // the car behind a defensive move was made against: no second one while it is near
    int plans = 0;        // plans the move has been held
  };
  std::map<std::string, Defence> defences_;
  // The defensive move for `car` if it makes (or goes on with) one now; mode kRacingLine if not.
  Candidate defend(const std::string& car, double s, double lateral, double speed,
                   const std::vector<TrafficCar>& traffic, const Trajectory& base,
                   const std::vector<Prediction>& predicted, const RaceDecision& memory);
  std::map<std::string, int> doubts_;                              // plans in a row a committed pass has looked blocked
  std::map<std::string, Trajectory> plans_;                        // each car's last window
  std::map<std::string, std::vector<PredictedPath>> predictions_;  // each car's last plan's view of the others
};

}  // namespace roar::planning

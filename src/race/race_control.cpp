#include "roar/race/race_control.h"

#include "roar/race/contact_fault.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <set>
#include <stdexcept>

namespace roar::race {

namespace {
constexpr double kPassageStep = 10.0;  // m between the recorded passage times used for gaps
}

RaceControl::RaceControl(const track::Track& track, RaceRules rules, const std::vector<std::string>& cars)
    : track_(track), rules_(rules) {
  if (cars.empty()) throw std::invalid_argument("race control: no cars");
  if (rules.laps < 1) throw std::invalid_argument("race control: laps must be at least 1");
  if (!track.closed()) rules_.laps = 1;  // a point-to-point course is raced once, start to finish
  for (const auto& name : cars) {
    if (cars_.count(name)) throw std::invalid_argument("race control: car '" + name + "' is listed twice");
    cars_.emplace(name, CarRecord(name, LapTimer(track)));
  }
}

CarRecord& RaceControl::record(const std::string& name) {
  auto it = cars_.find(name);
  if (it == cars_.end()) throw std::invalid_argument("race control: unknown car '" + name + "'");
  return it->second;
}

const CarRecord& RaceControl::car(const std::string& name) const {
  auto it = cars_.find(name);
  if (it == cars_.end()) throw std::invalid_argument("race control: unknown car '" + name + "'");
  return it->second;
}

Incident RaceControl::makeIncident(CarRecord& car, double time, const std::string& kind, IncidentRule rule,
                                   double penalty) {
  Incident incident;
  incident.time = time;
  incident.kind = kind;
  if (rule == IncidentRule::kPenalty) incident.penalty = penalty;
  if (rule == IncidentRule::kRespawn) {
    // Back on the centre line where the car last was on the circuit, facing the way of the race.
    incident.respawn = true;
    incident.respawn_pose = track_.poseAt(car.timer.progress() + track_.info().start_finish_s);
  }
  car.penalties += incident.penalty;
  car.incidents.push_back(incident);
  return incident;
}

std::optional<LapRecord> RaceControl::updatePosition(const std::string& name, double time,
                                                     const Eigen::Vector3d& position,
                                                     std::optional<Incident>* incident) {
  CarRecord& car = record(name);
  car.last_time = std::max(car.last_time, time);
  if (!(start_time_ <= time)) start_time_ = time;  // the first position of any car (NaN before)
  if (car.finished || !car.retired.empty()) return std::nullopt;
  auto lap = car.timer.update(time, position);
  if (car.timer.started()) {
    const double covered = car.timer.distanceCovered();
    while (covered >= 0 && static_cast<double>(car.passage.size()) * kPassageStep <= covered)
      car.passage.push_back(time);
  }
  if (lap && lap->lap >= rules_.laps) {
    car.finished = true;
    car.finish_time = lap->finish_time;
  }
  if (car.timer.started() && !car.recent.empty() && time > car.recent.back().first) {
    // Judged at the car's previous position, whose moment every other car's positions have most likely
    // reached by now (odometry of different cars arrives in any order).
    const auto [before, covered] = car.recent.back();
    const double speed = (car.timer.distanceCovered() - covered) / (time - before);
    if (inTraffic(car, before, covered, speed)) {
      car.time_in_traffic += time - before;
      car.traffic_this_lap += time - before;
    }
  }
  if (lap) {
    car.lap_traffic.push_back(car.traffic_this_lap);
    car.traffic_this_lap = 0.0;
  }
  if (car.timer.started()) {
    car.recent.emplace_back(time, car.timer.distanceCovered());
    while (car.recent.size() > 2 && car.recent.front().first < time - 10.0) car.recent.pop_front();
  }
  detectOvertakes(name, time);

  const track::Projection pr =
      track_.projectNear(position.head<2>(), car.timer.progress() + track_.info().start_finish_s, 100.0);
  const bool off = pr.beyondEdge() > rules_.track_limits_margin;
  if (off && !car.off_track && rules_.track_limits != IncidentRule::kIgnore) {
    ++car.track_limit_violations;
    const Incident made = makeIncident(car, time, "track limits", rules_.track_limits, rules_.track_limits_penalty);
    if (incident) *incident = made;
  }
  car.off_track = off;
  return lap;
}

double RaceControl::raceTime(const std::string& name) const {
  const CarRecord& car = cars_.at(name);
  const double start = std::isnan(start_time_) ? 0.0 : start_time_;
  return (car.finished ? car.finish_time : car.last_time) - start + car.penalties;
}

bool RaceControl::inTraffic(const CarRecord& car, double time, double covered, double speed) const {
  const double reach = rules_.car_length + rules_.traffic_gap * std::max(0.0, speed);
  for (const auto& [name, other] : cars_) {
    if (&other == &car || other.finished || !other.retired.empty()) continue;
    const auto theirs = distanceAt(other, time);
    if (!theirs) continue;
    if (track_.forwardDistance(covered, *theirs) < reach) return true;
  }
  return false;
}

double RaceControl::timeLostInTraffic(const std::string& name) const {
  const CarRecord& car = cars_.at(name);
  const auto& laps = car.timer.laps();
  double best_clean = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < laps.size() && k < car.lap_traffic.size(); ++k) {
    if (car.lap_traffic[k] == 0.0) best_clean = std::min(best_clean, laps[k].lap_time);
  }
  if (!std::isfinite(best_clean)) return std::numeric_limits<double>::quiet_NaN();
  double lost = 0.0;
  for (std::size_t k = 1; k < laps.size() && k < car.lap_traffic.size(); ++k) {
    if (car.lap_traffic[k] > 0.0) lost += std::max(0.0, laps[k].lap_time - best_clean);
  }
  return lost;
}

std::optional<double> RaceControl::distanceAt(const CarRecord& car, double time) {
  const auto& r = car.recent;
  if (r.empty() || time > r.back().first + 1e-6 || time < r.front().first - 1e-6) return std::nullopt;
  auto after = std::lower_bound(r.begin(), r.end(), time, [](const auto& e, double t) { return e.first < t; });
  if (after == r.end()) return r.back().second;
  if (after == r.begin() || after->first - time < 1e-9) return after->second;
  const auto before = std::prev(after);
  const double f = (time - before->first) / (after->first - before->first);
  return before->second + f * (after->second - before->second);
}

void RaceControl::detectOvertakes(const std::string& name, double time) {
  const CarRecord& me = cars_.at(name);
  if (!me.timer.started()) return;
  const double mine = me.timer.distanceCovered();
  for (const auto& [other_name, other] : cars_) {
    if (other_name == name || !other.timer.started() || other.finished) continue;
    // The other car where it was at this moment; when its positions have not reached this moment yet, it
    // makes the comparison itself when they do.
    const auto theirs = distanceAt(other, time);
    if (!theirs) continue;
    const double gap = mine - *theirs;
    // A lap or more apart is lapping, not racing for position.
    if (std::abs(gap) > 0.5 * track_.length()) continue;
    const bool first = name < other_name;
    const auto key = first ? std::make_pair(name, other_name) : std::make_pair(other_name, name);
    const int now_mine = gap > rules_.overtake_hysteresis ? 1 : gap < -rules_.overtake_hysteresis ? -1 : 0;
    if (now_mine == 0) continue;
    const int now = first ? now_mine : -now_mine;
    auto it = order_.find(key);
    if (it == order_.end()) {
      order_[key] = now;
    } else if (it->second != now) {
      it->second = now;
      // Whichever of the two got ahead; where: the passer's place at that moment.
      const bool mine_ahead = now_mine > 0;
      const double passer_covered = mine_ahead ? mine : *theirs;
      const int laps_done = std::max(0, static_cast<int>(std::floor(passer_covered / track_.length())));
      const double progress = passer_covered - laps_done * track_.length();
      overtakes_.push_back({time, mine_ahead ? name : other_name, mine_ahead ? other_name : name, laps_done + 1,
                            track_.wrap(track_.info().start_finish_s + progress)});
    }
  }
}

std::optional<Incident> RaceControl::updateContact(const std::string& name, double time, const std::string& other) {
  CarRecord& car = record(name);
  if (other == "ground" || car.finished) return std::nullopt;
  // One contact lasting several ticks is one incident.
  const bool fresh = time - car.last_contact > rules_.contact_merge;
  car.last_contact = time;
  if (!fresh) return std::nullopt;
  const bool barrier = other == "barrier";
  ++(barrier ? car.barrier_contacts : car.car_contacts);
  if (rules_.collision == IncidentRule::kIgnore) return std::nullopt;
  const auto them = cars_.find(other);
  if (barrier || them == cars_.end() || !car.motion_known || !them->second.motion_known) {
    return makeIncident(car, time, barrier ? "barrier" : "car " + other, rules_.collision, rules_.collision_penalty);
  }
  // Between cars, by the rules of racing: the car at fault pays, a racing incident costs nobody.
  const CarRecord& o = them->second;
  ContactFaultOptions options;
  options.car_length = rules_.car_length;
  const ContactFault fault = attributeContact(
      {name, car.position, car.yaw, car.velocity}, {other, o.position, o.yaw, o.velocity},
      // Where the car is on its lap: under a bridge, its own road's heading.
      track_.projectNear(car.position, car.timer.progress() + track_.info().start_finish_s, 100.0).heading, options);
  const bool mine = fault.at_fault == name;
  Incident incident = makeIncident(car, time, "car " + other, mine ? rules_.collision : IncidentRule::kPenalty,
                                   mine ? rules_.collision_penalty : 0.0);
  car.incidents.back().at_fault = incident.at_fault = fault.at_fault;
  car.incidents.back().contact = incident.contact = fault.kind;
  return incident;
}

void RaceControl::updateMotion(const std::string& name, const Eigen::Vector2d& position, double yaw,
                               const Eigen::Vector2d& velocity) {
  CarRecord& car = record(name);
  car.motion_known = std::isfinite(yaw) && position.allFinite() && velocity.allFinite();
  car.position = position;
  car.yaw = yaw;
  car.velocity = velocity;
}

void RaceControl::retire(const std::string& name, double time, const std::string& reason) {
  CarRecord& car = record(name);
  if (car.finished || !car.retired.empty()) return;
  car.retired = reason.empty() ? "retired" : reason;
  car.retire_time = time;
}

void RaceControl::driverLost(const std::string& name, double time) {
  CarRecord& car = record(name);
  if (car.finished || !car.retired.empty() || car.driver_lost_at >= 0) return;
  car.driver_lost_at = time;
}

void RaceControl::driverBack(const std::string& name) { record(name).driver_lost_at = -1.0; }

std::vector<std::string> RaceControl::retireLostDrivers(double now) {
  std::vector<std::string> retired;
  for (auto& [name, car] : cars_) {
    if (car.driver_lost_at < 0 || now - car.driver_lost_at < rules_.driver_grace) continue;
    retire(name, car.driver_lost_at, "driver lost");
    car.driver_lost_at = -1.0;
    if (car.retired == "driver lost") retired.push_back(name);
  }
  return retired;
}

bool RaceControl::anyFinisher() const {
  return std::any_of(cars_.begin(), cars_.end(), [](const auto& kv) { return kv.second.finished; });
}

bool RaceControl::finished() const {
  return std::all_of(cars_.begin(), cars_.end(),
                     [](const auto& kv) { return kv.second.finished || !kv.second.retired.empty(); });
}

std::vector<Standing> RaceControl::standings() const {
  // Finished cars by race time (finish plus penalties), then the others by distance covered.
  std::vector<const CarRecord*> order;
  for (const auto& [name, car] : cars_) order.push_back(&car);
  std::sort(order.begin(), order.end(), [](const CarRecord* a, const CarRecord* b) {
    if (a->finished != b->finished) return a->finished;
    if (a->finished) return a->finish_time + a->penalties < b->finish_time + b->penalties;
    if (a->retired.empty() != b->retired.empty()) return a->retired.empty();  // still running first
    return a->timer.distanceCovered() > b->timer.distanceCovered();
  });
  std::vector<Standing> out;
  const CarRecord& leader = *order.front();
  for (std::size_t k = 0; k < order.size(); ++k) {
    const CarRecord& car = *order[k];
    Standing s;
    s.name = car.name;
    s.position = static_cast<int>(k) + 1;
    if (car.finished && leader.finished) {
      s.gap_to_leader = car.finish_time + car.penalties - (leader.finish_time + leader.penalties);
    } else if (!car.passage.empty()) {
      // When the leader was where this car is now.
      const std::size_t at = car.passage.size() - 1;
      const double leader_then = at < leader.passage.size() ? leader.passage[at] : car.passage[at];
      s.gap_to_leader = std::max(0.0, car.passage[at] - leader_then);
    }
    out.push_back(s);
  }
  return out;
}

const char* outcomeWords(RaceOutcome outcome) {
  return outcome == RaceOutcome::kTimedOut ? "timed out" : outcomeName(outcome);
}

RaceVerdict judgeRaceEnd(const RaceEnd& end) {
  const bool no_finisher = end.complete && !end.any_finisher;
  RaceVerdict verdict;
  if (end.complete && !no_finisher) {
    verdict.outcome = RaceOutcome::kFinished;
  } else if (end.simulator_lost || no_finisher || !end.out_of_time) {
    verdict.outcome = RaceOutcome::kAborted;
    if (no_finisher) verdict.reason = "every car retired, none finished";
  } else {
    verdict.outcome = RaceOutcome::kTimedOut;
  }
  return verdict;
}

std::string standingLine(const RaceControl& race, const Standing& standing) {
  const CarRecord& car = race.car(standing.name);
  const auto best = car.timer.bestLap();
  const double lost = race.timeLostInTraffic(standing.name);  // NaN until there is a clean lap to compare
  char lost_text[32] = "no clean lap to compare";
  if (std::isfinite(lost)) std::snprintf(lost_text, sizeof lost_text, "lost %.1f s", lost);
  const std::string retired = car.retired.empty() ? "" : " (retired: " + car.retired + ")";
  const std::string best_text = best ? std::to_string(*best) : "-";
  // Sized by a first pass: a car's name or retirement reason may be of any length.
  auto print = [&](char* out, std::size_t size) {
    return std::snprintf(out, size,
                         "P%d %s: %d/%d laps%s, best lap %s s, gap %.3f s, penalties %.1f s, barrier contacts %d, "
                         "car contacts %d, track limits %d, in traffic %.1f s (%s)",
                         standing.position, standing.name.c_str(), car.timer.lapsCompleted(), race.rules().laps,
                         retired.c_str(), best_text.c_str(), standing.gap_to_leader, car.penalties,
                         car.barrier_contacts, car.car_contacts, car.track_limit_violations, car.time_in_traffic,
                         lost_text);
  };
  std::string line(static_cast<std::size_t>(print(nullptr, 0)), '\0');
  print(line.data(), line.size() + 1);
  return line;
}

const char* outcomeName(RaceOutcome outcome) {
  switch (outcome) {
    case RaceOutcome::kFinished:
      return "finished";
    case RaceOutcome::kTimedOut:
      return "timed_out";
    case RaceOutcome::kInterrupted:
      return "interrupted";
    case RaceOutcome::kAborted:
      return "aborted";
    case RaceOutcome::kRunning:
      return "running";
  }
  return "unknown";
}

namespace {

void writeResultFiles(const RaceControl& race, RaceOutcome outcome, const std::string& run,
                      const std::optional<RecordingState>& recording, std::ofstream& yaml, std::ofstream& laps,
                      std::ofstream& sectors) {
  for (auto* out :
       {&static_cast<std::ostream&>(yaml), &static_cast<std::ostream&>(laps), &static_cast<std::ostream&>(sectors)}) {
    *out << std::setprecision(10);
  }
  if (!run.empty()) yaml << "run_id: \"" << run << "\"\n";
  yaml << "map: \"" << race.track().info().name << "\"\nlaps: " << race.rules().laps
       << "\nstatus: " << outcomeName(outcome) << "\n";
  if (recording) {
    yaml << "recording:\n  complete: " << (recording->complete ? "true" : "false")
         << "\n  recorded_until_s: " << recording->recorded_until << "\n";
  }
  yaml << "cars:\n";
  laps << "car,lap,lap_time_s,sector_times_s\n";
  sectors << "car,lap,sector,time_s\n";
  std::map<std::string, Standing> standing;
  for (const auto& s : race.standings()) standing[s.name] = s;
  // In finishing order (the standings'), each race time from the start signal.
  for (const auto& place : race.standings()) {
    const std::string& name = place.name;
    const CarRecord& car = race.car(name);
    const auto& timer = car.timer;
    yaml << "  - name: " << name << "\n    position: " << standing[name].position
         << "\n    finished: " << (car.finished ? "true" : "false");
    if (!car.retired.empty()) yaml << "\n    retired: \"" << car.retired << "\"\n    retired_at_s: " << car.retire_time;
    yaml << "\n    laps_completed: " << timer.lapsCompleted() << "\n    barrier_contacts: " << car.barrier_contacts
         << "\n    car_contacts: " << car.car_contacts << "\n    track_limit_violations: " << car.track_limit_violations
         << "\n    penalties_s: " << car.penalties << "\n    race_time_s: " << race.raceTime(name)
         << "\n    gap_to_leader_s: " << standing[name].gap_to_leader;
    if (auto best = timer.bestLap()) yaml << "\n    best_lap_s: " << *best;
    yaml << "\n    time_in_traffic_s: " << car.time_in_traffic;
    const double lost = race.timeLostInTraffic(name);
    if (std::isfinite(lost)) yaml << "\n    time_lost_in_traffic_s: " << lost;
    yaml << "\n    laps:\n";
    for (const auto& lap : timer.laps()) {
      yaml << "      - {lap: " << lap.lap << ", time_s: " << lap.lap_time << ", sectors_s: [";
      laps << name << "," << lap.lap << "," << lap.lap_time << ",";
      for (std::size_t k = 0; k < lap.sector_times.size(); ++k) {
        yaml << (k ? ", " : "") << lap.sector_times[k];
        laps << (k ? ";" : "") << lap.sector_times[k];
        sectors << name << "," << lap.lap << "," << k + 1 << "," << lap.sector_times[k] << "\n";
      }
      yaml << "]}\n";
      laps << "\n";
    }
    yaml << "    incidents:" << (car.incidents.empty() ? " []\n" : "\n");
    for (const auto& incident : car.incidents) {
      yaml << "      - {time_s: " << incident.time << ", kind: \"" << incident.kind
           << "\", penalty_s: " << incident.penalty << ", respawn: " << (incident.respawn ? "true" : "false");
      if (!incident.contact.empty()) {
        yaml << ", contact: \"" << incident.contact << "\", at_fault: \"" << incident.at_fault << "\"";
      }
      yaml << "}\n";
    }
  }
  yaml << "overtakes:" << (race.overtakes().empty() ? " []\n" : "\n");
  for (const auto& o : race.overtakes()) {
    yaml << "  - {time_s: " << o.time << ", passer: " << o.passer << ", passed: " << o.passed << ", lap: " << o.lap
         << ", s_m: " << o.s << "}\n";
  }
}

}  // namespace

void writeResults(const std::string& dir, const RaceControl& race, RaceOutcome outcome, const std::string& run,
                  const std::optional<RecordingState>& recording) {
  std::filesystem::create_directories(dir);
  const std::string names[] = {"results.yaml", "laps.csv", "sectors.csv"};
  {
    std::ofstream yaml(dir + "/.results.yaml.new"), laps(dir + "/.laps.csv.new"), sectors(dir + "/.sectors.csv.new");
    if (!yaml || !laps || !sectors) throw std::runtime_error("race control: cannot write results in " + dir);
    writeResultFiles(race, outcome, run, recording, yaml, laps, sectors);
    if (!yaml.flush() || !laps.flush() || !sectors.flush())
      throw std::runtime_error("race control: cannot write results in " + dir);
  }
  for (const auto& name : names) std::filesystem::rename(dir + "/." + name + ".new", dir + "/" + name);
}

}  // namespace roar::race

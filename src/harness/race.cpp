#include "roar/harness/race.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "roar/control/tracker_sizing.h"
#include "roar/harness/time_trial.h"
#include "roar/planning/field_planner_sizing.h"
#include "roar/sim/world.h"

namespace roar::harness {

namespace {

// What the race keeps of each car between ticks.
struct Entrant {
  RaceCar spec;
  control::TrajectoryTracker tracker;
  RaceCarResult result;
  long open_pass = -1;       // index into passes while one is under way (the two cars alongside)
  std::string engaged_with;  // the car it follows or passes
  double engaged_since = 0.0;
  PassAttempt moving_out;  // the planner's pass before the car is alongside (passer empty: none)
  int round = 0;           // SpeedSample::round
  double last_s = std::numeric_limits<double>::quiet_NaN();  // line s at the last tick
};

void checkCars(const std::vector<RaceCar>& cars) {
  if (cars.empty()) throw std::invalid_argument("race: no cars");
  std::set<std::string> names;
  std::set<int> slots;
  for (const auto& c : cars) {
    if (!names.insert(c.name).second) throw std::invalid_argument("race: car '" + c.name + "' is listed twice");
    if (c.grid_slot < 0 || c.grid_slot >= track::kGridSlots || !slots.insert(c.grid_slot).second) {
      throw std::invalid_argument("race: car '" + c.name + "': grid slot " + std::to_string(c.grid_slot) +
                                  " is taken or not in 0.." + std::to_string(track::kGridSlots - 1));
    }
    if (!(c.pace > 0.0 && c.pace <= 1.0)) {
      throw std::invalid_argument("race: car '" + c.name + "': pace " + std::to_string(c.pace) + " is not in (0, 1]");
    }
    if (!(c.max_speed >= 0.0))
      throw std::invalid_argument("race: car '" + c.name + "': max_speed must not be negative");
  }
}

}  // namespace

const RaceCarResult& RaceResult::car(const std::string& name) const {
  for (const auto& c : cars) {
    if (c.name == name) return c;
  }
  throw std::out_of_range("race result: no car '" + name + "'");
}

double passingSpeedShare(const PassAttempt& pass, const std::vector<std::vector<double>>& free_air, double speed_bin) {
  double sum = 0.0;
  int n = 0;
  if (free_air.empty()) return std::numeric_limits<double>::quiet_NaN();
  for (const auto& sample : pass.samples) {
    const auto& round =
        free_air[std::min<std::size_t>(static_cast<std::size_t>(std::max(0, sample.round)), free_air.size() - 1)];
    const auto bin = static_cast<std::size_t>(std::max(0.0, sample.s) / speed_bin);
    if (bin >= round.size() || !(round[bin] > 1.0)) continue;
    sum += sample.speed / round[bin];
    ++n;
  }
  return n ? sum / n : std::numeric_limits<double>::quiet_NaN();
}

double lapTimeLoss(const RaceCarResult& in_traffic, const RaceCarResult& alone) {
  const std::size_t laps = in_traffic.lap_times.size();
  if (!in_traffic.finished || !alone.finished || laps == 0 || alone.lap_times.size() != laps) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  double lost = 0.0;
  for (std::size_t k = 0; k < laps; ++k) lost += in_traffic.lap_times[k] - alone.lap_times[k];
  return lost / static_cast<double>(laps);
}

int pairsOutOfOrder(const RaceResult& race, const std::vector<std::string>& order) {
  std::vector<std::size_t> finished_at;
  for (const auto& name : order) finished_at.push_back(static_cast<std::size_t>(&race.car(name) - race.cars.data()));
  int out = 0;
  for (std::size_t a = 0; a < finished_at.size(); ++a)
    for (std::size_t b = a + 1; b < finished_at.size(); ++b) out += finished_at[a] > finished_at[b];
  return out;
}

RaceResult runRace(const track::Track& track, const vehicle::VehicleParams& vehicle, const std::vector<RaceCar>& cars,
                   const RaceOptions& options) {
  checkCars(cars);
  const planning::VehicleLimits limits = planning::vehicleLimits(vehicle, track.info().friction, options.grip_use);
  planning::FieldPlanner field =
      planning::fieldPlannerFor(track, vehicle, options.grip_use, options.planner, options.field);
  const planning::Trajectory& line = field.line();

  sim::World world(track, {});
  const auto grid = track.gridSpawnPoints(track::kGridSlots);
  std::vector<Entrant> entrants;
  std::vector<std::string> names;
  double slowest_lap = line.lap_time;
  for (const auto& c : cars) {
    control::TrackerOptions tracker_options = control::trackerFor(vehicle, options.tracker);
    if (c.max_speed > 0) tracker_options.max_speed = c.max_speed;
    entrants.push_back({c, control::TrajectoryTracker(tracker_options, limits), {}, -1, "", 0.0, {}});
    entrants.back().result.name = c.name;
    entrants.back().result.pace = c.pace;
    field.setPace(c.name, c.pace);
    world.spawnVehicle(c.name, vehicle, track::poseOnTrack(grid.at(static_cast<std::size_t>(c.grid_slot))));
    names.push_back(c.name);
    slowest_lap = std::max({slowest_lap, line.lap_time / c.pace, c.max_speed > 0 ? line.length / c.max_speed : 0.0});
  }
  race::RaceRules rules = options.rules;
  rules.laps = options.laps;
  rules.car_length = vehicle.chassis.box_size.x();
  race::RaceControl control(track, rules, names);
  const double time_limit = options.time_limit > 0 ? options.time_limit : 3.0 * slowest_lap * (options.laps + 1) + 60.0;
  const double dt = world.options().control_dt;

  RaceResult result;
  result.line_length = line.length;
  result.speed_bin = options.speed_bin;

  // A pass attempt is the car going alongside another in a pass (its nose past the other's tail); it is
  // completed when the passer is clear ahead, aborted when it drops back behind. Pulling out and thinking
  // better of it before drawing alongside is not an attempt: it is recorded apart (given_up_before_alongside).
  // A pass that goes on to draw alongside counts its time and speeds from pulling out.
  const double car_length = vehicle.chassis.box_size.x();
  auto gapAhead = [&](const std::string& a, const std::string& b) {  // a ahead of b (m, along the line)
    return planning::aheadOnLap(field.onLine(a).s, field.onLine(b).s, planning::lapLength(line));
  };
  auto closePass = [&](Entrant& e, double time) {
    PassAttempt& pass = result.passes[static_cast<std::size_t>(e.open_pass)];
    pass.end_time = time;
    pass.completed = gapAhead(e.spec.name, pass.passed) > 0;
    if (pass.completed) e.engaged_with.clear();
    e.open_pass = -1;
  };

  while (world.time() < time_limit && !control.finished()) {
    std::map<std::string, vehicle::VehicleState> states;
    for (auto& e : entrants) {
      const vehicle::VehicleState state = world.vehicleState(e.spec.name);
      field.locate(e.spec.name, state.pose.position, state.forward_speed, world.time(),
                   Eigen::Vector2d(state.linear_velocity.head<2>()));
      states[e.spec.name] = state;
    }
    const double now = world.time();
    // A pass given up before drawing alongside (or turned to another car) is kept apart from the attempts.
    auto giveUp = [&](Entrant& e) {
      if (e.moving_out.passer.empty()) return;
      e.moving_out.end_time = now;
      e.moving_out.samples = {};  // its memory too (clear() keeps it): a race keeps hundreds of these
      result.given_up_before_alongside.push_back(std::move(e.moving_out));
      e.moving_out = PassAttempt{};
    };
    for (auto& e : entrants) {
      const std::string& name = e.spec.name;
      const vehicle::VehicleState& state = states[name];
      e.tracker.setTrajectory(field.window(name));
      const planning::RaceDecision d = field.decision(name);
      // The bookkeeping of passes: when one began, whether it was completed or aborted.
      const bool passing = d.mode == planning::RaceMode::kPass;
      if ((d.mode == planning::RaceMode::kFollow || passing) && d.other != e.engaged_with) {
        e.engaged_with = d.other;
        e.engaged_since = now;
      } else if (d.mode == planning::RaceMode::kRacingLine && e.open_pass < 0) {
        e.engaged_with.clear();
      }
      if (e.open_pass >= 0) {
        const std::string& passed = result.passes[static_cast<std::size_t>(e.open_pass)].passed;
        if (std::abs(gapAhead(name, passed)) > car_length + 1.0) closePass(e, now);
      }
      // Only a pass between two cars still racing is one: after the flag a car drives on and may go by a
      // car still racing (or be gone by), which is no pass of the race (the traffic table counted them).
      const bool finished = control.car(name).finished;
      const bool racing = !finished && !(passing && control.car(d.other).finished);
      // A pass still under way on a car already a length behind (the planner keeps it until clear ahead)
      // is no new attempt, nor one begun and given up.
      const double passed_ahead = passing ? gapAhead(d.other, name) : 0.0;  // m the car passed is ahead
      const bool got_by = passing && passed_ahead <= -car_length;
      if (passing && e.open_pass < 0 && racing && !got_by) {
        if (e.moving_out.passer.empty() || e.moving_out.passed != d.other) {
          giveUp(e);
          e.moving_out.passer = name;
          e.moving_out.passed = d.other;
          e.moving_out.caught_time = e.engaged_since;
          e.moving_out.start_time = now;
        }
        e.moving_out.side = d.side;
        if (passed_ahead < car_length) {  // alongside
          result.passes.push_back(std::move(e.moving_out));
          e.moving_out = PassAttempt{};
          e.open_pass = static_cast<long>(result.passes.size()) - 1;
        }
      } else if (!passing || !racing) {
        giveUp(e);
      }
      const double s_line = field.onLine(name).s;
      if (std::isfinite(e.last_s) && e.last_s - s_line > 0.5 * line.length) ++e.round;
      if (std::isfinite(e.last_s) && s_line - e.last_s > 0.5 * line.length) e.round = std::max(0, e.round - 1);
      e.last_s = s_line;
      const SpeedSample sample{e.round, s_line, state.forward_speed};
      if (options.on_tick)
        options.on_tick({now, &name, state.pose.position.head<2>(), state.forward_speed, field.onLine(name), d});
      if (e.open_pass >= 0) {
        PassAttempt& pass = result.passes[static_cast<std::size_t>(e.open_pass)];
        pass.samples.push_back(sample);
        if (std::isnan(pass.level_s) && gapAhead(name, pass.passed) >= 0) pass.level_s = s_line;
      }
      if (!e.moving_out.passer.empty()) e.moving_out.samples.push_back(sample);
      if (!finished && !e.engaged_with.empty()) e.result.time_in_traffic += dt;
      auto& rounds = e.result.round_speeds;
      while (rounds.size() <= static_cast<std::size_t>(e.round))
        rounds.emplace_back(static_cast<std::size_t>(std::ceil(line.length / options.speed_bin)),
                            std::numeric_limits<double>::quiet_NaN());
      auto& speeds = rounds[static_cast<std::size_t>(e.round)];
      const auto bin = static_cast<std::size_t>(std::max(0.0, s_line) / options.speed_bin);
      if (bin < speeds.size()) speeds[bin] = state.forward_speed;

      world.setControl(name, e.tracker.update(control::trackerInputOf(state)));
    }
    world.step();
    const double time = world.time();
    for (auto& e : entrants) {
      const vehicle::VehicleState state = world.vehicleState(e.spec.name);
      control.updatePosition(e.spec.name, time, state.pose.position);
      control.updateMotion(e.spec.name, state.pose.position.head<2>(), track::yawOf(state.pose.orientation),
                           state.linear_velocity.head<2>());
    }
    for (auto& e : entrants) {
      const std::string& name = e.spec.name;
      for (const auto& contact : world.contacts(name)) {
        const auto incident = control.updateContact(name, time, contact.other);
        // Each contact between two cars once, as the first of the two (by name) saw it.
        if (incident && contact.other != "barrier" && name < contact.other) {
          result.contacts.push_back({time, name, contact.other, incident->at_fault, incident->contact});
        }
      }
    }
  }
  for (auto& e : entrants) {
    if (e.open_pass >= 0) closePass(e, world.time());
  }
  result.sim_time = world.time();
  result.finished = control.finished();
  result.overtakes = control.overtakes();
  for (const auto& standing : control.standings()) {
    auto it =
        std::find_if(entrants.begin(), entrants.end(), [&](const Entrant& e) { return e.spec.name == standing.name; });
    RaceCarResult r = it->result;
    const race::CarRecord& record = control.car(standing.name);
    r.position = standing.position;
    r.finished = record.finished;
    r.race_time = control.raceTime(standing.name);
    for (const auto& lap : record.timer.laps()) r.lap_times.push_back(lap.lap_time);
    r.car_contacts = record.car_contacts;
    r.barrier_contacts = record.barrier_contacts;
    r.track_limit_violations = record.track_limit_violations;
    result.cars.push_back(std::move(r));
  }
  return result;
}

}  // namespace roar::harness

#include "roar/harness/traffic.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "roar/planning/vehicle_limits.h"

namespace roar::harness {

namespace {

double jitter(std::mt19937& rng, double amount) { return std::uniform_real_distribution<double>(-amount, amount)(rng); }

// The pace car: a slow car (60-75% of the line's speeds) on pole, three stack cars behind it.
TrafficField paceCarField(std::mt19937& rng) {
  TrafficField f{"pace_car", {}, {}};
  f.cars.push_back({"pace", 0, 0.675 + jitter(rng, 0.075), 0.0});
  for (int k = 1; k <= 3; ++k) f.cars.push_back({"car" + std::to_string(k), k, 1.0, 0.0});
  return f;
}

// Six cars pace_step apart (each jittered by up to 1%; the fastest at full pace), started in reverse order of pace.
TrafficField reverseGridField(std::mt19937& rng, double pace_step) {
  TrafficField f{"reverse_grid", {}, {}};
  const double slowest = 1.0 - 5.0 * pace_step;
  for (int k = 0; k < 6; ++k) {
    const double pace = std::min(1.0, slowest + pace_step * k + jitter(rng, 0.01));
    f.cars.push_back({"p" + std::to_string(k), k, pace, 0.0});
  }
  return f;
}

// Two equal cars, the one on pole slowed by 5% (4-6%).
TrafficField twoCarField(std::mt19937& rng) {
  TrafficField f{"five_percent", {}, {}};
  f.cars.push_back({"slowed", 0, 0.95 + jitter(rng, 0.01), 0.0});
  f.cars.push_back({"full", 1, 1.0, 0.0});
  return f;
}

void orderByPace(TrafficField* f) {
  std::vector<RaceCar> cars = f->cars;
  std::stable_sort(cars.begin(), cars.end(), [](const auto& a, const auto& b) { return a.pace > b.pace; });
  for (const auto& c : cars) f->pace_order.push_back(c.name);
}

}  // namespace

const std::vector<std::string>& trafficFieldKinds() {
  static const std::vector<std::string> kinds = {"pace_car", "reverse_grid", "five_percent"};
  return kinds;
}

TrafficField trafficField(const std::string& kind, int seed, double pace_step) {
  if (!(pace_step >= kMinPaceStep && pace_step <= kMaxPaceStep)) {
    char said[160];
    std::snprintf(said, sizeof said, "pace step %g: expected %g to %g (of pace between the reverse grid's cars)",
                  pace_step, kMinPaceStep, kMaxPaceStep);
    throw std::invalid_argument(said);
  }
  std::mt19937 rng(static_cast<unsigned>(seed * 7919 + 17));
  TrafficField field;
  if (kind == "pace_car") {
    field = paceCarField(rng);
  } else if (kind == "reverse_grid") {
    field = reverseGridField(rng, pace_step);
  } else if (kind == "five_percent") {
    field = twoCarField(rng);
  } else {
    throw std::invalid_argument("field '" + kind + "': expected pace_car, reverse_grid or five_percent");
  }
  orderByPace(&field);
  return field;
}

void TrafficTotals::add(const TrafficTotals& t) {
  races += t.races, attempts += t.attempts, completed += t.completed, aborted += t.aborted;
  contacts += t.contacts, at_fault += t.at_fault, track_limits += t.track_limits, barrier += t.barrier;
  pace_order += t.pace_order, pace_order_races += t.pace_order_races, late_passes += t.late_passes;
  pairs_out_of_order += t.pairs_out_of_order;
  defences += t.defences, given_up += t.given_up;
  traffic_time += t.traffic_time, race_seconds += t.race_seconds;
  catch_to_pass.insert(catch_to_pass.end(), t.catch_to_pass.begin(), t.catch_to_pass.end());
  passing_share.insert(passing_share.end(), t.passing_share.begin(), t.passing_share.end());
  lap_loss.insert(lap_loss.end(), t.lap_loss.begin(), t.lap_loss.end());
  for (int p = 0; p < 3; ++p)
    for (int side = 0; side < 2; ++side)
      for (int inside = 0; inside < 2; ++inside) won[p][side][inside] += t.won[p][side][inside];
}

std::vector<std::pair<std::string, TrafficFigure>> trafficFigures(TrafficTotals* t, std::array<int, 12>* won) {
  int k = 0;
  for (const auto& place : t->won)
    for (const auto& side : place)
      for (int count : side) (*won)[k++] = count;
  return {{"races", &t->races},
          {"attempts", &t->attempts},
          {"completed", &t->completed},
          {"aborted", &t->aborted},
          {"contacts", &t->contacts},
          {"at_fault", &t->at_fault},
          {"track_limits", &t->track_limits},
          {"barrier", &t->barrier},
          {"pace_order", &t->pace_order},
          {"pace_order_races", &t->pace_order_races},
          {"late_passes", &t->late_passes},
          {"defences", &t->defences},
          {"given_up", &t->given_up},
          {"pairs_out_of_order", &t->pairs_out_of_order},
          {"catch_to_pass", &t->catch_to_pass},
          {"passing_share", &t->passing_share},
          {"lap_loss", &t->lap_loss},
          {"traffic_time", &t->traffic_time},
          {"race_seconds", &t->race_seconds},
          {"won", won}};
}

void setWon(TrafficTotals* t, const std::array<int, 12>& won) {
  int k = 0;
  for (auto& place : t->won)
    for (auto& side : place)
      for (int& count : side) count = won[k++];
}

TrafficCircuit::TrafficCircuit(const std::string& name, const track::Track& track,
                               const vehicle::VehicleParams& vehicle, int laps,
                               const planning::OvertakeOptions& overtake)
    : name_(name), track_(track), vehicle_(vehicle) {
  options_.laps = laps;
  options_.field.overtaking = true;
  options_.field.overtake = overtake;
  // The racing line the races drive (FieldPlanner plans the same): where passes were won is read on it.
  const auto limits = planning::vehicleLimits(vehicle, track.info().friction, options_.grip_use);
  line_ = planning::planRacingTrajectory(track, limits, options_.planner);
}

const RaceCarResult& TrafficCircuit::alone(const RaceCar& car) {
  // Free air: the car alone, from its grid slot at its pace, for the lap time traffic costs it and the
  // passing speed's reference.
  const auto key = std::make_pair(car.grid_slot, car.pace);
  auto it = alone_at_.find(key);
  if (it == alone_at_.end())
    it = alone_at_.emplace(key, runRace(track_, vehicle_, {car}, options_).car(car.name)).first;
  return it->second;
}

TrafficTotals TrafficCircuit::race(const TrafficField& field, int seed, std::FILE* verbose) {
  const char* map = name_.c_str();
  TrafficTotals t;
  if (verbose) {
    std::fprintf(verbose, "  %s seed %d %s:", map, seed, field.kind.c_str());
    for (const auto& c : field.cars) std::fprintf(verbose, " %s@%d pace %.17g", c.name.c_str(), c.grid_slot, c.pace);
    std::fprintf(verbose, "\n");
  }
  // Defensive moves made (OvertakeOptions::defend): a car's decisions turning to kDefend.
  std::map<std::string, planning::RaceMode> last_mode;
  RaceOptions traced = options_;
  traced.on_tick = [&](const RaceTick& tick) {
    planning::RaceMode& last = last_mode[*tick.car];
    if (tick.decision.mode == planning::RaceMode::kDefend && last != planning::RaceMode::kDefend) ++t.defences;
    last = tick.decision.mode;
  };
  const auto r = runRace(track_, vehicle_, field.cars, traced);
  ++t.races;
  t.race_seconds += r.sim_time;
  std::map<std::string, double> best_lap;
  std::map<std::string, const RaceCar*> spec_of;
  for (const auto& c : field.cars) {
    spec_of[c.name] = &c;
    const double loss = lapTimeLoss(r.car(c.name), alone(c));
    if (std::isfinite(loss)) t.lap_loss.push_back(loss);
  }
  for (const auto& c : r.cars) {
    t.track_limits += c.track_limit_violations;
    t.barrier += c.barrier_contacts;
    t.traffic_time += c.time_in_traffic;
    best_lap[c.name] = c.lap_times.empty() ? 1e9 : *std::min_element(c.lap_times.begin(), c.lap_times.end());
    if (verbose && (c.track_limit_violations > 0 || c.barrier_contacts > 0 || !c.finished)) {
      std::fprintf(verbose, "  %s seed %d: %s: %d track-limit excursions, %d barrier contacts%s\n", map, seed,
                   c.name.c_str(), c.track_limit_violations, c.barrier_contacts, c.finished ? "" : ", did not finish");
    }
  }
  for (const auto& p : r.passes) {
    ++t.attempts;
    std::string won_where;
    if (p.completed) {
      ++t.completed;
      t.catch_to_pass.push_back(p.end_time - p.caught_time);
      if (p.end_time - p.caught_time > best_lap[p.passer]) ++t.late_passes;
      if (std::isfinite(p.level_s)) {
        const PassWhere where = passPlace(line_, p.level_s, p.side);
        ++t.won[static_cast<int>(where.place)][p.side > 0 ? 0 : 1][where.inside ? 1 : 0];
        won_where =
            std::string(where.place == PassPlace::kStraight ? ", won on a " : ", won in a ") + describe(where.place);
        if (where.place != PassPlace::kStraight) won_where += where.inside ? " inside" : " outside";
      }
    } else {
      ++t.aborted;
    }
    const double share = passingSpeedShare(p, alone(*spec_of.at(p.passer)).round_speeds, r.speed_bin);
    if (std::isfinite(share)) t.passing_share.push_back(share);
    if (verbose) {
      std::fprintf(verbose, "  %s seed %d: %s %s %s on the %s, caught %.1f, %.1f-%.1f s, speed %.0f%%%s\n", map, seed,
                   p.passer.c_str(), p.completed ? "passed" : "aborted passing", p.passed.c_str(),
                   p.side > 0 ? "left" : "right", p.caught_time, p.start_time, p.end_time, 100 * share,
                   won_where.c_str());
    }
  }
  t.given_up += static_cast<int>(r.given_up_before_alongside.size());
  if (verbose) {
    for (const auto& p : r.given_up_before_alongside) {
      std::fprintf(verbose, "  %s seed %d: %s gave up a pass on %s on the %s before drawing alongside, %.1f-%.1f s\n",
                   map, seed, p.passer.c_str(), p.passed.c_str(), p.side > 0 ? "left" : "right", p.start_time,
                   p.end_time);
    }
  }
  t.contacts += static_cast<int>(r.contacts.size());
  for (const auto& c : r.contacts) {
    if (!c.at_fault.empty()) ++t.at_fault;
    if (verbose) {
      std::fprintf(verbose, "  %s seed %d: CONTACT %s-%s at t = %.2f s, %s, at fault: %s\n", map, seed, c.a.c_str(),
                   c.b.c_str(), c.time, c.kind.c_str(), c.at_fault.empty() ? "nobody" : c.at_fault.c_str());
    }
  }
  if (field.kind == "reverse_grid") {
    ++t.pace_order_races;
    // How far from pace order (the grid has all 15 pairs the other way round); none out: in pace order.
    const int out = pairsOutOfOrder(r, field.pace_order);
    t.pairs_out_of_order += out;
    t.pace_order += r.finished && out == 0;
    if (verbose) {
      std::fprintf(verbose, "  %s seed %d: finishing order", map, seed);
      for (const auto& c : r.cars) std::fprintf(verbose, " %s", c.name.c_str());
      std::fprintf(verbose, " (%d pairs out of pace order)\n", out);
    }
  }
  return t;
}

}  // namespace roar::harness

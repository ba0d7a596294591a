#include "traffic_table.h"

#include "roar/planning/overtaking/option_table.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <random>
#include <stdexcept>
#include <vector>

#include "roar/config/number.h"
#include "roar/config/package_layout.h"
#include "roar/config/yaml_section.h"
#include "roar/harness/pass_place.h"
#include "roar/harness/race.h"
#include "roar/planning/overtaking/planner.h"
#include "roar/track/map_folder.h"
#include "roar/vehicle/vehicle_config.h"
#include "statistics.h"

namespace roar::bench {

namespace {

// A field of one race: its name and its cars, made from a seed.
struct Field {
  std::string kind;
  std::vector<harness::RaceCar> cars;
  std::vector<std::string> pace_order;  // fastest first (ties: grid order)
};

double jitter(std::mt19937& rng, double amount) { return std::uniform_real_distribution<double>(-amount, amount)(rng); }

// The pace car: a slow car (60-75% of the line's speeds) on pole, three stack cars behind it.
Field paceCarField(std::mt19937& rng) {
  Field f{"pace_car", {}, {}};
  f.cars.push_back({"pace", 0, 0.675 + jitter(rng, 0.075), 0.0});
  for (int k = 1; k <= 3; ++k) f.cars.push_back({"car" + std::to_string(k), k, 1.0, 0.0});
  return f;
}

// Six cars pace_step apart (each jittered by up to 1%; the fastest at full pace), started in reverse order of pace.
Field reverseGridField(std::mt19937& rng, double pace_step) {
  Field f{"reverse_grid", {}, {}};
  const double slowest = 1.0 - 5.0 * pace_step;
  for (int k = 0; k < 6; ++k) {
    const double pace = std::min(1.0, slowest + pace_step * k + jitter(rng, 0.01));
    f.cars.push_back({"p" + std::to_string(k), k, pace, 0.0});
  }
  return f;
}

// Two equal cars, the one on pole slowed by 5% (4-6%).
Field twoCarField(std::mt19937& rng) {
  Field f{"five_percent", {}, {}};
  f.cars.push_back({"slowed", 0, 0.95 + jitter(rng, 0.01), 0.0});
  f.cars.push_back({"full", 1, 1.0, 0.0});
  return f;
}

void orderByPace(Field* f) {
  std::vector<harness::RaceCar> cars = f->cars;
  std::stable_sort(cars.begin(), cars.end(), [](const auto& a, const auto& b) { return a.pace > b.pace; });
  for (const auto& c : cars) f->pace_order.push_back(c.name);
}

// Completed passes by where they were won (harness::passPlace), the side passed on and the corner's inside.
struct PassPlaces {
  int won[3][2][2] = {};  // [place][0 left, 1 right][1 inside]

  void count(const harness::PassWhere& where, int side) {
    ++won[static_cast<int>(where.place)][side > 0 ? 0 : 1][where.inside ? 1 : 0];
  }
  void add(const PassPlaces& other) {
    for (int p = 0; p < 3; ++p)
      for (int side = 0; side < 2; ++side)
        for (int inside = 0; inside < 2; ++inside) won[p][side][inside] += other.won[p][side][inside];
  }
  int at(harness::PassPlace place, int side, int inside) const { return won[static_cast<int>(place)][side][inside]; }
};

struct Totals {
  int races = 0, attempts = 0, completed = 0, aborted = 0, contacts = 0, at_fault = 0, track_limits = 0, barrier = 0;
  int pace_order = 0, pace_order_races = 0, late_passes = 0, defences = 0, given_up = 0;
  int pairs_out_of_order = 0;  // over the reverse-grid races: pairs of cars finishing against their pace
  std::vector<double> catch_to_pass, passing_share, lap_loss;
  double traffic_time = 0.0, race_seconds = 0.0;
  PassPlaces places;

  void add(const Totals& t) {
    races += t.races, attempts += t.attempts, completed += t.completed, aborted += t.aborted;
    contacts += t.contacts, at_fault += t.at_fault, track_limits += t.track_limits, barrier += t.barrier;
    pace_order += t.pace_order, pace_order_races += t.pace_order_races, late_passes += t.late_passes;
    pairs_out_of_order += t.pairs_out_of_order;
    defences += t.defences, given_up += t.given_up;
    traffic_time += t.traffic_time, race_seconds += t.race_seconds;
    catch_to_pass.insert(catch_to_pass.end(), t.catch_to_pass.begin(), t.catch_to_pass.end());
    passing_share.insert(passing_share.end(), t.passing_share.begin(), t.passing_share.end());
    lap_loss.insert(lap_loss.end(), t.lap_loss.begin(), t.lap_loss.end());
    places.add(t.places);
  }
};

// Where a circuit's completed passes were won: "straight: left 3, right 2; braking zone: inside 4 (left 1,
// right 3), outside 0; corner: inside 1 (...), outside 0 (...)".
std::string wonLine(const std::string& circuit, const PassPlaces& t) {
  using harness::PassPlace;
  const int straight_left = t.at(PassPlace::kStraight, 0, 0), straight_right = t.at(PassPlace::kStraight, 1, 0);
  std::string out =
      circuit + ": straight left " + std::to_string(straight_left) + ", right " + std::to_string(straight_right);
  for (const PassPlace place : {PassPlace::kBrakingZone, PassPlace::kCorner}) {
    out += "; " + harness::describe(place);
    for (const int inside : {1, 0}) {
      const int left = t.at(place, 0, inside), right = t.at(place, 1, inside);
      out += std::string(inside ? " inside " : ", outside ") + std::to_string(left + right) + " (left " +
             std::to_string(left) + ", right " + std::to_string(right) + ")";
    }
  }
  return out;
}

void printRow(const std::string& circuit, const std::string& kind, const Totals& t) {
  const double rate = t.attempts ? 100.0 * t.completed / t.attempts : std::nan("");
  char pairs[16] = "-";
  if (t.pace_order_races) std::snprintf(pairs, sizeof pairs, "%.1f", double(t.pairs_out_of_order) / t.pace_order_races);
  std::printf(
      "%-14s %-13s %5d %8d %9d %7d %7d %7.1f %9.1f %8.1f %8d %8d %7d %8d %9s %9s %7.2f\n", circuit.c_str(),
      kind.c_str(), t.races, t.attempts, t.completed, t.aborted, t.given_up, rate, median(t.catch_to_pass),
      100.0 * mean(t.passing_share), t.contacts, t.at_fault, t.track_limits, t.late_passes,
      t.pace_order_races ? (std::to_string(t.pace_order) + "/" + std::to_string(t.pace_order_races)).c_str() : "-",
      pairs, mean(t.lap_loss));
}

}  // namespace

int printTrafficTable(const std::string& maps_dir, const std::string& urdf_dir, const std::string& vehicle_config_dir,
                      const TrafficTableOptions& table) {
  const std::string& only_field = table.only_field;
  const std::string& only_map = table.only_map;
  const planning::OvertakeOptions& overtake = table.overtake;
  const int seeds = table.seeds, laps = table.laps;
  const bool verbose = table.verbose;
  if (!only_field.empty() && only_field != "pace_car" && only_field != "reverse_grid" && only_field != "five_percent") {
    throw std::invalid_argument("--field=" + only_field + ": expected pace_car, reverse_grid or five_percent");
  }
  if (!(table.pace_step >= kMinPaceStep && table.pace_step <= kMaxPaceStep)) {
    char said[160];
    std::snprintf(said, sizeof said, "--pace-step=%g: expected %g to %g (of pace between the reverse grid's cars)",
                  table.pace_step, kMinPaceStep, kMaxPaceStep);
    throw std::invalid_argument(said);
  }
  const auto vehicle = vehicle::loadVehicleModel(config::kDefaultModel, urdf_dir, vehicle_config_dir);
  std::printf(
      "\nTraffic: the stack's cars racing each other, overtaking on, %d laps, %d seeds per circuit and field, "
      "reverse grids %g%% of pace apart, lockstep, in one process\n",
      laps, seeds, 100.0 * table.pace_step);
  std::printf("%-14s %-13s %5s %8s %9s %7s %7s %7s %9s %8s %8s %8s %7s %8s %9s %9s %7s\n", "circuit", "field", "races",
              "attempts", "completed", "aborted", "gave_up", "rate_%", "catch_s", "speed_%", "contacts", "at_fault",
              "limits", "late", "in_order", "pairs_out", "loss_s");
  Totals all;
  std::vector<std::string> lanes;  // each circuit's room to pass, printed under the table
  std::vector<std::string> won;    // where each circuit's passes were won, printed under it too
  const auto started = std::chrono::steady_clock::now();
  for (const auto& map : track::listMaps(maps_dir)) {
    if (!only_map.empty() && map != only_map) continue;
    const auto track = track::loadMapFolder(maps_dir + "/" + map);
    if (!track.closed()) continue;  // laps of circuits: a point-to-point course has no laps to catch a car on
    harness::RaceOptions options;
    options.laps = laps;
    options.field.overtaking = true;
    options.field.overtake = overtake;
    // The racing line the races drive (FieldPlanner plans the same): where passes were won is read on it.
    const auto limits = planning::vehicleLimits(vehicle, track.info().friction, options.grip_use);
    const planning::Trajectory line = planning::planRacingTrajectory(track, limits, options.planner);
    PassPlaces circuit_places;  // every field's races on this circuit
    {
      // Where a car on the racing line leaves a lane beside it long enough for the reverse grid's passes:
      // its pace step of speed gained, two car lengths and margins to go by in.
      planning::OvertakeOptions sized = overtake;
      sized.car.length = vehicle.chassis.box_size.x();
      sized.car.width = vehicle.chassis.box_size.y();
      const planning::OvertakePlanner planner(track, line, limits, sized);
      const double run = 2.0 * (sized.car.length + sized.margins.longitudinal) / table.pace_step;
      char room[200];
      std::snprintf(room, sizeof room, "%-14s %4.0f m: left %3.0f%%, right %3.0f%% of the lap", map.c_str(), run,
                    100.0 * planner.laneShare(+1, run), 100.0 * planner.laneShare(-1, run));
      lanes.push_back(room);
    }
    // Free air: each car of a field alone, from its grid slot at its pace, for the lap time traffic costs
    // it and the passing speed's reference (the full-pace cars' runs serve every seed).
    std::map<std::pair<int, double>, harness::RaceCarResult> alone_at;
    auto aloneAs = [&](const harness::RaceCar& car) -> const harness::RaceCarResult& {
      const auto key = std::make_pair(car.grid_slot, car.pace);
      auto it = alone_at.find(key);
      if (it == alone_at.end())
        it = alone_at.emplace(key, harness::runRace(track, vehicle, {car}, options).car(car.name)).first;
      return it->second;
    };
    const std::vector<std::function<Field(std::mt19937&)>> fields = {
        paceCarField, [&](std::mt19937& rng) { return reverseGridField(rng, table.pace_step); }, twoCarField};
    for (const auto& make : fields) {
      std::mt19937 probe(0);
      if (!only_field.empty() && make(probe).kind != only_field) continue;
      Totals t;
      std::string kind;
      for (int seed = 0; seed < seeds; ++seed) {
        std::mt19937 rng(static_cast<unsigned>(seed * 7919 + 17));
        Field field = make(rng);
        kind = field.kind;
        orderByPace(&field);
        if (verbose) {
          std::printf("  %s seed %d %s:", map.c_str(), seed, field.kind.c_str());
          for (const auto& c : field.cars) std::printf(" %s@%d pace %.17g", c.name.c_str(), c.grid_slot, c.pace);
          std::printf("\n");
        }
        // Defensive moves made (OvertakeOptions::defend): a car's decisions turning to kDefend.
        std::map<std::string, planning::RaceMode> last_mode;
        harness::RaceOptions traced = options;
        traced.on_tick = [&](const harness::RaceTick& tick) {
          planning::RaceMode& last = last_mode[*tick.car];
          if (tick.decision.mode == planning::RaceMode::kDefend && last != planning::RaceMode::kDefend) ++t.defences;
          last = tick.decision.mode;
        };
        const auto r = harness::runRace(track, vehicle, field.cars, traced);
        ++t.races;
        t.race_seconds += r.sim_time;
        std::map<std::string, double> best_lap;
        std::map<std::string, const harness::RaceCar*> spec_of;
        for (const auto& c : field.cars) {
          spec_of[c.name] = &c;
          const double loss = harness::lapTimeLoss(r.car(c.name), aloneAs(c));
          if (std::isfinite(loss)) t.lap_loss.push_back(loss);
        }
        for (const auto& c : r.cars) {
          t.track_limits += c.track_limit_violations;
          t.barrier += c.barrier_contacts;
          t.traffic_time += c.time_in_traffic;
          best_lap[c.name] = c.lap_times.empty() ? 1e9 : *std::min_element(c.lap_times.begin(), c.lap_times.end());
          if (verbose && (c.track_limit_violations > 0 || c.barrier_contacts > 0 || !c.finished)) {
            std::printf("  %s seed %d: %s: %d track-limit excursions, %d barrier contacts%s\n", map.c_str(), seed,
                        c.name.c_str(), c.track_limit_violations, c.barrier_contacts,
                        c.finished ? "" : ", did not finish");
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
              const harness::PassWhere where = harness::passPlace(line, p.level_s, p.side);
              t.places.count(where, p.side);
              won_where = std::string(where.place == harness::PassPlace::kStraight ? ", won on a " : ", won in a ") +
                          harness::describe(where.place);
              if (where.place != harness::PassPlace::kStraight) won_where += where.inside ? " inside" : " outside";
            }
          } else {
            ++t.aborted;
          }
          const double share = harness::passingSpeedShare(p, aloneAs(*spec_of.at(p.passer)).round_speeds, r.speed_bin);
          if (std::isfinite(share)) t.passing_share.push_back(share);
          if (verbose) {
            std::printf("  %s seed %d: %s %s %s on the %s, caught %.1f, %.1f-%.1f s, speed %.0f%%%s\n", map.c_str(),
                        seed, p.passer.c_str(), p.completed ? "passed" : "aborted passing", p.passed.c_str(),
                        p.side > 0 ? "left" : "right", p.caught_time, p.start_time, p.end_time, 100 * share,
                        won_where.c_str());
          }
        }
        t.given_up += static_cast<int>(r.given_up_before_alongside.size());
        if (verbose) {
          for (const auto& p : r.given_up_before_alongside) {
            std::printf("  %s seed %d: %s gave up a pass on %s on the %s before drawing alongside, %.1f-%.1f s\n",
                        map.c_str(), seed, p.passer.c_str(), p.passed.c_str(), p.side > 0 ? "left" : "right",
                        p.start_time, p.end_time);
          }
        }
        t.contacts += static_cast<int>(r.contacts.size());
        for (const auto& c : r.contacts) {
          if (!c.at_fault.empty()) ++t.at_fault;
          if (verbose) {
            std::printf("  %s seed %d: CONTACT %s-%s at t = %.2f s, %s, at fault: %s\n", map.c_str(), seed, c.a.c_str(),
                        c.b.c_str(), c.time, c.kind.c_str(), c.at_fault.empty() ? "nobody" : c.at_fault.c_str());
          }
        }
        if (field.kind == "reverse_grid") {
          ++t.pace_order_races;
          // How far from pace order (the grid has all 15 pairs the other way round); none out: in pace order.
          const int out = harness::pairsOutOfOrder(r, field.pace_order);
          t.pairs_out_of_order += out;
          t.pace_order += r.finished && out == 0;
          if (verbose) {
            std::printf("  %s seed %d: finishing order", map.c_str(), seed);
            for (const auto& c : r.cars) std::printf(" %s", c.name.c_str());
            std::printf(" (%d pairs out of pace order)\n", out);
          }
        }
      }
      printRow(map, kind, t);
      std::fflush(stdout);
      all.add(t);
      circuit_places.add(t.places);
    }
    won.push_back(wonLine(map, circuit_places));
  }
  printRow("all", "", all);
  std::printf(
      "where completed passes were won (the passer drawing level, on the racing line there: a braking zone where\n"
      "it slows at %g m/s^2 or more, inside or outside of the corner braked for; a corner where it turns tighter\n"
      "than %g m; else a straight):\n",
      harness::PassPlaceOptions().braking, harness::PassPlaceOptions().corner_radius);
  for (const auto& w : won) std::printf("  %s\n", w.c_str());
  std::printf("  %s\n", wonLine("all", all.places).c_str());
  std::printf(
      "room to pass: where a lane runs beside a car on the racing line (its width and air, and the pass's edge\n"
      "margin) for as far as a pass gaining the reverse grid's %g%% of speed needs to go by:\n",
      100.0 * table.pace_step);
  for (const auto& l : lanes) std::printf("  %s\n", l.c_str());
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::printf(
      "columns: passes attempted (the passer drawn alongside), completed and aborted; gave_up: passes begun and\n"
      "given up before drawing alongside (pulled out and back in: not attempts); rate_%% completed/attempted;\n"
      "catch_s median time from catching a car to completing the pass; speed_%% mean passing speed against the\n"
      "passer's free-air speed at the same place on the same lap (the car alone from its grid slot); contacts\n"
      "between cars (at_fault: with a car at fault); limits:\n"
      "track-limit excursions; late: passes completed more than a lap after catching; in_order: reverse-grid\n"
      "races finished in pace order; pairs_out: pairs of cars a reverse grid finished out of pace order (of 15;\n"
      "the grid has all 15), mean of the races;\n"
      "loss_s: seconds a lap a car lost in traffic, against the same car alone from its grid slot (mean of the cars).\n"
      "%.0f simulated s in %.0f s wall; barrier contacts %d; defensive moves %d\n",
      all.race_seconds, wall, all.barrier, all.defences);
  return all.contacts;
}

void setOvertakeOption(planning::OvertakeOptions* options, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos) throw std::invalid_argument("--overtake " + assignment + ": expected name=value");
  planning::setOvertakeOption(options, assignment.substr(0, eq), assignment.substr(eq + 1), "--overtake");
}

}  // namespace roar::bench

#include "traffic_table.h"

#include "roar/planning/overtaking/option_table.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>

#include "roar/config/package_layout.h"
#include "roar/harness/pass_place.h"
#include "roar/harness/race.h"
#include "roar/harness/traffic.h"
#include "roar/planning/overtaking/planner.h"
#include "roar/planning/vehicle_limits.h"
#include "roar/track/map_folder.h"
#include "roar/vehicle/vehicle_config.h"
#include "statistics.h"

namespace roar::bench {

namespace {

using harness::TrafficTotals;

// Where a circuit's completed passes were won: "straight: left 3, right 2; braking zone: inside 4 (left 1,
// right 3), outside 0; corner: inside 1 (...), outside 0 (...)".
std::string wonLine(const std::string& circuit, const TrafficTotals& t) {
  using harness::PassPlace;
  const int straight_left = t.wonAt(PassPlace::kStraight, 0, 0), straight_right = t.wonAt(PassPlace::kStraight, 1, 0);
  std::string out =
      circuit + ": straight left " + std::to_string(straight_left) + ", right " + std::to_string(straight_right);
  for (const PassPlace place : {PassPlace::kBrakingZone, PassPlace::kCorner}) {
    out += "; " + harness::describe(place);
    for (const int inside : {1, 0}) {
      const int left = t.wonAt(place, 0, inside), right = t.wonAt(place, 1, inside);
      out += std::string(inside ? " inside " : ", outside ") + std::to_string(left + right) + " (left " +
             std::to_string(left) + ", right " + std::to_string(right) + ")";
    }
  }
  return out;
}

void printRow(const std::string& circuit, const std::string& kind, const TrafficTotals& t) {
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

// The table's circuits: every closed one of maps_dir (a point-to-point course has no laps to catch a car on),
// or the one asked for.
struct Circuit {
  std::string name;
  track::Track track;
};

std::vector<Circuit> circuitsOf(const std::string& maps_dir, const std::string& only_map) {
  std::vector<Circuit> out;
  for (const auto& map : track::listMaps(maps_dir)) {
    if (!only_map.empty() && map != only_map) continue;
    auto track = track::loadMapFolder(maps_dir + "/" + map);
    if (track.closed()) out.push_back({map, std::move(track)});
  }
  return out;
}

std::vector<std::string> fieldsOf(const std::string& only_field) {
  const auto& kinds = harness::trafficFieldKinds();
  if (only_field.empty()) return kinds;
  if (std::find(kinds.begin(), kinds.end(), only_field) == kinds.end()) {
    throw std::invalid_argument("--field=" + only_field + ": expected pace_car, reverse_grid or five_percent");
  }
  return {only_field};
}

// Where a car on the racing line leaves a lane beside it long enough for the reverse grid's passes: its pace
// step of speed gained, two car lengths and margins to go by in.
std::string laneLine(const Circuit& c, const harness::TrafficCircuit& races, const vehicle::VehicleParams& vehicle,
                     const TrafficTableOptions& table) {
  planning::OvertakeOptions sized = table.overtake;
  sized.car.length = vehicle.chassis.box_size.x();
  sized.car.width = vehicle.chassis.box_size.y();
  const auto limits = planning::vehicleLimits(vehicle, c.track.info().friction, races.options().grip_use);
  const planning::OvertakePlanner planner(c.track, races.line(), limits, sized);
  const double run = 2.0 * (sized.car.length + sized.margins.longitudinal) / table.pace_step;
  char room[200];
  std::snprintf(room, sizeof room, "%-14s %4.0f m: left %3.0f%%, right %3.0f%% of the lap", c.name.c_str(), run,
                100.0 * planner.laneShare(+1, run), 100.0 * planner.laneShare(-1, run));
  return room;
}

}  // namespace

int printTrafficTable(const std::string& maps_dir, const std::string& urdf_dir, const std::string& vehicle_config_dir,
                      const TrafficTableOptions& table) {
  const std::vector<std::string> fields = fieldsOf(table.only_field);
  if (!(table.pace_step >= harness::kMinPaceStep && table.pace_step <= harness::kMaxPaceStep)) {
    char said[160];
    std::snprintf(said, sizeof said, "--pace-step=%g: expected %g to %g (of pace between the reverse grid's cars)",
                  table.pace_step, harness::kMinPaceStep, harness::kMaxPaceStep);
    throw std::invalid_argument(said);
  }
  if (table.batch.enabled && table.verbose) {
    throw std::invalid_argument("--verbose: the races of a batch run elsewhere and print nothing");
  }
  const auto vehicle = vehicle::loadVehicleModel(config::kDefaultModel, urdf_dir, vehicle_config_dir);
  const std::vector<Circuit> circuits = circuitsOf(maps_dir, table.only_map);
  std::vector<std::unique_ptr<harness::TrafficCircuit>> races;
  for (const auto& c : circuits) {
    races.push_back(std::make_unique<harness::TrafficCircuit>(c.name, c.track, vehicle, table.laps, table.overtake));
  }
  // A batch runs every race on Dask first and the table reads them back in its order; in one process each
  // race runs as the table reaches it. Either way the totals add in the same order.
  const auto started = std::chrono::steady_clock::now();
  std::vector<TrafficTotals> batched;
  if (table.batch.enabled) {
    std::vector<TrafficRace> order;
    for (const auto& c : circuits)
      for (const auto& field : fields)
        for (int seed = 0; seed < table.seeds; ++seed) order.push_back({c.name, field, seed});
    batched = raceAsBatch(order, table);
  }
  std::printf(
      "\nTraffic: the stack's cars racing each other, overtaking on, %d laps, %d seeds per circuit and field, "
      "reverse grids %g%% of pace apart, lockstep, %s\n",
      table.laps, table.seeds, 100.0 * table.pace_step, table.batch.enabled ? "as a batch on Dask" : "in one process");
  std::printf("%-14s %-13s %5s %8s %9s %7s %7s %7s %9s %8s %8s %8s %7s %8s %9s %9s %7s\n", "circuit", "field", "races",
              "attempts", "completed", "aborted", "gave_up", "rate_%", "catch_s", "speed_%", "contacts", "at_fault",
              "limits", "late", "in_order", "pairs_out", "loss_s");
  TrafficTotals all;
  std::vector<std::string> lanes;  // each circuit's room to pass, printed under the table
  std::vector<std::string> won;    // where each circuit's passes were won, printed under it too
  std::size_t next = 0;
  for (std::size_t k = 0; k < circuits.size(); ++k) {
    lanes.push_back(laneLine(circuits[k], *races[k], vehicle, table));
    TrafficTotals circuit_places;  // every field's races on this circuit
    for (const auto& kind : fields) {
      TrafficTotals t;
      for (int seed = 0; seed < table.seeds; ++seed) {
        t.add(table.batch.enabled ? batched.at(next++)
                                  : races[k]->race(harness::trafficField(kind, seed, table.pace_step), seed,
                                                   table.verbose ? stdout : nullptr));
      }
      printRow(circuits[k].name, kind, t);
      std::fflush(stdout);
      all.add(t);
      circuit_places.add(t);
    }
    won.push_back(wonLine(circuits[k].name, circuit_places));
  }
  printRow("all", "", all);
  std::printf(
      "where completed passes were won (the passer drawing level, on the racing line there: a braking zone where\n"
      "it slows at %g m/s^2 or more, inside or outside of the corner braked for; a corner where it turns tighter\n"
      "than %g m; else a straight):\n",
      harness::PassPlaceOptions().braking, harness::PassPlaceOptions().corner_radius);
  for (const auto& w : won) std::printf("  %s\n", w.c_str());
  std::printf("  %s\n", wonLine("all", all).c_str());
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

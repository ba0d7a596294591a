#pragma once
// One race of the traffic benchmark (roar_bench --traffic): a field drawn from its seed on a circuit, raced
// by harness::runRace, and what the benchmark's table counts of it (passes attempted, completed and where
// won, contacts, lap time lost against each car alone, ...). The same race in roar_bench's loop, in a
// batch job on Dask (roar_core.traffic_race) and in the table's sums: TrafficTotals add in the order of
// the races, so that the table is the same to the last digit however the races ran.
#include <array>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "roar/harness/pass_place.h"
#include "roar/harness/race.h"
#include "roar/planning/overtaking/options.h"
#include "roar/planning/trajectory.h"
#include "roar/track/track.h"
#include "roar/vehicle/vehicle_params.h"

namespace roar::harness {

// The fields the benchmark races, in its table's order: a slow pace car on pole and three stack cars behind
// it; six cars pace_step apart on a reverse grid; two equal cars, the one on pole slowed by 5 %.
const std::vector<std::string>& trafficFieldKinds();

struct TrafficField {
  std::string kind;
  std::vector<RaceCar> cars;
  std::vector<std::string> pace_order;  // fastest first (ties: grid order)
};

// Of pace between neighbours of the reverse grid (the fastest at 1).
constexpr double kMinPaceStep = 0.01, kMaxPaceStep = 0.15;

// The field of `kind` drawn from `seed` (the paces' jitter); std::invalid_argument for an unknown kind or a
// pace step outside its range.
TrafficField trafficField(const std::string& kind, int seed, double pace_step);

// What the table counts of races, summed over them.
struct TrafficTotals {
  int races = 0, attempts = 0, completed = 0, aborted = 0, contacts = 0, at_fault = 0, track_limits = 0, barrier = 0;
  int pace_order = 0, pace_order_races = 0, late_passes = 0, defences = 0, given_up = 0;
  int pairs_out_of_order = 0;  // over the reverse-grid races: pairs of cars finishing against their pace
  std::vector<double> catch_to_pass, passing_share, lap_loss;
  double traffic_time = 0.0, race_seconds = 0.0;
  // Completed passes by where they were won (harness::passPlace): [place][0 left, 1 right][1 inside].
  std::array<std::array<std::array<int, 2>, 2>, 3> won{};

  void add(const TrafficTotals& other);
  int wonAt(PassPlace place, int side, int inside) const { return won[static_cast<int>(place)][side][inside]; }
};

// Every figure of TrafficTotals by name: the one list its conversions (to Python, from a batch's rows) read.
// `won` is the 12 counts in [place][side][inside] order.
using TrafficFigure = std::variant<int*, double*, std::vector<double>*, std::array<int, 12>*>;
std::vector<std::pair<std::string, TrafficFigure>> trafficFigures(TrafficTotals* totals, std::array<int, 12>* won);
void setWon(TrafficTotals* totals, const std::array<int, 12>& won);

// A circuit's races: the racing line they drive and each car's run alone from its grid slot at its pace
// (kept for the races after: the full-pace cars' runs serve every seed).
class TrafficCircuit {
 public:
  // `name`: the map's, for the verbose lines.
  TrafficCircuit(const std::string& name, const track::Track& track, const vehicle::VehicleParams& vehicle, int laps,
                 const planning::OvertakeOptions& overtake);

  // One race of `field`; with `verbose`, a line per pass, contact and excursion on it ("<map> seed <n>: ...").
  TrafficTotals race(const TrafficField& field, int seed, std::FILE* verbose = nullptr);

  const planning::Trajectory& line() const { return line_; }
  const RaceOptions& options() const { return options_; }

 private:
  const RaceCarResult& alone(const RaceCar& car);

  std::string name_;
  const track::Track& track_;
  const vehicle::VehicleParams& vehicle_;
  RaceOptions options_;
  planning::Trajectory line_;
  std::map<std::pair<int, double>, RaceCarResult> alone_at_;
};

}  // namespace roar::harness

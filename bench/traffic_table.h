#pragma once
// roar_bench --traffic: races of the stack's cars in traffic on every shipped circuit (harness::runRace).
#include <string>
#include <vector>

#include "roar/harness/traffic.h"
#include "roar/planning/overtaking/planner.h"

namespace roar::bench {

struct TrafficTableOptions {
  int seeds = 3;  // races per circuit and field
  int laps = 3;   // per race
  planning::OvertakeOptions overtake;
  std::string only_map, only_field;  // one circuit, one field (empty: all)
  bool verbose = false;
  // Of pace between neighbours of the reverse grid (the fastest at 1): harness::kMinPaceStep to kMaxPaceStep.
  double pace_step = 0.05;
  // The races as a batch on Dask (python3 -m roar_batch) rather than one after another here: on an embedded
  // local cluster of `workers` processes (0: one a core), or on the running cluster at `scheduler`.
  struct Batch {
    bool enabled = false;
    std::string scheduler;
    int workers = 0;
  } batch;
};

// One race of the table: a circuit, a field, a seed.
struct TrafficRace {
  std::string map, field;
  int seed = 0;
};

// Runs the races as one batch (roar_batch's kind traffic: each race a job calling roar_core.traffic_race)
// and returns their totals in the races' order; std::runtime_error when the batch or a race fails.
std::vector<harness::TrafficTotals> raceAsBatch(const std::vector<TrafficRace>& races,
                                                const TrafficTableOptions& table);

// maps_dir: the circuits; the sedan of urdf_dir and vehicle_config_dir is every entrant's car. Returns the number
// of contacts between cars over every race. Throws std::invalid_argument for an unknown field or a pace step
// outside its range.
int printTrafficTable(const std::string& maps_dir, const std::string& urdf_dir, const std::string& vehicle_config_dir,
                      const TrafficTableOptions& options);

// Sets one option of planning::overtakeOptionTable from "<group>.<name>=value" (roar_bench --overtake); throws
// std::invalid_argument.
void setOvertakeOption(planning::OvertakeOptions* options, const std::string& assignment);

}  // namespace roar::bench

#pragma once
// roar_bench --traffic: races of the stack's cars in traffic on every shipped circuit (harness::runRace).
#include <string>

#include "roar/planning/overtaking/planner.h"

namespace roar::bench {

struct TrafficTableOptions {
  int seeds = 3;  // races per circuit and field
  int laps = 3;   // per race
  planning::OvertakeOptions overtake;
  std::string only_map, only_field;  // one circuit, one field (empty: all)
  bool verbose = false;
  // Of pace between neighbours of the reverse grid (the fastest at 1): kMinPaceStep to kMaxPaceStep.
  double pace_step = 0.05;
};
constexpr double kMinPaceStep = 0.01, kMaxPaceStep = 0.15;

// maps_dir: the circuits; the sedan of urdf_dir and vehicle_config_dir is every entrant's car. Returns the number
// of contacts between cars over every race. Throws std::invalid_argument for an unknown field or a pace step
// outside its range.
int printTrafficTable(const std::string& maps_dir, const std::string& urdf_dir, const std::string& vehicle_config_dir,
                      const TrafficTableOptions& options);

// Sets one option of planning::overtakeOptionTable from "<group>.<name>=value" (roar_bench --overtake); throws
// std::invalid_argument.
void setOvertakeOption(planning::OvertakeOptions* options, const std::string& assignment);

}  // namespace roar::bench

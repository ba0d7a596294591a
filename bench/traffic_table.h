#pragma once
// roar_bench --traffic: races of the stack's cars in traffic on every shipped circuit (stack::runRace).
#include <string>

#include "roar/planning/overtaking.h"

namespace roar::bench {

// seeds: races per circuit and field; only_map, only_field: one circuit, one field (empty: all); laps per race;
// maps_dir: the circuits; vehicle: the car of every entrant. Returns the number of contacts between cars over every
// race.
int printTrafficTable(const std::string& maps_dir, const std::string& urdf_dir, const std::string& vehicle_config_dir,
                      int seeds, int laps, const planning::OvertakeOptions& overtake, const std::string& only_map = "",
                      bool verbose = false, const std::string& only_field = "");

// Sets one OvertakeOptions field from "name=value" (roar_bench --overtake); throws std::invalid_argument.
void setOvertakeOption(planning::OvertakeOptions* options, const std::string& assignment);

}  // namespace roar::bench

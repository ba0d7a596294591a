#pragma once
// The overtaking planner's options by name: the one table roar_bench --overtake=<group>.<name>=<value> and
// the planner node's parameters ~<group>/<name> both read, with the range each value must lie in. The car's
// size is not in it (a race takes it from the vehicle's body), nor prediction.keep (the node keeps them).
#include <string>
#include <vector>

#include "roar/config/option_table.h"
#include "roar/planning/overtaking/options.h"

namespace roar::planning {

using OvertakeOptionEntry = config::OptionEntry;

// Every settable option of `options`, in its groups' order.
std::vector<OvertakeOptionEntry> overtakeOptionTable(OvertakeOptions* options);

// Sets the option `name` from `text` (a number, a whole one for counts, 0 or 1 for flags, in its range).
// Throws std::invalid_argument naming `label` and the option: an unknown name with the nearest known one.
void setOvertakeOption(OvertakeOptions* options, const std::string& name, const std::string& text,
                       const std::string& label);

}  // namespace roar::planning

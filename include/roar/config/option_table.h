#pragma once
// Options set by name at run time (a command-line flag, a batch's matrix, a binding's dict): a table of each
// option's name, the field it sets and the range its value must lie in, and the one setter that reads a value
// into it. planning::overtakeOptionTable and control::trackerOptionTable are such tables.
#include <limits>
#include <string>
#include <variant>
#include <vector>

namespace roar::config {

struct OptionEntry {
  std::string name;  // e.g. passing.stall_time
  std::variant<double*, int*, bool*> field;
  double low = -std::numeric_limits<double>::infinity();  // the range a value must lie in (flags: 0 or 1)
  double high = std::numeric_limits<double>::infinity();
};

// Sets the option `name` of `table` from `text` (a number, a whole one for counts, 0 or 1 for flags, in its
// range). Throws std::invalid_argument naming `label` and the option: an unknown name with the nearest known
// one and the list of them.
void setOption(const std::vector<OptionEntry>& table, const std::string& name, const std::string& text,
               const std::string& label);

}  // namespace roar::config

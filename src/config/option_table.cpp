#include "roar/config/option_table.h"

#include <stdexcept>

#include "roar/config/number.h"
#include "roar/config/yaml_section.h"

namespace roar::config {

namespace {

// "[low, high]" with no trailing zeros.
std::string rangeText(double low, double high) {
  auto text = [](double x) {
    std::string s = std::to_string(x);
    s.erase(s.find_last_not_of('0') + 1);
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
  };
  return "[" + text(low) + ", " + text(high) + "]";
}

}  // namespace

void setOption(const std::vector<OptionEntry>& table, const std::string& name, const std::string& text,
               const std::string& label) {
  const std::string option = label + " " + name;
  for (const auto& entry : table) {
    if (entry.name != name) continue;
    if (auto* count = std::get_if<int*>(&entry.field)) {
      **count = static_cast<int>(
          wholeNumberArgument(option, text, static_cast<long long>(entry.low), static_cast<long long>(entry.high)));
      return;
    }
    const double value = numberArgument(option, text);
    if (auto* flag = std::get_if<bool*>(&entry.field)) {
      if (value != 0.0 && value != 1.0) throw std::invalid_argument(option + " '" + text + "' is not 0 or 1");
      **flag = value != 0.0;
      return;
    }
    if (!(value >= entry.low && value <= entry.high)) {
      throw std::invalid_argument(option + " " + text + " is outside " + rangeText(entry.low, entry.high));
    }
    *std::get<double*>(entry.field) = value;
    return;
  }
  std::vector<std::string> known;
  std::string list;
  for (const auto& entry : table) {
    known.push_back(entry.name);
    list += (list.empty() ? "" : ", ") + entry.name;
  }
  const std::string near = nearestKey(name, known);
  throw std::invalid_argument(label + ": no option '" + name + "'" +
                              (near.empty() ? "" : " (did you mean '" + near + "'?)") + "; options: " + list);
}

}  // namespace roar::config

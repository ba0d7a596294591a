#include "roar/config/number.h"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace roar::config {

bool parseNumber(const std::string& text, double* value) {
  if (text.empty()) return false;
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

double numberArgument(const std::string& name, const std::string& text) {
  double value = 0.0;
  if (!parseNumber(text, &value) || !std::isfinite(value))
    throw std::invalid_argument(name + " '" + text + "' is not a number");
  return value;
}

long long wholeNumberArgument(const std::string& name, const std::string& text, long long low, long long high) {
  double value = 0.0;
  const bool whole = parseNumber(text, &value) && std::isfinite(value) && value == std::floor(value);
  if (!whole || value < static_cast<double>(low) || value > static_cast<double>(high)) {
    const std::string range = high == INT_MAX ? "of at least " + std::to_string(low)
                                              : "from " + std::to_string(low) + " to " + std::to_string(high);
    throw std::invalid_argument(name + " '" + text + "' is not a whole number " + range);
  }
  return static_cast<long long>(value);
}

bool helpRequested(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") return true;
  }
  return false;
}

}  // namespace roar::config

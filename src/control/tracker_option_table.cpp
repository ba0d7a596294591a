#include "roar/control/tracker_option_table.h"

#include <stdexcept>

namespace roar::control {

std::vector<config::OptionEntry> trackerOptionTable(TrackerOptions* o) {
  return {
      {"lookahead_min", &o->lookahead_min, 0.5, 100.0}, {"lookahead_time", &o->lookahead_time, 0.0, 5.0},
      {"stanley_gain", &o->stanley_gain, 0.01, 50.0},   {"yaw_rate_gain", &o->yaw_rate_gain, 0.0, 2.0},
      {"speed_gain", &o->speed_gain, 0.01, 10.0},       {"speed_preview", &o->speed_preview, 0.0, 3.0},
      {"max_speed", &o->max_speed, 0.0, 150.0},
  };
}

std::string lateralMethodName(LateralMethod method) {
  return method == LateralMethod::kStanley ? "stanley" : "pure_pursuit";
}

void setTrackerOption(TrackerOptions* options, const std::string& name, const std::string& text,
                      const std::string& label) {
  if (name != "lateral_control") {
    config::setOption(trackerOptionTable(options), name, text, label);
    return;
  }
  if (text == "stanley") {
    options->lateral = LateralMethod::kStanley;
  } else if (text == "pure_pursuit") {
    options->lateral = LateralMethod::kPurePursuit;
  } else {
    throw std::invalid_argument(label + " lateral_control '" + text + "' is neither pure_pursuit nor stanley");
  }
}

}  // namespace roar::control

#pragma once
// The trajectory tracker's gains and limits by name: the names and ranges of the controller node's live
// settings (cfg/Controller.cfg; msg_conversion_test ControllerConfig.RangesAreTheTrackerTables holds them
// together), for what sets them without ROS (a batch's matrix, roar_core.run_time_trial and run_race).
#include <string>
#include <vector>

#include "roar/config/option_table.h"
#include "roar/control/trajectory_tracker.h"

namespace roar::control {

// The numeric options of `options`; the lateral law is `lateral_control` (setTrackerOption).
std::vector<config::OptionEntry> trackerOptionTable(TrackerOptions* options);

// The lateral law's names, as Controller.cfg's lateral_control takes them.
std::string lateralMethodName(LateralMethod method);

// Sets `name` from `text`: lateral_control (pure_pursuit or stanley) or an option of trackerOptionTable.
// Throws std::invalid_argument naming `label` and the option.
void setTrackerOption(TrackerOptions* options, const std::string& name, const std::string& text,
                      const std::string& label);

}  // namespace roar::control

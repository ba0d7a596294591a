#pragma once
// Race control -> ROS messages: /race_status.
#include <roar_ros/RaceStatus.h>

#include "roar/race/race_control.h"

namespace roar::ros_bridge {

// The race at simulated time `now`: the map, the laps, whether it is over, and every car's standing,
// lap, sector and incidents in the standings' order. msg_conversion_test RaceStatusHasEveryCarsStanding.
roar_ros::RaceStatus toRaceStatus(const race::RaceControl& race, double now);

}  // namespace roar::ros_bridge

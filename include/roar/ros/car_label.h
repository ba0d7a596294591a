#pragma once
// Text that rides above a car in rviz: race_control's timing and the planner's decision. Each is placed in
// the car's own frame and frame-locked, so rviz draws it where the car is now, whatever each publisher's
// lag; the two heights keep one from covering the other (MsgConversion.CarLabelsRideInTheCarsFrame).
#include <visualization_msgs/Marker.h>

#include <string>

namespace roar::ros_bridge {

inline constexpr double kTimingLabelHeight = 5.0;     // m above base_link: two lines of 0.8 m
inline constexpr double kManoeuvreLabelHeight = 3.2;  // m above base_link: one line of 0.7 m, over the roof

// A TEXT_VIEW_FACING marker `height` above the car's base_link, `size` metres high per line.
visualization_msgs::Marker carLabel(const std::string& car, double height, double size, const ros::Time& stamp);

}  // namespace roar::ros_bridge

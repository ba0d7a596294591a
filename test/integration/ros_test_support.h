#pragma once
#include <ros/ros.h>

#include <functional>

namespace roar::test {

// Spins callbacks until cond() holds or `seconds` of wall time pass; returns cond().
inline bool waitFor(const std::function<bool()>& cond, double seconds = 20.0) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    ros::spinOnce();
    if (cond()) return true;
    ros::WallDuration(0.01).sleep();
  }
  return cond();
}

}  // namespace roar::test

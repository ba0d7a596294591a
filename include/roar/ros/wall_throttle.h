#pragma once
// rosconsole's *_THROTTLE macros count in ros::Time, which is simulated time under /use_sim_time: a
// simulator stepping faster than real time (real_time_factor 0) let a "throttled" warning flood hundreds
// of lines a wall second. These count in wall time.
#include <ros/console.h>
#include <ros/time.h>

#define ROAR_LOG_WALL_THROTTLE(log_macro, period, ...)                                       \
  do {                                                                                       \
    static ros::WallTime roar_last_logged_;                                                  \
    const ros::WallTime roar_now_ = ros::WallTime::now();                                    \
    if (roar_last_logged_.isZero() || (roar_now_ - roar_last_logged_).toSec() >= (period)) { \
      roar_last_logged_ = roar_now_;                                                         \
      log_macro(__VA_ARGS__);                                                                \
    }                                                                                        \
  } while (0)
#define ROAR_WARN_WALL_THROTTLE(period, ...) ROAR_LOG_WALL_THROTTLE(ROS_WARN, period, __VA_ARGS__)
#define ROAR_ERROR_WALL_THROTTLE(period, ...) ROAR_LOG_WALL_THROTTLE(ROS_ERROR, period, __VA_ARGS__)

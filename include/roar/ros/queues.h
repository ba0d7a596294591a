#pragma once
#include <roar_ros/QueueDepths.h>

#include <algorithm>
#include <cmath>

namespace roar::ros_bridge {

// Outgoing queue of every per-tick topic, the drivers' (control, local_trajectory, local_path) and roar_sim's
// (odom, vehicle_status, joint_states, collision, rl/observation, rl/step), Python's too (msg/QueueDepths.msg):
// 10 s of ticks at the default 20 Hz. roar_sim paces itself by the /clock a recorder has written, not by its
// links to the drivers, which can fall further behind on a loaded machine: ten messages lost one control of
// 6,000 beside two busy loops and a compiler. A step request of many ticks publishes its ticks' messages at once.
inline constexpr int kPerTickQueue = roar_ros::QueueDepths::PER_TICK;
// s of messages every outgoing queue keeps for a subscriber whose link lags: the per-tick queue's.
inline constexpr double kQueueSeconds = kPerTickQueue / 20.0;

// Outgoing queue of a sensor's topic: kQueueSeconds of its messages, as the per-tick topics keep (at least 10,
// at most 1,000). In step mode a request for 20 ticks publishes a second of camera images at once, every one of
// which a subscriber gets (rostest sensors). An image queue costs memory only while a link lags: 10 s of
// 640x480 RGB at 20 Hz is 184 MB.
inline int sensorQueue(double rate_hz) {
  return static_cast<int>(std::clamp(std::ceil(rate_hz * kQueueSeconds), 10.0, 1000.0));
}

}  // namespace roar::ros_bridge

#pragma once
#include <algorithm>
#include <cmath>

// Outgoing queue of every per-tick topic, the drivers' (control, local_trajectory, local_path) and roar_sim's
// (odom, vehicle_status, joint_states, collision, rl/observation, rl/step): a publisher keeps this many messages
// for each subscriber whose link lags. roar_sim paces itself by the /clock a recorder has written, not by its
// links to the drivers, which can fall further behind on a loaded machine: ten messages lost one control of
// 6,000 beside two busy loops and a compiler. A step request of many ticks publishes its ticks' messages at
// once. 200 are 10 s of ticks at 20 Hz.
namespace roar::ros_bridge {

inline constexpr int kPerTickQueue = 200;

// Outgoing queue of a sensor's topic: as many seconds of its messages as the per-tick topics keep (at least 10,
// at most 1,000) for each subscriber whose link lags. In step mode a request for 20 ticks publishes a second of
// camera images at once: a queue of 10 lost 2 of them to a tester on a loaded machine (rostest sensors). An
// image queue costs memory only while a link lags: 10 s of 640x480 RGB at 20 Hz is 184 MB.
inline constexpr double kSensorQueueSeconds = 10.0;
inline int sensorQueue(double rate_hz) {
  return static_cast<int>(std::clamp(std::ceil(rate_hz * kSensorQueueSeconds), 10.0, 1000.0));
}

}  // namespace roar::ros_bridge

#pragma once
// Outgoing queue of the drivers' per-tick topics (control, local_trajectory, local_path): a publisher
// keeps this many messages for each subscriber whose link lags. roar_sim paces itself by the /clock a
// recorder has written, not by its links to the drivers, which can fall further behind on a loaded
// machine: ten messages lost one control of 6,000 beside two busy loops and a compiler. 200 are 10 s of
// ticks at 20 Hz.
namespace roar::ros_bridge {

inline constexpr int kPerTickQueue = 200;

}  // namespace roar::ros_bridge

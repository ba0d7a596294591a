#pragma once
// What an agent's observation holds (rl/observation.h builds it): readable and checked where the
// simulator is not linked, as a scenario's agent is checked by the stack's programs.
#include <string>
#include <vector>

#include "roar/sensors/sensor_spec.h"

namespace roar::rl {

struct LidarObservation {
  int beams = 0;            // 0: no lidar key
  double max_range = 50.0;  // m: a beam that hits nothing nearer reads this
  double fov_deg = 180.0;   // horizontal, centred straight ahead
  double height = 0.6;      // m above base_link
};

struct CameraObservation {
  int width = 0, height = 0;  // 0: no camera keys
  double fov_deg = 90.0;      // horizontal
  bool rgb = true;
  bool depth = false;
  double max_depth = 100.0;  // m: farther (and sky) reads this
  sensors::Mount mount = defaultMount();
  static sensors::Mount defaultMount();  // the default sensor set's front camera: 0.6 m ahead, 1.55 m up, 5 deg down
};

struct ObservationOptions {
  bool speed = true;
  bool velocity = true;
  bool angular_velocity = true;
  bool imu = false;
  std::vector<double> waypoint_distances = {5.0, 10.0, 20.0, 40.0, 60.0, 80.0};  // m; empty: no waypoints
  LidarObservation lidar;
  CameraObservation camera;
};

// Throws std::invalid_argument naming the option that cannot work (nothing observed, a negative distance,
// a camera of zero width, ...).
void validate(const ObservationOptions& options);

// The key of the waypoint d metres ahead: "waypoint_10", "waypoint_2.5".
std::string waypointKey(double distance);

}  // namespace roar::rl

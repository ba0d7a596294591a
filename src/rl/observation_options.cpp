#include "roar/rl/observation_options.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace roar::rl {

sensors::Mount CameraObservation::defaultMount() {
  sensors::Mount m;
  m.position = Eigen::Vector3d(0.6, 0.0, 1.55);
  m.pitch = 5.0 * M_PI / 180.0;
  return m;
}

std::string waypointKey(double distance) {
  char key[64];
  std::snprintf(key, sizeof(key), "waypoint_%g", distance);
  return key;
}

void validate(const ObservationOptions& o) {
  auto fail = [](const std::string& why) { throw std::invalid_argument("observation: " + why); };
  for (double d : o.waypoint_distances) {
    if (!(d >= 0.0) || !std::isfinite(d))
      fail("waypoint_distances: " + std::to_string(d) + " is not a distance ahead (>= 0)");
  }
  for (std::size_t i = 0; i < o.waypoint_distances.size(); ++i) {
    for (std::size_t k = 0; k < i; ++k) {
      if (waypointKey(o.waypoint_distances[i]) == waypointKey(o.waypoint_distances[k])) {
        fail("waypoint_distances: " + waypointKey(o.waypoint_distances[i]) + " is asked for twice");
      }
    }
  }
  if (o.lidar.beams < 0 || o.lidar.beams > 4096) fail("lidar.beams must be in [0, 4096]");
  if (o.lidar.beams > 0 && !(o.lidar.max_range > 0.0)) fail("lidar.max_range must be positive");
  if (o.lidar.beams > 0 && !(o.lidar.fov_deg > 0.0 && o.lidar.fov_deg <= 360.0)) fail("lidar.fov must be in (0, 360]");
  const auto& c = o.camera;
  if (c.width < 0 || c.height < 0 || (c.width > 0) != (c.height > 0) || c.width > 4096 || c.height > 4096) {
    fail("camera.width and camera.height must both be 0 (no camera) or in [1, 4096]");
  }
  if (c.width > 0 && !(c.fov_deg > 0.0 && c.fov_deg < 180.0)) fail("camera.fov must be in (0, 180)");
  if (c.width > 0 && !c.rgb && !c.depth) fail("camera: neither rgb nor depth is asked for");
  if (c.width > 0 && c.depth && !(c.max_depth > 0.0)) fail("camera.max_depth must be positive");
  if (!o.speed && !o.velocity && !o.angular_velocity && !o.imu && o.waypoint_distances.empty() && o.lidar.beams == 0 &&
      c.width == 0) {
    fail("nothing is observed");
  }
}

}  // namespace roar::rl

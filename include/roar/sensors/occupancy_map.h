#pragma once
// The occupancy map sensor: a bird's-eye image of the ground around a car, centred on the sensor and
// turned with the car's heading (forward is up, left is left; ROAR_PY's layout), one byte a pixel:
// the road (with its markings and kerbs), another car, or anything else (grass, barriers). Rendered by
// casting one ray straight down per pixel into the ray scene, so other cars show by their real shape and
// the car's own body is left out.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "roar/sensors/ray_scene.h"
#include "roar/sensors/sensor_spec.h"

namespace roar::sensors {

constexpr std::uint8_t kOccupancyRoad = 255;
constexpr std::uint8_t kOccupancyVehicle = 128;
constexpr std::uint8_t kOccupancyElsewhere = 0;

struct OccupancyFrame {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // mono8, row-major, row 0 the farthest ahead
};

class OccupancyMapRenderer {
 public:
  explicit OccupancyMapRenderer(const OccupancyMapSpec& spec);
  // sensor_in_map: the sensor's frame; only its position and heading (yaw) count.
  void render(const RayScene& scene, const Eigen::Isometry3d& sensor_in_map, int own_vehicle, OccupancyFrame* frame);

 private:
  OccupancyMapSpec spec_;
  std::vector<Eigen::Vector2d> offsets_;  // per pixel: (forward, left) metres from the centre
  std::vector<Eigen::Vector3d> origins_;
  std::vector<RayHit> hits_;
};

}  // namespace roar::sensors

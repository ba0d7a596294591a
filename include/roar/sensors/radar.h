#pragma once
// CARLA's radar: each scan casts points_per_second * dt rays spread uniformly over an elliptical cone
// (horizontal_fov by vertical_fov) and reports every hit within max_distance as a detection, with the
// column order and signs of CARLA's radar measurement (what ROAR_PY's CARLA backend hands on).
#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "roar/sensors/ray_scene.h"
#include "roar/sensors/sensor_spec.h"

namespace roar::sensors {

struct RadarDetection {
  float velocity;  // m/s along the line of sight: the hit's velocity less the sensor's; negative approaching
  float azimuth;   // rad from the sensor's x axis, positive to the right (CARLA's sign)
  float altitude;  // rad above the sensor's x-y plane
  float depth;     // m
};

class Radar {
 public:
  Radar(const RadarSpec& spec, unsigned seed);
  // sensor_velocity: the sensor's own velocity (m/s, map frame).
  void scan(const RayScene& scene, const Eigen::Isometry3d& sensor_in_map, const Eigen::Vector3d& sensor_velocity,
            int own_vehicle, double dt, std::vector<RadarDetection>* detections);

 private:
  RadarSpec spec_;
  double carry_ = 0.0;  // fractional rays left over from the last scan
  std::mt19937 rng_;
  std::vector<Eigen::Vector3f> dirs_;
  std::vector<RayHit> hits_;
};

}  // namespace roar::sensors

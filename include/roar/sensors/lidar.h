#pragma once
// A spinning multi-beam LiDAR with ROAR_PY's (CARLA's) parameters. Each scan() returns the slice swept
// since the previous one: points_per_second * dt points, num_lasers beams per firing, the head turning
// rotation_frequency * 360 degrees per second (limited to horizontal_fov).
#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "roar/sensors/ray_scene.h"
#include "roar/sensors/sensor_spec.h"

namespace roar::sensors {

struct LidarPoint {
  float x, y, z;    // m, sensor frame
  float intensity;  // 0..1: material reflectivity, incidence angle and atmospheric attenuation
};

class SpinningLidar {
 public:
  SpinningLidar(const LidarSpec& spec, unsigned seed);
  void scan(const RayScene& scene, const Eigen::Isometry3d& sensor_in_map, int own_vehicle, double dt,
            std::vector<LidarPoint>* points);
  double azimuthDeg() const { return azimuth_deg_; }

 private:
  LidarSpec spec_;
  std::vector<double> elevations_;  // rad, one per laser
  double azimuth_deg_ = 0.0;        // of the next firing, from the sensor's x axis towards y
  double carry_ = 0.0;              // fractional firings left over from the last scan
  std::mt19937 rng_;
  std::vector<Eigen::Vector3f> dirs_;
  std::vector<Eigen::Vector3f> local_dirs_;
  std::vector<RayHit> hits_;
};

}  // namespace roar::sensors

#pragma once
// Scenes for sensor tests: a stadium circuit with long straight barriers, and helpers.
#include "roar/sensors/ray_scene.h"
#include "roar/sensors/vehicle_looks.h"
#include "test_support.h"

namespace roar::test {

// Two 400 m straights along y = 0 (driven towards +x) and y = 120, joined by semicircles of radius 60;
// road 12 m wide, barriers 3 m outside the edges.
inline track::Track stadiumTrack() {
  std::vector<track::CentreLinePoint> pts;
  auto add = [&](double x, double y) { pts.push_back({x, y, 6.0, 6.0}); };
  for (double x = 0; x < 400; x += 2) add(x, 0);
  for (int k = 0; k < 94; ++k) {
    const double a = -M_PI / 2 + M_PI * k / 94;
    add(400 + 60 * std::cos(a), 60 + 60 * std::sin(a));
  }
  for (double x = 400; x > 0; x -= 2) add(x, 120);
  for (int k = 0; k < 94; ++k) {
    const double a = M_PI / 2 + M_PI * k / 94;
    add(60 * std::cos(a), 60 + 60 * std::sin(a));
  }
  track::TrackInfo info;
  info.name = "stadium";
  info.barrier_offset = 3.0;
  info.start_finish_s = 300.0;
  return track::Track(pts, info);
}

inline sensors::VisualMesh sedanLooks() { return sensors::readVehicleLooks(sourceDir() + "/urdf/sedan.urdf"); }

inline Eigen::Isometry3d poseAt(double x, double y, double z, double yaw = 0, double pitch = 0) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(x, y, z);
  t.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix();
  return t;
}

}  // namespace roar::test

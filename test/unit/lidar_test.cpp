#include <gtest/gtest.h>

#include "roar/sensors/lidar.h"
#include "sensor_test_scene.h"

using namespace roar;

namespace {
sensors::LidarSpec defaultLidar() { return sensors::LidarSpec(); }
}  // namespace

TEST(Lidar, PointsOffAFlatWallLieOnItsPlane) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  sensors::SpinningLidar lidar(defaultLidar(), 1);
  std::vector<sensors::LidarPoint> points;
  const Eigen::Isometry3d pose = test::poseAt(200, 0, 1.0);
  int on_wall = 0;
  for (int k = 0; k < 20; ++k) {  // one second: 20 sweeps
    lidar.scan(scene, pose, -1, 0.05, &points);
    for (const auto& p : points) {
      const Eigen::Vector3d w = pose * Eigen::Vector3d(p.x, p.y, p.z);
      if (w.z() < 0.1 || w.z() > 0.9 || std::abs(w.y()) < 8.0 || std::abs(w.x() - 200) > 30) continue;
      EXPECT_NEAR(std::abs(w.y()), 9.0, 0.01);
      ++on_wall;
    }
  }
  EXPECT_GT(on_wall, 500);
}

TEST(Lidar, EachScanIsTheSliceSweptSinceTheLast) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  sensors::LidarSpec spec = defaultLidar();
  spec.rotation_frequency = 10.0;  // half a turn per 0.05 s scan
  spec.upper_fov = -5.0;           // every beam hits the ground or a wall
  spec.max_distance = 200.0;
  sensors::SpinningLidar lidar(spec, 1);
  std::vector<sensors::LidarPoint> points;
  lidar.scan(scene, test::poseAt(200, 0, 1.0), -1, 0.05, &points);
  const std::size_t first = points.size();
  EXPECT_EQ(first, 87u * 32u) << "87.5 firings of 32 beams in 0.05 s: whole firings, the half carried over";
  for (const auto& p : points) {
    const double az = std::atan2(p.y, p.x);
    EXPECT_GE(az, -1e-6);  // [0, 180) degrees: the first half turn
  }
  EXPECT_NEAR(lidar.azimuthDeg(), 180.0, 1e-9);
  lidar.scan(scene, test::poseAt(200, 0, 1.0), -1, 0.05, &points);
  EXPECT_EQ(first + points.size(), 5600u) << "56000 points/s over 0.1 s";
  for (const auto& p : points) {
    EXPECT_GE(std::fmod(std::atan2(p.y, p.x) + 2 * M_PI, 2 * M_PI), M_PI - 1e-6) << "the second half turn";
  }
}

TEST(Lidar, ACarInFrontAppearsAndTheOwnCarDoesNot) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  const int ego = scene.addVehicle(test::sedanLooks(), {0.2f, 0.2f, 0.2f});
  const int rival = scene.addVehicle(test::sedanLooks(), {0.2f, 0.2f, 0.2f});
  scene.setVehiclePose(ego, test::poseAt(200, 0, 0));
  scene.setVehiclePose(rival, test::poseAt(212, 0, 0));
  scene.commit();
  sensors::SpinningLidar lidar(defaultLidar(), 1);
  std::vector<sensors::LidarPoint> points;
  lidar.scan(scene, test::poseAt(200, 0, 1.9), ego, 0.05, &points);
  int on_rival = 0, near_self = 0;
  for (const auto& p : points) {
    if (p.x > 9 && p.x < 15 && std::abs(p.y) < 1.0 && p.z > -1.8) ++on_rival;
    if (std::hypot(p.x, p.y) < 2.0) ++near_self;
  }
  // 87 firings per turn are 4.1 degrees apart; the car, 9 degrees wide at 12 m, takes two of them.
  EXPECT_GE(on_rival, 10);
  EXPECT_EQ(near_self, 0);
  scene.removeVehicle(rival);
  scene.commit();
  lidar.scan(scene, test::poseAt(200, 0, 1.9), ego, 0.05, &points);
  on_rival = 0;
  for (const auto& p : points) on_rival += p.x > 9 && p.x < 15 && std::abs(p.y) < 1.0 && p.z > -1.8;
  EXPECT_EQ(on_rival, 0);
}

TEST(Lidar, RangeNoiseHasTheConfiguredSpreadAndRepeatsForASeed) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  sensors::LidarSpec spec = defaultLidar();
  spec.noise_std = 0.05;
  auto run = [&](unsigned seed) {
    sensors::SpinningLidar lidar(spec, seed);
    std::vector<sensors::LidarPoint> points;
    lidar.scan(scene, test::poseAt(200, 0, 1.0, -M_PI / 2), -1, 0.05, &points);
    return points;
  };
  const auto a = run(7), b = run(7), c = run(8);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].x, b[i].x);
  double sum2 = 0;
  int n = 0;
  for (const auto& p : a) {
    const Eigen::Vector3d w = test::poseAt(200, 0, 1.0, -M_PI / 2) * Eigen::Vector3d(p.x, p.y, p.z);
    if (w.z() < 0.1 || w.z() > 0.9 || w.y() > -8 || std::abs(w.x() - 200) > 3) continue;
    const double range = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    const double true_range = range * 9.0 / std::abs(w.y() - 0.0);  // scale along the ray to the wall
    sum2 += (range - true_range) * (range - true_range);
    ++n;
  }
  ASSERT_GT(n, 30);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.05, 0.02);
  EXPECT_NE(a.front().x, c.front().x);
}

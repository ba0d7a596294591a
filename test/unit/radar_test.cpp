#include <gtest/gtest.h>

#include "roar/sensors/radar.h"
#include "sensor_test_scene.h"

using namespace roar;

namespace {

sensors::RadarSpec narrow(double fov = 10.0) {
  sensors::RadarSpec spec;
  spec.horizontal_fov = fov;
  spec.vertical_fov = fov;
  spec.points_per_second = 20000;
  return spec;
}

}  // namespace

// CARLA's radar measurement: depth to the hit, azimuth positive to the right, altitude positive up, and
// the velocity of the hit relative to the sensor along the line of sight (negative closing).
TEST(Radar, ACarAheadReadsItsRangeAndClosingSpeed) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  const int rival = scene.addVehicle(test::sedanLooks(), {0.2f, 0.2f, 0.2f});
  scene.setVehiclePose(rival, test::poseAt(230, 0, 0, M_PI));  // facing us, 30 m ahead
  scene.setVehicleVelocity(rival, {-8.0, 0, 0}, Eigen::Vector3d::Zero());
  scene.commit();
  // A 1.5 degree cone 0.95 m up spans 0.6 to 1.3 m up at the car's nose, 27.7 m away: every ray meets it.
  sensors::Radar radar(narrow(1.5), 3);
  std::vector<sensors::RadarDetection> detections;
  radar.scan(scene, test::poseAt(200, 0, 0.95), Eigen::Vector3d(12.0, 0, 0), -1, 0.05, &detections);
  ASSERT_EQ(detections.size(), 1000u) << "20,000 points/s for 0.05 s: every ray hits the car";
  for (const auto& d : detections) {
    EXPECT_GT(d.depth, 27.5f);
    EXPECT_LT(d.depth, 30.5f);
    EXPECT_NEAR(d.velocity, -20.0, 0.2) << "closing at 12 + 8 m/s";
    EXPECT_LE(std::abs(d.azimuth), 0.75 * M_PI / 180.0 + 1e-6) << "within the 1.5 degree cone";
  }
}

TEST(Radar, AzimuthIsPositiveToTheRightAndTheTrackIsStill) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  const int rival = scene.addVehicle(test::sedanLooks(), {0.2f, 0.2f, 0.2f});
  scene.setVehiclePose(rival, test::poseAt(215, -4, 0));  // ahead and to the right
  scene.commit();
  sensors::RadarSpec spec = narrow(60.0);
  spec.vertical_fov = 4.0;
  sensors::Radar radar(spec, 5);
  std::vector<sensors::RadarDetection> detections;
  radar.scan(scene, test::poseAt(200, 0, 0.8), Eigen::Vector3d::Zero(), -1, 0.05, &detections);
  int on_rival = 0;
  for (const auto& d : detections) {
    EXPECT_NEAR(d.velocity, 0.0, 1e-5) << "a still sensor sees the still track and car still";
    if (d.depth > 12.0 && d.depth < 16.0) {
      EXPECT_GT(d.azimuth, 0.0f) << "the car is to the right";
      ++on_rival;
    }
  }
  EXPECT_GT(on_rival, 20);
}

TEST(Radar, ScansCarryTheFractionOfARay) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  scene.commit();
  sensors::RadarSpec spec = narrow();
  spec.points_per_second = 1500;  // 75 rays per 0.05 s scan
  spec.max_distance = 1000;
  sensors::Radar radar(spec, 1);
  std::vector<sensors::RadarDetection> detections;
  std::size_t total = 0;
  for (int i = 0; i < 20; ++i) {
    radar.scan(scene, test::poseAt(200, 0, 1.0, 0, 0.3), Eigen::Vector3d::Zero(), -1, 0.0333, &detections);
    total += detections.size();
  }
  EXPECT_EQ(total, 999u) << "1500 points/s over 0.666 s, pointed at the ground so every ray hits";
}

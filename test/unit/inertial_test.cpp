#include <gtest/gtest.h>

#include <GeographicLib/Geodesic.hpp>

#include "roar/sensors/inertial.h"
#include "roar/sensors/vehicle_motion.h"
#include "roar/sim/world.h"
#include "test_support.h"

using namespace roar;

TEST(Imu, ParkedCarReadsGravityUpAndNoRotation) {
  const auto track = test::openGround();
  sim::World world(track, {});
  world.spawnVehicle("ego", test::sedan(), sim::Pose());
  for (int i = 0; i < 40; ++i) world.step();  // settle
  sensors::Mount mount;
  mount.position = {-0.086, 0.0, 0.5};
  std::mt19937 rng(1);
  int samples = 0;
  world.step([&](double) {
    const auto imu = sensors::sampleImu(sensors::motionOf(world.vehicleState("ego")), mount, {}, 9.81, &rng);
    EXPECT_NEAR(imu.linear_acceleration.z(), 9.81, 0.02);
    EXPECT_NEAR(imu.linear_acceleration.x(), 0.0, 0.02);
    EXPECT_NEAR(imu.linear_acceleration.y(), 0.0, 0.02);
    EXPECT_LT(imu.angular_velocity.norm(), 1e-3);
    ++samples;
  });
  EXPECT_EQ(samples, 10) << "once per physics substep";
}

TEST(Imu, MountRotationTurnsTheReading) {
  sensors::BodyMotion still;
  sensors::Mount nose_down;
  nose_down.pitch = M_PI / 2;  // the sensor's x axis points down
  std::mt19937 rng(1);
  const auto imu = sensors::sampleImu(still, nose_down, {}, 9.81, &rng);
  EXPECT_NEAR(imu.linear_acceleration.x(), -9.81, 1e-9);
  EXPECT_NEAR(imu.linear_acceleration.z(), 0.0, 1e-9);
}

TEST(Imu, TurningCarReadsCentripetalAccelerationAndYawRate) {
  sensors::BodyMotion m;
  m.angular_velocity = {0, 0, 0.5};
  m.linear_velocity = {10, 0, 0};
  m.linear_acceleration = {0, 5.0, 0};  // v * omega towards the centre (left)
  std::mt19937 rng(1);
  const auto imu = sensors::sampleImu(m, {}, {}, 9.81, &rng);
  EXPECT_NEAR(imu.linear_acceleration.y(), 5.0, 1e-9);
  EXPECT_NEAR(imu.angular_velocity.z(), 0.5, 1e-9);
}

TEST(Imu, NoiseAndBiasAreAppliedAndRepeatForASeed) {
  sensors::ImuSpec spec;
  spec.accel_noise_std = 0.1;
  spec.gyro_bias = {0.01, 0, 0};
  auto stats = [&](unsigned seed) {
    std::mt19937 rng(seed);
    double sum = 0, sum2 = 0, gx = 0;
    for (int i = 0; i < 4000; ++i) {
      const auto imu = sensors::sampleImu({}, {}, spec, 9.81, &rng);
      sum += imu.linear_acceleration.x();
      sum2 += imu.linear_acceleration.x() * imu.linear_acceleration.x();
      gx = imu.angular_velocity.x();
    }
    return std::make_tuple(sum / 4000, std::sqrt(sum2 / 4000), gx);
  };
  const auto [mean, rms, gyro] = stats(3);
  EXPECT_NEAR(mean, 0.0, 0.01);
  EXPECT_NEAR(rms, 0.1, 0.01);
  EXPECT_DOUBLE_EQ(gyro, 0.01);
  EXPECT_EQ(std::get<1>(stats(3)), rms);
}

TEST(Gnss, TheMapOriginReadsTheOriginAndEastIsEast) {
  track::GeoOrigin origin{37.9137, -122.3353, 10.0};
  std::mt19937 rng(1);
  sensors::BodyMotion at_origin;
  const auto fix = sensors::sampleGnss(at_origin, {}, {}, origin, &rng);
  EXPECT_NEAR(fix.latitude, origin.latitude, 1e-12);
  EXPECT_NEAR(fix.longitude, origin.longitude, 1e-12);
  EXPECT_NEAR(fix.altitude, origin.altitude, 1e-6);
  sensors::BodyMotion east = at_origin;
  east.pose.translation() = Eigen::Vector3d(1000.0, 0.0, 0.0);
  const auto e = sensors::sampleGnss(east, {}, {}, origin, &rng);
  double distance, azimuth1, azimuth2;
  GeographicLib::Geodesic::WGS84().Inverse(origin.latitude, origin.longitude, e.latitude, e.longitude, distance, azimuth1,
                                           azimuth2);
  EXPECT_NEAR(distance, 1000.0, 0.01);
  EXPECT_NEAR(azimuth1, 90.0, 0.01);
}

TEST(Velocimeter, BodyAndWorldVelocities) {
  sensors::BodyMotion m;
  m.pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();  // facing north
  m.linear_velocity = {0, 20, 0};
  const auto v = sensors::sampleVelocity(m, {});
  EXPECT_NEAR(v.linear_body.x(), 20.0, 1e-9);
  EXPECT_NEAR(v.linear_body.y(), 0.0, 1e-9);
  EXPECT_NEAR(v.linear_world.y(), 20.0, 1e-9);
}

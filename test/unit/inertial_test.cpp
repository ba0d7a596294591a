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
  world.spawnVehicle("ego", test::sedan(), track::Pose());
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
  GeographicLib::Geodesic::WGS84().Inverse(origin.latitude, origin.longitude, e.latitude, e.longitude, distance,
                                           azimuth1, azimuth2);
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

namespace {
sensors::SensorSpec vectorSensor(sensors::SensorType type) {
  sensors::SensorSpec s;
  s.name = sensors::typeName(type);
  s.type = type;
  return s;
}
}  // namespace

TEST(VectorSensors, ReadWhatROARPYsSensorsReadOfATurningCar) {
  // A car at (10, 5, 0.3) heading 90 degrees (north), turning left at 0.5 rad/s at 20 m/s: it accelerates
  // towards the centre of its turn (west) at v w = 10 m/s^2.
  sensors::BodyMotion m;
  m.pose.translation() = Eigen::Vector3d(10, 5, 0.3);
  m.pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  m.linear_velocity = {0, 20, 0};
  m.angular_velocity = {0, 0, 0.5};
  m.linear_acceleration = {-10, 0, 0};
  std::mt19937 rng(1);
  auto accelerometer = vectorSensor(sensors::SensorType::kAccelerometer);
  Eigen::Vector3d a = sensors::sampleVector(accelerometer, m, 9.81, &rng);
  EXPECT_NEAR(a.x(), 0.0, 1e-9) << "sensor frame: the turn pulls to the car's left (+y)";
  EXPECT_NEAR(a.y(), 10.0, 1e-9);
  EXPECT_NEAR(a.z(), 9.81, 1e-9) << "specific force, as a real accelerometer";
  accelerometer.vector.map_frame = true;
  accelerometer.vector.gravity = false;
  a = sensors::sampleVector(accelerometer, m, 9.81, &rng);
  EXPECT_NEAR(a.x(), -10.0, 1e-9) << "map frame without gravity: ROAR_PY's accelerometer";
  EXPECT_NEAR(a.z(), 0.0, 1e-9);

  auto gyroscope = vectorSensor(sensors::SensorType::kGyroscope);
  gyroscope.mount.pitch = M_PI / 2;  // sensor x points down: yaw rate shows on its x axis, negated
  EXPECT_NEAR(sensors::sampleVector(gyroscope, m, 9.81, &rng).x(), -0.5, 1e-9);
  gyroscope.vector.map_frame = true;
  EXPECT_NEAR(sensors::sampleVector(gyroscope, m, 9.81, &rng).z(), 0.5, 1e-9);

  auto rpy = vectorSensor(sensors::SensorType::kRollPitchYaw);
  const Eigen::Vector3d angles = sensors::sampleVector(rpy, m, 9.81, &rng);
  EXPECT_NEAR(angles.x(), 0.0, 1e-9);
  EXPECT_NEAR(angles.y(), 0.0, 1e-9);
  EXPECT_NEAR(angles.z(), M_PI / 2, 1e-9);
  rpy.vector.bias = {0, 0, M_PI};  // 3 pi / 2 wraps to -pi / 2
  EXPECT_NEAR(sensors::sampleVector(rpy, m, 9.81, &rng).z(), -M_PI / 2, 1e-9);

  auto location = vectorSensor(sensors::SensorType::kLocation);
  location.mount.position = {1.0, 0.0, 1.5};  // 1 m ahead of base_link: north of it
  const Eigen::Vector3d where = sensors::sampleVector(location, m, 9.81, &rng);
  EXPECT_NEAR(where.x(), 10.0, 1e-9);
  EXPECT_NEAR(where.y(), 6.0, 1e-9);
  EXPECT_NEAR(where.z(), 1.8, 1e-9);
  EXPECT_THROW(sensors::sampleVector(vectorSensor(sensors::SensorType::kImu), m, 9.81, &rng), std::invalid_argument);
}

TEST(VectorSensors, RollPitchYawOfARotationRoundTrips) {
  for (const Eigen::Vector3d& rpy : {Eigen::Vector3d(0.1, -0.2, 3.0), Eigen::Vector3d(-1.0, 0.5, -2.0)}) {
    const Eigen::Matrix3d r =
        (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    EXPECT_LT((sensors::rollPitchYaw(r) - rpy).norm(), 1e-12);
  }
}

TEST(VectorSensors, NoiseRepeatsForASeedAndHasItsSpread) {
  sensors::BodyMotion still;
  auto location = vectorSensor(sensors::SensorType::kLocation);
  location.vector.noise_std = 0.5;
  std::mt19937 a(7), b(7);
  double sum2 = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d ra = sensors::sampleVector(location, still, 9.81, &a);
    EXPECT_EQ(ra, sensors::sampleVector(location, still, 9.81, &b));
    sum2 += ra.squaredNorm();
  }
  EXPECT_NEAR(std::sqrt(sum2 / 6000), 0.5, 0.03);
}

TEST(Gnss, GeolocationOfAPointIsWhatGnssReadsThere) {
  track::GeoOrigin origin{37.9137, -122.3353, 10.0};
  sensors::BodyMotion m;
  m.pose.translation() = Eigen::Vector3d(120, -40, 2);
  std::mt19937 rng(1);
  const auto gnss = sensors::sampleGnss(m, {}, {}, origin, &rng);
  const auto geo = sensors::toGeodetic(Eigen::Vector3d(120, -40, 2), origin);
  EXPECT_EQ(gnss.latitude, geo.latitude);
  EXPECT_EQ(gnss.longitude, geo.longitude);
  EXPECT_EQ(gnss.altitude, geo.altitude);
  EXPECT_LT(geo.latitude, origin.latitude) << "south of the origin";
  EXPECT_GT(geo.longitude, origin.longitude) << "east of it";
}

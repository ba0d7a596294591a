#include "roar/sensors/inertial.h"

#include <GeographicLib/LocalCartesian.hpp>

#include <algorithm>
#include <stdexcept>

namespace roar::sensors {

namespace {

Eigen::Vector3d gaussian(double std, std::mt19937* rng) {
  if (std <= 0) return Eigen::Vector3d::Zero();
  std::normal_distribution<double> n(0.0, std);
  const double x = n(*rng), y = n(*rng), z = n(*rng);
  return {x, y, z};
}

// Velocity of a point fixed to the car at `offset` (map frame, from base_link).
Eigen::Vector3d pointVelocity(const BodyMotion& m, const Eigen::Vector3d& offset) {
  return m.linear_velocity + m.angular_velocity.cross(offset);
}

}  // namespace

Eigen::Isometry3d mountTransform(const Mount& mount) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = mount.position;
  t.linear() = (Eigen::AngleAxisd(mount.yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(mount.pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(mount.roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return t;
}

ImuSample sampleImu(const BodyMotion& m, const Mount& mount, const ImuSpec& spec, double gravity, std::mt19937* rng) {
  const Eigen::Isometry3d sensor = m.pose * mountTransform(mount);
  const Eigen::Matrix3d to_sensor = sensor.linear().transpose();
  const Eigen::Vector3d offset = sensor.translation() - m.pose.translation();
  // A point off the rotation axis also feels the centripetal acceleration (angular acceleration neglected).
  const Eigen::Vector3d accel = m.linear_acceleration + m.angular_velocity.cross(m.angular_velocity.cross(offset));
  const Eigen::Vector3d specific_force = accel + Eigen::Vector3d(0, 0, gravity);
  ImuSample s;
  s.orientation = Eigen::Quaterniond(sensor.linear());
  s.linear_acceleration = to_sensor * specific_force + spec.accel_bias + gaussian(spec.accel_noise_std, rng);
  s.angular_velocity = to_sensor * m.angular_velocity + spec.gyro_bias + gaussian(spec.gyro_noise_std, rng);
  return s;
}

GnssFix sampleGnss(const BodyMotion& m, const Mount& mount, const GnssSpec& spec, const track::GeoOrigin& origin,
                   std::mt19937* rng) {
  Eigen::Vector3d p = (m.pose * mountTransform(mount)).translation();
  if (spec.horizontal_noise_std > 0) {
    std::normal_distribution<double> n(0.0, spec.horizontal_noise_std);
    p.x() += n(*rng);
    p.y() += n(*rng);
  }
  if (spec.vertical_noise_std > 0) p.z() += std::normal_distribution<double>(0.0, spec.vertical_noise_std)(*rng);
  return toGeodetic(p, origin);
}

GnssFix toGeodetic(const Eigen::Vector3d& p, const track::GeoOrigin& origin) {
  // The map frame is east-north-up at the origin, as GeographicLib's local cartesian frame.
  const GeographicLib::LocalCartesian local(origin.latitude, origin.longitude, origin.altitude);
  GnssFix fix;
  local.Reverse(p.x(), p.y(), p.z(), fix.latitude, fix.longitude, fix.altitude);
  return fix;
}

Eigen::Vector3d rollPitchYaw(const Eigen::Matrix3d& r) {
  return {std::atan2(r(2, 1), r(2, 2)), std::asin(std::clamp(-r(2, 0), -1.0, 1.0)), std::atan2(r(1, 0), r(0, 0))};
}

Eigen::Vector3d sampleVector(const SensorSpec& spec, const BodyMotion& m, double gravity, std::mt19937* rng) {
  const Eigen::Isometry3d sensor = m.pose * mountTransform(spec.mount);
  const Eigen::Matrix3d to_sensor = sensor.linear().transpose();
  const VectorSpec& v = spec.vector;
  Eigen::Vector3d reading;
  switch (spec.type) {
    case SensorType::kAccelerometer: {
      const Eigen::Vector3d offset = sensor.translation() - m.pose.translation();
      Eigen::Vector3d a = m.linear_acceleration + m.angular_velocity.cross(m.angular_velocity.cross(offset));
      if (v.gravity) a.z() += gravity;
      reading = v.map_frame ? a : Eigen::Vector3d(to_sensor * a);
      break;
    }
    case SensorType::kGyroscope:
      reading = v.map_frame ? m.angular_velocity : Eigen::Vector3d(to_sensor * m.angular_velocity);
      break;
    case SensorType::kRollPitchYaw:
      reading = rollPitchYaw(sensor.linear());
      break;
    case SensorType::kLocation:
      reading = sensor.translation();
      break;
    default:
      throw std::invalid_argument(std::string("sampleVector: '") + typeName(spec.type) +
                                  "' is not a one-vector sensor");
  }
  reading += v.bias + gaussian(v.noise_std, rng);
  if (spec.type == SensorType::kRollPitchYaw) {
    for (int i = 0; i < 3; ++i) reading[i] = track::wrapAngle(reading[i]);
  }
  return reading;
}

Velocity sampleVelocity(const BodyMotion& m, const Mount& mount) {
  const Eigen::Isometry3d sensor = m.pose * mountTransform(mount);
  Velocity v;
  v.linear_world = pointVelocity(m, sensor.translation() - m.pose.translation());
  v.angular_world = m.angular_velocity;
  v.linear_body = sensor.linear().transpose() * v.linear_world;
  v.angular_body = sensor.linear().transpose() * v.angular_world;
  return v;
}

}  // namespace roar::sensors

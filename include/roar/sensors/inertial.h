#pragma once
// Sensors that read the car's motion: IMU, GNSS and velocimeter. Pure functions of the state, with
// their noise drawn from the caller's generator (seeded per sensor: the same seed, the same noise).
#include <Eigen/Geometry>
#include <random>

#include "roar/sensors/sensor_spec.h"
#include "roar/track/track.h"

namespace roar::sensors {

// Motion of the car's base_link, all in the map frame.
struct BodyMotion {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();     // base_link in map
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();  // of base_link
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();  // of base_link, gravity not included
};

Eigen::Isometry3d mountTransform(const Mount& mount);  // sensor frame in base_link

struct ImuSample {
  Eigen::Quaterniond orientation;       // sensor frame in map
  Eigen::Vector3d angular_velocity;     // rad/s, sensor frame
  Eigen::Vector3d linear_acceleration;  // m/s^2 specific force (reads +g upwards at rest), sensor frame
};
ImuSample sampleImu(const BodyMotion& motion, const Mount& mount, const ImuSpec& spec, double gravity,
                    std::mt19937* rng);

struct GnssFix {
  double latitude, longitude, altitude;  // degrees, degrees, metres
};
// A map position (east-north-up from the map's geodetic origin) as latitude, longitude and altitude
// (GeographicLib's local cartesian conversion): what GNSS reads and /roar_sim/get_geolocation answers.
GnssFix toGeodetic(const Eigen::Vector3d& map_position, const track::GeoOrigin& origin);

// The antenna's map position converted with toGeodetic.
GnssFix sampleGnss(const BodyMotion& motion, const Mount& mount, const GnssSpec& spec, const track::GeoOrigin& origin,
                   std::mt19937* rng);

struct Velocity {
  Eigen::Vector3d linear_body, angular_body;    // sensor frame
  Eigen::Vector3d linear_world, angular_world;  // map frame
};
Velocity sampleVelocity(const BodyMotion& motion, const Mount& mount);

// The reading of a one-vector sensor (spec.type kAccelerometer, kGyroscope, kRollPitchYaw or kLocation)
// mounted at spec.mount, with its bias and noise:
//   accelerometer  m/s^2: specific force (or, without gravity, the acceleration) of the mount point,
//                  in the sensor frame (or the map frame)
//   gyroscope      rad/s: angular velocity, in the sensor frame (or the map frame)
//   roll_pitch_yaw rad: the sensor frame's orientation in the map frame, each in [-pi, pi)
//   location       m: the sensor's position in the map frame
Eigen::Vector3d sampleVector(const SensorSpec& spec, const BodyMotion& motion, double gravity, std::mt19937* rng);

// Roll, pitch and yaw (rad, applied as yaw * pitch * roll) of a rotation.
Eigen::Vector3d rollPitchYaw(const Eigen::Matrix3d& rotation);

}  // namespace roar::sensors

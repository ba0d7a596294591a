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
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // base_link in map
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();       // of base_link
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();   // of base_link, gravity not included
};

Eigen::Isometry3d mountTransform(const Mount& mount);  // sensor frame in base_link

struct ImuSample {
  Eigen::Quaterniond orientation;           // sensor frame in map
  Eigen::Vector3d angular_velocity;         // rad/s, sensor frame
  Eigen::Vector3d linear_acceleration;      // m/s^2 specific force (reads +g upwards at rest), sensor frame
};
ImuSample sampleImu(const BodyMotion& motion, const Mount& mount, const ImuSpec& spec, double gravity,
                    std::mt19937* rng);

struct GnssFix {
  double latitude, longitude, altitude;  // degrees, degrees, metres
};
// The antenna's map position (ENU from the map's geodetic origin) converted with GeographicLib.
GnssFix sampleGnss(const BodyMotion& motion, const Mount& mount, const GnssSpec& spec, const track::GeoOrigin& origin,
                   std::mt19937* rng);

struct Velocity {
  Eigen::Vector3d linear_body, angular_body;    // sensor frame
  Eigen::Vector3d linear_world, angular_world;  // map frame
};
Velocity sampleVelocity(const BodyMotion& motion, const Mount& mount);

}  // namespace roar::sensors

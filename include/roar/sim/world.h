#pragma once
// The simulated world: a track's road, barriers and ground in Bullet, and vehicles driving on it.
// Time advances in fixed control ticks, each split into fixed physics substeps; the same inputs give the
// same trajectory bit for bit. Bullet stays behind this header (pimpl) to keep its headers out of users.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "roar/sim/world_options.h"
#include "roar/track/pose.h"
#include "roar/track/track.h"
#include "roar/vehicle/vehicle_control.h"
#include "roar/vehicle/vehicle_params.h"
#include "roar/vehicle/vehicle_state.h"

namespace roar::sim {

// How a car is put at a pose. kOnGround: at its x, y and yaw, set on the ground (z, roll and pitch from
// it). kAsGiven: at the whole pose (never below the ground), as CARLA spawns and teleports actors: a car
// above the road falls onto it (world_test SpawnedAsGivenAboveTheRoadFallsOntoIt).
enum class Placement { kOnGround, kAsGiven };

// A collision of a vehicle's body during the last tick, summed per other body: other cars and the barriers
// (the world's edge among them), not the road or the run-off the car drives on, as CARLA's collision sensor
// reports them (world_test TheRunOffCarriesAWheelOverTheEdgeWithoutACollision).
struct Contact {
  std::string other;                                   // vehicle name or "barrier"
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();   // N s on this vehicle, map frame
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // impulse-weighted contact point, map frame
};

class SpawnError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Where a world's clock starts: a world built to replace another (a map loaded at run time) goes on from
// the old one's tick and time, so simulated time never runs backwards.
struct WorldClock {
  std::uint64_t tick = 0;
  double time = 0.0;  // s
};

class World {
 public:
  // Throws std::invalid_argument for inconsistent options.
  World(const track::Track& track, const WorldOptions& options, const WorldClock& start = {});
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  const track::Track& track() const;
  const WorldOptions& options() const;

  // Places the car at rest at the pose (see Placement). Throws SpawnError with the reason: a taken name,
  // overlap with another car, no ground.
  void spawnVehicle(const std::string& name, const vehicle::VehicleParams& params, const track::Pose& pose,
                    Placement placement = Placement::kOnGround);
  void destroyVehicle(const std::string& name);  // throws SpawnError for an unknown name
  void resetVehicle(const std::string& name, const track::Pose& pose, Placement placement = Placement::kOnGround);
  // Sets base_link's velocities (m/s and rad/s, map frame), the wheels rolling with the road; throws
  // std::invalid_argument for velocities that are not finite or beyond 150 m/s and 20 rad/s.
  void setVehicleVelocity(const std::string& name, const Eigen::Vector3d& linear, const Eigen::Vector3d& angular);
  // Moves a moving car: base_link to (x, y) facing yaw at the speed (m/s), its height, roll and pitch kept,
  // its motion kept in its own frame (slip angle, yaw rate) and its wheels', steering's and drivetrain's
  // states kept: a logged path's replay holds the car on the log while its own state settles
  // (bench/carla_fidelity.py). Throws std::invalid_argument for values that are not finite or a speed
  // beyond 150 m/s.
  void moveVehicle(const std::string& name, const Eigen::Vector2d& position, double yaw, double speed);
  bool hasVehicle(const std::string& name) const;
  std::vector<std::string> vehicleNames() const;
  const vehicle::VehicleParams& vehicleParams(const std::string& name) const;

  // The control stays until replaced; it must have passed checkControl.
  void setControl(const std::string& name, const vehicle::VehicleControl& control);

  // One control tick. `after_substep`, when given, runs after every physics substep with the simulated
  // time at its end (vehicle states are current then): motion sensors sample at the physics rate.
  void step(const std::function<void(double)>& after_substep = {});
  std::uint64_t tick() const;
  // s: the start time plus the ticks since, each of the control_dt it was stepped with.
  double time() const;
  // New control and physics steps from the next tick on; throws std::invalid_argument, changing nothing,
  // when control_dt is not a whole multiple of physics_dt.
  void setTiming(double control_dt, double physics_dt);

  vehicle::VehicleState vehicleState(const std::string& name) const;
  const std::vector<Contact>& contacts(const std::string& name) const;  // during the last tick

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace roar::sim

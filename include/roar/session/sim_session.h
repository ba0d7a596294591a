#pragma once
// The simulator's session, ROS-free: the map in use (its track, physics world and ray scene, replaced
// together or not at all), the cars on it with what each was spawned with, and the ray scene's state kept
// tick by tick for frames rendered after their tick. roar_sim's SimNode wires ROS to it (topics, services,
// sensors' publishers, lockstep); sim_session_test drives it without ROS.
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "roar/sensors/ray_scene.h"
#include "roar/sim/world.h"
#include "roar/sim/world_options.h"
#include "roar/track/track.h"
#include "roar/vehicle/vehicle_control.h"
#include "roar/vehicle/vehicle_params.h"

namespace roar::session {

// Ticks of the ray scene's state kept for frames rendered after their tick: 10 s at 20 Hz.
inline constexpr std::size_t kKeptSceneTicks = 200;

// Every car's pose and velocities at one moment: what the ray scene is posed from.
struct SceneTick {
  struct Car {
    Eigen::Isometry3d pose;
    Eigen::Vector3d linear, angular;
  };
  double time = 0.0;
  std::map<std::string, Car> cars;
};

// What a car was spawned with, to spawn it again on another map.
struct SpawnRecord {
  std::string model;
  std::string sensor_set;
  Eigen::Vector3f colour{-1, -1, -1};  // negative: the next of the palette when spawned
  std::string agent;                   // the RL environment file of an agent that drives it ("": none)
  int spawn_point = -1;                // -1: spawned at a pose
};

struct SessionOptions {
  sim::WorldOptions world;
  std::string urdf_dir;            // the cars' URDFs (looks, geometry)
  std::string vehicle_config_dir;  // their YAML models
};

// A control as the session applied it: rejected (nothing changed) or applied, and what was wrong with it.
struct AppliedControl {
  bool applied = false;
  std::string problems;  // "": none
};

class SimSession {
 public:
  // Loads the map folder; throws what track::loadMapFolder throws for a broken one.
  SimSession(const SessionOptions& options, const std::string& map_folder);
  ~SimSession();

  // Replaces the map (every car gone) by another folder's, the clock running on from its tick and time.
  // Everything is built before anything is replaced: a broken folder throws and leaves the session as it was.
  // before_replacing runs once the new map is built, before the old one goes: what refers to the old track
  // lets go of it there.
  void loadMap(const std::string& folder, const std::function<void()>& before_replacing = {});
  const std::string& mapFolder() const { return map_folder_; }
  // How many times a map was loaded after the first (sim_session_test LoadingAMapCountsGenerations).
  std::uint32_t mapGeneration() const { return map_generation_; }

  const track::Track& track() const { return *track_; }
  sim::World& world() { return *world_; }
  const sim::World& world() const { return *world_; }
  sensors::RayScene& scene() { return *scene_; }

  // The pose of a grid slot; std::invalid_argument for one that does not exist.
  track::Pose spawnPose(int spawn_point) const;
  // A request's spawn point (>= 0), or for -1 its pose, which must be finite, within the track's elevation
  // and on the track or its run-off; std::invalid_argument saying why not.
  track::Pose requestedPose(int spawn_point, const track::Pose& pose) const;

  // The model a new car would have: its name checked (a plain ROS name, not yet taken) and its model read,
  // before anything is made. Throws sim::SpawnError, std::invalid_argument or the model's reader's error.
  vehicle::VehicleParams carToSpawn(const std::string& name, const std::string& model) const;
  // Puts a car checked by carToSpawn in the physics world and the ray scene; the last step that can refuse
  // (overlap, no ground), leaving nothing behind when it does. Returns its record, its colour chosen.
  const SpawnRecord& spawn(const std::string& name, const vehicle::VehicleParams& params, const track::Pose& pose,
                           SpawnRecord record, sim::Placement placement = sim::Placement::kOnGround);
  // sim::SpawnError for a car that does not exist.
  void remove(const std::string& name);
  bool has(const std::string& name) const { return cars_.count(name) > 0; }
  // Every car's record, by name (their names in order).
  std::map<std::string, SpawnRecord> records() const;
  const SpawnRecord& record(const std::string& name) const { return cars_.at(name).spawned; }
  int sceneId(const std::string& name) const { return cars_.at(name).scene_id; }

  // A driver's control, checked against the car's gearbox: a rejected one changes nothing.
  AppliedControl applyControl(const std::string& name, const vehicle::VehicleControl& control);
  // The same check alone (`applied`: whether applyControl would apply it), for requests checked whole first.
  AppliedControl checkControl(const std::string& name, const vehicle::VehicleControl& control) const;

  // Every car's pose and velocities now.
  SceneTick sceneNow() const;
  // Keeps this tick's scene state (the oldest beyond kKeptSceneTicks dropped) and, with pose_scene, poses the
  // ray scene at it (Embree's refit is most of a tick's cost when no ray is cast this tick).
  const SceneTick& keepTick(bool pose_scene);
  // The kept tick at a stamp, one that has the car when `vehicle` is not empty; std::invalid_argument saying
  // which ticks are kept.
  const SceneTick& keptTick(double stamp, const std::string& vehicle) const;
  // Poses the ray scene's cars where they were at a tick (cars spawned since: out of sight). A tick that is
  // not kept (sceneNow's) leaves the scene unposed as far as keepTick is concerned.
  void poseScene(const SceneTick& tick);
  std::size_t keptTicks() const { return scene_ticks_.size(); }

 private:
  struct Car {
    SpawnRecord spawned;
    int scene_id = -1;
  };
  vehicle::CheckedControl checked(const std::string& name, const vehicle::VehicleControl& control) const;
  // Poses the ray scene at a tick; `kept`: one of scene_ticks_, remembered as posed.
  void pose(const SceneTick& tick, bool kept);

  SessionOptions options_;
  std::string map_folder_;
  std::uint32_t map_generation_ = 0;
  std::unique_ptr<track::Track> track_;
  std::unique_ptr<sim::World> world_;
  std::unique_ptr<sensors::RayScene> scene_;
  std::map<std::string, sensors::VisualMesh> looks_;  // by vehicle model
  std::map<std::string, Car> cars_;
  std::size_t spawned_count_ = 0;  // for the palette
  std::deque<SceneTick> scene_ticks_;
  // The kept tick whose poses the ray scene has (nullptr: none kept).
  const SceneTick* scene_posed_at_ = nullptr;
};

}  // namespace roar::session

#include "roar/session/sim_session.h"

#include <algorithm>
#include <cmath>
#include <regex>
#include <stdexcept>

#include "roar/sensors/vehicle_looks.h"
#include "roar/sensors/vehicle_motion.h"
#include "roar/track/map_folder.h"
#include "roar/vehicle/vehicle_config.h"

namespace roar::session {

namespace {

// Paint of the n-th car: distinct, saturated colours (linear RGB).
Eigen::Vector3f paint(std::size_t n) {
  static const Eigen::Vector3f kPalette[] = {{0.05f, 0.15f, 0.75f}, {0.75f, 0.05f, 0.04f}, {0.9f, 0.6f, 0.02f},
                                             {0.05f, 0.5f, 0.1f},   {0.5f, 0.05f, 0.6f},   {0.02f, 0.55f, 0.6f},
                                             {0.85f, 0.85f, 0.85f}, {0.1f, 0.1f, 0.1f}};
  return kPalette[n % (sizeof(kPalette) / sizeof(kPalette[0]))];
}

// A car's name is its namespace and its tf prefix: a plain ROS name.
void checkCarName(const std::string& name) {
  static const std::regex valid("[A-Za-z][A-Za-z0-9_]{0,63}");
  if (!std::regex_match(name, valid)) {
    throw std::invalid_argument(
        "name '" + name + "' must start with a letter and hold only letters, digits and underscores (at most 64)");
  }
}

}  // namespace

SimSession::SimSession(const SessionOptions& options, const std::string& map_folder) : options_(options) {
  loadMap(map_folder);
  map_generation_ = 0;
}

SimSession::~SimSession() = default;

void SimSession::loadMap(const std::string& folder, const std::function<void()>& before_replacing) {
  auto track = std::make_unique<track::Track>(track::loadMapFolder(folder));
  sim::WorldClock clock;
  if (world_) clock = {world_->tick(), world_->time()};
  auto world = std::make_unique<sim::World>(*track, options_.world, clock);
  auto scene = std::make_unique<sensors::RayScene>(*track);
  if (before_replacing) before_replacing();
  cars_.clear();
  scene_ticks_.clear();
  scene_posed_at_ = nullptr;
  // The world refers to its track: it goes first.
  world_ = std::move(world);
  scene_ = std::move(scene);
  track_ = std::move(track);
  map_folder_ = folder;
  ++map_generation_;
}

track::Pose SimSession::spawnPose(int spawn_point) const {
  if (spawn_point < 0 || spawn_point >= track::kGridSlots) {
    throw std::invalid_argument("spawn_point " + std::to_string(spawn_point) + " does not exist (0.." +
                                std::to_string(track::kGridSlots - 1) + ")");
  }
  return track::poseOnTrack(track_->gridSpawnPoints(track::kGridSlots).at(static_cast<std::size_t>(spawn_point)));
}

track::Pose SimSession::requestedPose(int spawn_point, const track::Pose& pose) const {
  if (spawn_point >= track::kGridSlots || spawn_point < -1) {
    throw std::invalid_argument("spawn_point " + std::to_string(spawn_point) + " does not exist (-1 for pose, 0.." +
                                std::to_string(track::kGridSlots - 1) + ")");
  }
  if (spawn_point >= 0) return spawnPose(spawn_point);
  if (!pose.position.allFinite() || !pose.orientation.coeffs().allFinite()) {
    throw std::invalid_argument("pose must be finite");
  }
  // Its height picks the road where one runs over another; no road is further up or down than this.
  if (std::abs(pose.position.z()) > track::kMaxElevation) {
    throw std::invalid_argument("pose z = " + std::to_string(pose.position.z()) + " m is outside [" +
                                std::to_string(-track::kMaxElevation) + ", " + std::to_string(track::kMaxElevation) +
                                "]");
  }
  const std::string problem = track::offTrackProblem(*track_, pose.position.head<2>(), "pose");
  if (!problem.empty()) throw std::invalid_argument(problem);
  return pose;
}

vehicle::VehicleParams SimSession::carToSpawn(const std::string& name, const std::string& model) const {
  checkCarName(name);
  if (cars_.count(name)) throw sim::SpawnError("a vehicle named '" + name + "' already exists");
  return vehicle::loadVehicleModel(model, options_.urdf_dir, options_.vehicle_config_dir);
}

const SpawnRecord& SimSession::spawn(const std::string& name, const vehicle::VehicleParams& params,
                                     const track::Pose& pose, SpawnRecord record, sim::Placement placement) {
  if (cars_.count(name)) throw sim::SpawnError("a vehicle named '" + name + "' already exists");
  auto looks = looks_.find(params.model);
  if (looks == looks_.end())
    looks =
        looks_.emplace(params.model, sensors::readVehicleLooks(options_.urdf_dir + "/" + params.model + ".urdf")).first;
  world_->spawnVehicle(name, params, pose, placement);
  record.model = params.model;
  if ((record.colour.array() < 0).any()) record.colour = paint(spawned_count_);
  Car car;
  car.spawned = std::move(record);
  car.scene_id = scene_->addVehicle(looks->second, car.spawned.colour);
  ++spawned_count_;
  return cars_.emplace(name, std::move(car)).first->second.spawned;
}

void SimSession::remove(const std::string& name) {
  const auto it = cars_.find(name);
  if (it == cars_.end()) throw sim::SpawnError("no vehicle named '" + name + "'");
  world_->destroyVehicle(name);
  scene_->removeVehicle(it->second.scene_id);
  cars_.erase(it);
}

std::map<std::string, SpawnRecord> SimSession::records() const {
  std::map<std::string, SpawnRecord> out;
  for (const auto& [name, car] : cars_) out.emplace(name, car.spawned);
  return out;
}

vehicle::CheckedControl SimSession::checked(const std::string& name, const vehicle::VehicleControl& control) const {
  return vehicle::checkControl(control, static_cast<int>(world_->vehicleParams(name).gearbox.ratios.size()));
}

namespace {
AppliedControl outcomeOf(const vehicle::CheckedControl& checked) {
  AppliedControl out;
  for (const auto& p : checked.problems) out.problems += (out.problems.empty() ? "" : "; ") + p;
  out.applied = !checked.rejected;
  return out;
}
}  // namespace

AppliedControl SimSession::checkControl(const std::string& name, const vehicle::VehicleControl& control) const {
  return outcomeOf(checked(name, control));
}

AppliedControl SimSession::applyControl(const std::string& name, const vehicle::VehicleControl& control) {
  const vehicle::CheckedControl c = checked(name, control);
  if (!c.rejected) world_->setControl(name, c.control);
  return outcomeOf(c);
}

SceneTick SimSession::sceneNow() const {
  SceneTick now;
  now.time = world_->time();
  for (const auto& [name, car] : cars_) {
    const vehicle::VehicleState state = world_->vehicleState(name);
    now.cars[name] = {sensors::poseOf(state), state.linear_velocity, state.angular_velocity};
  }
  return now;
}

const SceneTick& SimSession::keepTick(bool pose_scene) {
  scene_ticks_.push_back(sceneNow());
  while (scene_ticks_.size() > kKeptSceneTicks) {
    if (scene_posed_at_ == &scene_ticks_.front()) scene_posed_at_ = nullptr;
    scene_ticks_.pop_front();
  }
  if (pose_scene) pose(scene_ticks_.back(), true);
  return scene_ticks_.back();
}

const SceneTick& SimSession::keptTick(double stamp, const std::string& vehicle) const {
  const auto tick = std::find_if(scene_ticks_.begin(), scene_ticks_.end(),
                                 [&](const SceneTick& t) { return std::abs(t.time - stamp) < 1e-6; });
  if (tick != scene_ticks_.end() && (vehicle.empty() || tick->cars.count(vehicle))) return *tick;
  throw std::invalid_argument("no frame of t = " + std::to_string(stamp) + " s is kept" +
                              (scene_ticks_.empty()
                                   ? std::string(" (no tick since the car's sensors came)")
                                   : " (the last " + std::to_string(scene_ticks_.size()) +
                                         " ticks are: t = " + std::to_string(scene_ticks_.front().time) + " to " +
                                         std::to_string(scene_ticks_.back().time) + " s)"));
}

void SimSession::poseScene(const SceneTick& tick) {
  if (&tick == scene_posed_at_) return;
  pose(tick, std::any_of(scene_ticks_.begin(), scene_ticks_.end(), [&](const SceneTick& t) { return &t == &tick; }));
}

void SimSession::pose(const SceneTick& tick, bool kept) {
  for (const auto& [name, car] : cars_) {
    const auto at = tick.cars.find(name);
    if (at == tick.cars.end()) {
      scene_->setVehiclePose(car.scene_id, Eigen::Isometry3d(Eigen::Translation3d(0, 0, -1e5)));
      continue;
    }
    scene_->setVehiclePose(car.scene_id, at->second.pose);
    scene_->setVehicleVelocity(car.scene_id, at->second.linear, at->second.angular);
  }
  scene_->commit();
  scene_posed_at_ = kept ? &tick : nullptr;
}

}  // namespace roar::session

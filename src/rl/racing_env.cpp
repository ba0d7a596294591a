#include "roar/rl/racing_env.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "roar/rl/action.h"
#include "roar/sensors/ray_scene.h"
#include "roar/sim/world.h"
#include "roar/track/heading.h"

namespace roar::rl {

namespace {

EnvOptions checked(EnvOptions options) {
  validate(options);
  return options;
}

}  // namespace

RacingEnv::RacingEnv(const track::Track& track, const vehicle::VehicleParams& vehicle, const EnvOptions& options)
    : track_(track),
      vehicle_(vehicle),
      options_(checked(options)),
      action_space_(rl::actionSpace(options_.action, static_cast<int>(vehicle.gearbox.ratios.size()))),
      world_(std::make_unique<sim::World>(track_, options_.world)),
      observer_(track_, options_.observation, options_.world.gravity),
      episode_(track_, options_.reward, options_.termination) {
  if (observer_.needsScene()) scene_ = std::make_unique<sensors::RayScene>(track_);
  world_->spawnVehicle(kCar, vehicle_, track::poseOnTrack(track_.gridSpawnPoints(1).front()));
}

RacingEnv::~RacingEnv() = default;

const Space& RacingEnv::observationSpace() const { return observer_.space(); }
const sim::World& RacingEnv::world() const { return *world_; }

track::Pose drawSpawnPose(const track::Track& track, const EnvOptions& options, std::mt19937_64& rng) {
  if (options.spawn == SpawnMode::kGrid) return track::poseOnTrack(track.gridSpawnPoints(1).front());
  // A course's road past its finish line is where cars stop, not where they race.
  const double spawn_to = track.closed() ? track.length() : track.finishLine();
  track::TrackPose at = track.poseAt(std::uniform_real_distribution<double>(0.0, spawn_to)(rng));
  if (options.spawn_lateral > 0.0) {
    // Keep the car's half width and a little more on the road.
    const double room_left = std::max(0.0, at.width_left - 1.5), room_right = std::max(0.0, at.width_right - 1.5);
    const double offset = std::clamp(std::uniform_real_distribution<double>(-1.0, 1.0)(rng) * options.spawn_lateral,
                                     -room_right, room_left);
    at.position += offset * track::leftOf(at.heading);
  }
  return track::poseOnTrack(at);
}

void RacingEnv::observeInto(Value* obs) {
  observer_.observeInto(world_->vehicleState(kCar), episode_.where(), scene_.get(), -1, obs);
}

ResetResult RacingEnv::reset(std::uint64_t seed) {
  rng_.seed(seed);
  return reset();
}

ResetResult RacingEnv::reset() {
  world_->resetVehicle(kCar, drawSpawnPose(track_, options_, rng_));
  for (int i = 0; i < settleTicks(options_); ++i) {
    world_->setControl(kCar, vehicle::parkedControl());
    world_->step();
  }
  started_ = true;
  ResetResult r;
  r.info = episode_.begin(world_->vehicleState(kCar), world_->time());
  observeInto(&r.observation);
  return r;
}

StepResult RacingEnv::step(const Value& action) {
  StepResult r;
  step(action, &r);
  return r;
}

void RacingEnv::step(const Value& action, StepResult* out) {
  if (!started_) throw std::logic_error("RacingEnv::step before the first reset");
  const vehicle::VehicleControl control = toControl(action_space_, action);
  const int gears = static_cast<int>(vehicle_.gearbox.ratios.size());
  world_->setControl(kCar, vehicle::checkControl(control, gears).control);
  world_->step();
  const StepOutcome outcome = episode_.step(world_->vehicleState(kCar), world_->contacts(kCar), world_->time());
  out->reward = outcome.reward;
  out->terminated = outcome.terminated;
  out->truncated = outcome.truncated;
  out->info = outcome.info;
  observeInto(&out->observation);
}

}  // namespace roar::rl

#pragma once
// A Gymnasium-style environment of one car on a circuit: reset(seed) and step(action) return the
// observation, the reward, terminated, truncated and what happened (StepInfo), with ROAR_PY's action spec
// and the observations, reward and termination of EnvOptions. Deterministic: the same seed and actions
// give the same episode bit for bit. Not thread-safe; one environment per thread (VectorEnv does that).
#include <cstdint>
#include <memory>
#include <random>

#include "roar/rl/env_options.h"
#include "roar/rl/episode.h"
#include "roar/rl/observation.h"
#include "roar/rl/space.h"
#include "roar/track/track.h"
#include "roar/vehicle/vehicle_params.h"

namespace roar::rl {

struct ResetResult {
  Value observation;
  StepInfo info;
};

struct StepResult {
  Value observation;
  double reward = 0.0;
  bool terminated = false;
  bool truncated = false;
  StepInfo info;
  bool done() const { return terminated || truncated; }
};

// Where a new episode starts: the pole position (SpawnMode::kGrid) or anywhere round the lap drawn from
// `rng` (up to spawn_lateral either side of the centre line, the car kept on the road), facing the way of
// the track.
track::Pose drawSpawnPose(const track::Track& track, const EnvOptions& options, std::mt19937_64& rng);

class RacingEnv {
 public:
  // Throws EnvConfigError for options that cannot work.
  RacingEnv(const track::Track& track, const vehicle::VehicleParams& vehicle, const EnvOptions& options);
  ~RacingEnv();
  RacingEnv(const RacingEnv&) = delete;
  RacingEnv& operator=(const RacingEnv&) = delete;

  const Space& actionSpace() const { return action_space_; }
  const Space& observationSpace() const;
  const EnvOptions& options() const { return options_; }

  // A new episode: the car at rest on a spawn point (random ones drawn from the seed), settled for
  // settle_time, then observed. reset() without a seed draws from where the last episode's generator left off.
  ResetResult reset(std::uint64_t seed);
  ResetResult reset();
  // Throws SpaceError naming the key for an action outside the action space (nothing is stepped then),
  // std::logic_error before the first reset.
  StepResult step(const Value& action);
  // The same into `out`, reusing the memory of the observation it holds (from an earlier step or reset).
  void step(const Value& action, StepResult* out);

  const sim::World& world() const;
  static constexpr const char* kCar = "agent";

 private:
  void observeInto(Value* obs);

  track::Track track_;
  vehicle::VehicleParams vehicle_;
  EnvOptions options_;
  Space action_space_;
  std::unique_ptr<sim::World> world_;
  std::unique_ptr<sensors::RayScene> scene_;  // only when camera or LiDAR are observed
  ObservationBuilder observer_;
  Episode episode_;
  std::mt19937_64 rng_;
  bool started_ = false;
};

}  // namespace roar::rl

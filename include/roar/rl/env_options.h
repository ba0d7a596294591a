#pragma once
// Everything that makes a racing environment what it is, bar the track and the car: observations,
// actions, reward, termination, spawning and time steps. Read from config/rl/<name>.yaml:
//
//   control_dt: 0.05          # s per step
//   physics_dt: 0.005         # s per physics substep
//   spawn: random             # random (anywhere round the lap) or grid (pole position)
//   spawn_lateral: 0.0        # m: a random spawn lies up to this far either side of the centre line
//   settle_time: 0.3          # s the car rests after a reset before its first observation
//   action: {manual_gears: false}
//   observation: {speed: true, velocity: true, angular_velocity: true, imu: false,
//                 waypoint_distances: [5, 10, 20, 40, 60, 80],
//                 lidar: {beams: 0, max_range: 50, fov: 180, height: 0.6},
//                 camera: {width: 0, height: 0, fov: 90, rgb: true, depth: false, max_depth: 100}}
//   reward: {progress_weight: 20, centre_weight: 0.2, backwards_weight: 20, step_penalty: 0,
//            collision_penalty_scale: 1, collision_penalty_cap: 100, off_track_penalty: 10}
//   termination: {collision_threshold: 30, off_track_margin: 1.0, time_limit: 120, stall_time: 10,
//                 max_backwards: 50}
//
// Every key is optional (the defaults above); an unknown key or a bad value is an error naming the file
// and the key.
#include <stdexcept>
#include <string>

#include "roar/rl/action.h"
#include "roar/rl/episode_options.h"
#include "roar/rl/observation_options.h"
#include "roar/sim/world_options.h"

namespace roar::rl {

enum class SpawnMode { kRandom, kGrid };

struct EnvOptions {
  ObservationOptions observation;
  ActionOptions action;
  RewardOptions reward;
  TerminationOptions termination;
  SpawnMode spawn = SpawnMode::kRandom;
  double spawn_lateral = 0.0;  // m
  double settle_time = 0.3;    // s
  sim::WorldOptions world;     // control_dt and physics_dt
};

class EnvConfigError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Throws EnvConfigError naming the option that cannot work.
void validate(const EnvOptions& options);
// Control steps in settle_time.
int settleTicks(const EnvOptions& options);
EnvOptions readEnvOptions(const std::string& path);
EnvOptions parseEnvOptions(const std::string& yaml_text, const std::string& source);
// The observation part alone (a policy file carries the observation it was trained with).
ObservationOptions parseObservationOptions(const std::string& yaml_text, const std::string& source);
std::string toYaml(const ObservationOptions& options);

}  // namespace roar::rl

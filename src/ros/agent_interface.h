#pragma once
// A car that an RL agent drives through roar_sim, the ROAR_PY loop over ROS: the action and observation
// spaces latched on /<vehicle>/rl/action_space and /<vehicle>/rl/observation_space, and after every tick
// the observation (/<vehicle>/rl/observation) and the step's reward and done flags (/<vehicle>/rl/step),
// both stamped with the tick's time. Episodes are judged by the RL core's Episode, as rl::RacingEnv judges
// them; the agent acts through /roar_sim/step's controls (or /<vehicle>/control) and starts episodes
// through /roar_sim/reset_episode (SimNode runs the reset: spawn, settle ticks, begin()).
#include <ros/ros.h>

#include <random>
#include <string>
#include <vector>

#include "roar/rl/env_options.h"
#include "roar/rl/episode.h"
#include "roar/rl/observation.h"
#include "roar_ros/Observation.h"

namespace roar::sensors {
class RayScene;
}

namespace roar::ros_bridge {

class AgentInterface {
 public:
  AgentInterface(ros::NodeHandle& nh, const std::string& vehicle, const track::Track& track,
                 const rl::EnvOptions& options, int forward_gears);

  const rl::EnvOptions& options() const { return options_; }
  bool needsScene() const { return observer_.needsScene(); }
  // The next episode's spawn pose; seed < 0 goes on with the last episode's generator.
  track::Pose nextSpawn(std::int64_t seed);
  // Until begin(), ticks are not judged (the car is being settled).
  void pause() { active_ = false; }
  // The episode starts with the car in `state` at `time`: publishes and returns its first observation.
  roar_ros::Observation begin(const vehicle::VehicleState& state, double time, const sensors::RayScene* scene, int own);
  // After a tick: judges it and publishes the observation and the step. Once the episode is over, the
  // steps keep its done flags with no reward until the next begin() (and say so, throttled).
  void afterTick(const vehicle::VehicleState& state, const std::vector<sim::Contact>& contacts, double time,
                 const sensors::RayScene* scene, int own);

 private:
  std::string vehicle_;
  const track::Track* track_;
  rl::EnvOptions options_;
  rl::ObservationBuilder observer_;
  rl::Episode episode_;
  std::mt19937_64 rng_;
  ros::Publisher action_space_, observation_space_, observation_, step_;
  bool active_ = false;
  bool over_ = false;
  rl::StepOutcome last_;
};

}  // namespace roar::ros_bridge

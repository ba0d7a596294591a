#include "agent_interface.h"

#include "roar/rl/action.h"
#include "roar/rl/racing_env.h"
#include "roar/ros/msg_conversion.h"
#include "roar/ros/queues.h"
#include "roar/ros/rl_msg_conversion.h"
#include "roar/ros/wall_throttle.h"

namespace roar::ros_bridge {

AgentInterface::AgentInterface(ros::NodeHandle& nh, const std::string& vehicle, const track::Track& track,
                               const rl::EnvOptions& options, int forward_gears)
    : vehicle_(vehicle),
      track_(&track),
      options_(options),
      observer_(track, options.observation, options.world.gravity),
      episode_(track, options.reward, options.termination) {
  action_space_ = nh.advertise<roar_ros::SpaceDescription>(vehicle + "/rl/action_space", 1, true);
  observation_space_ = nh.advertise<roar_ros::SpaceDescription>(vehicle + "/rl/observation_space", 1, true);
  observation_ = nh.advertise<roar_ros::Observation>(vehicle + "/rl/observation", kPerTickQueue);
  step_ = nh.advertise<roar_ros::EpisodeStep>(vehicle + "/rl/step", kPerTickQueue);
  action_space_.publish(toMessage(rl::actionSpace(options.action, forward_gears)));
  observation_space_.publish(toMessage(observer_.space()));
}

track::Pose AgentInterface::nextSpawn(std::int64_t seed) {
  if (seed >= 0) rng_.seed(static_cast<std::uint64_t>(seed));
  return rl::drawSpawnPose(*track_, options_, rng_);
}

roar_ros::Observation AgentInterface::begin(const vehicle::VehicleState& state, double time,
                                            const sensors::RayScene* scene, int own) {
  episode_.begin(state, time);
  active_ = true;
  over_ = false;
  const roar_ros::Observation msg =
      toObservation(observer_.space(), observer_.observe(state, episode_.where(), scene, own), toRosTime(time));
  observation_.publish(msg);
  return msg;
}

void AgentInterface::afterTick(const vehicle::VehicleState& state, const std::vector<sim::Contact>& contacts,
                               double time, const sensors::RayScene* scene, int own) {
  if (!active_) return;
  const ros::Time stamp = toRosTime(time);
  if (over_) {
    ROAR_WARN_WALL_THROTTLE(5.0, "roar_sim: the episode of '%s' is over; call /roar_sim/reset_episode",
                            vehicle_.c_str());
    last_.reward = 0.0;
  } else {
    last_ = episode_.step(state, contacts, time);
    over_ = last_.terminated || last_.truncated;
  }
  observation_.publish(toObservation(observer_.space(), observer_.observe(state, episode_.where(), scene, own), stamp));
  step_.publish(toEpisodeStep(last_, stamp));
}

}  // namespace roar::ros_bridge

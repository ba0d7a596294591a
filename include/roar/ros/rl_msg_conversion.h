#pragma once
// Conversions between the RL core's spaces, observations and step outcomes and roar_ros messages.
#include <roar_ros/EpisodeStep.h>
#include <roar_ros/Observation.h>
#include <roar_ros/SpaceDescription.h>
#include <ros/time.h>

#include "roar/rl/episode.h"
#include "roar/rl/space.h"

namespace roar::ros_bridge {

roar_ros::SpaceDescription toMessage(const rl::Space& space);
// The observation's leaves in the space's order.
roar_ros::Observation toObservation(const rl::Space& space, const rl::Value& observation, const ros::Time& stamp);
// Throws rl::SpaceError naming the key that is missing or has the wrong number of elements.
rl::Value fromMessage(const rl::Space& space, const roar_ros::Observation& msg);
roar_ros::EpisodeStep toEpisodeStep(const rl::StepOutcome& outcome, const ros::Time& stamp);

}  // namespace roar::ros_bridge

#pragma once
// A pose in the map frame, and the pose a car stands at on the track: shared by the simulator, the stack's
// programs and the tools, none of which needs the other to say where a car is.
#include <Eigen/Geometry>

#include "roar/track/track.h"

namespace roar::track {

struct Pose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

// A spawn pose on the track surface at a track pose (heading along the driving direction).
Pose poseOnTrack(const TrackPose& track_pose);

// Heading (rad, about z, from x towards y) of an orientation.
double yawOf(const Eigen::Quaterniond& q);

}  // namespace roar::track

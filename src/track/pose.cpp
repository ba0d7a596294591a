#include "roar/track/pose.h"

#include <cmath>

namespace roar::track {

double yawOf(const Eigen::Quaterniond& q) {
  return std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()), 1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
}

Pose poseOnTrack(const TrackPose& track_pose) {
  Pose pose;
  pose.position = Eigen::Vector3d(track_pose.position.x(), track_pose.position.y(), track_pose.height);
  pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(track_pose.heading, Eigen::Vector3d::UnitZ()));
  return pose;
}

}  // namespace roar::track

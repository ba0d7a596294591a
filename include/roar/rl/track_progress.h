#pragma once
// Where a car is along the track, followed from one step to the next (ROAR_PY's waypoint tracer): each
// projection searches only near the last one, so a car where the circuit passes close to itself stays on
// its own part of it, and the distance it advanced is measured along the centre line.
#include <Eigen/Core>

#include "roar/track/track.h"

namespace roar::rl {

class TrackProgress {
 public:
  explicit TrackProgress(const track::Track& track) : track_(&track) {}

  // Starts following a car at `position` (map frame, z the height: a search of the whole track at its
  // height, so under a bridge the road below).
  void reset(const Eigen::Vector3d& position);
  // Follows the car to `position`; returns the metres it advanced along the centre line since the last
  // update (negative when it went backwards).
  double update(const Eigen::Vector2d& position);
  const track::Projection& projection() const { return projection_; }

 private:
  const track::Track* track_;
  track::Projection projection_;
};

}  // namespace roar::rl

#include "roar/rl/track_progress.h"

namespace roar::rl {

namespace {
// Metres either side of the last projection searched: far more than a car drives in one step.
constexpr double kSearchWindow = 30.0;
}  // namespace

void TrackProgress::reset(const Eigen::Vector3d& position) { projection_ = track_->projectAtHeight(position); }

double TrackProgress::update(const Eigen::Vector2d& position) {
  const double before = projection_.s;
  projection_ = track_->projectNear(position, before, kSearchWindow);
  double advanced = projection_.s - before;
  if (!track_->closed()) return advanced;
  // Across the start of the centre line the progress wraps.
  if (advanced > 0.5 * track_->length()) advanced -= track_->length();
  if (advanced < -0.5 * track_->length()) advanced += track_->length();
  return advanced;
}

}  // namespace roar::rl

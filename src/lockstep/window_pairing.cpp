#include "roar/lockstep/window_pairing.h"

#include <algorithm>

namespace roar::lockstep {

void WindowPairing::hold(double stamp, double wall) {
  holding_ = true;
  held_stamp_ = stamp;
  held_since_ = wall;
}

bool WindowPairing::onOdometry(double stamp, double wall) {
  newest_odometry_ = odometry_seen_ ? std::max(newest_odometry_, stamp) : stamp;
  odometry_seen_ = true;
  // A window planned from this very odometry came before it (the planner's answer was quicker than this
  // odometry's way here): the planner answers odometry (lockstep_test
  // EveryControlIsDrivenWithTheWindowOfItsOwnTickWhateverTheDelays).
  if (has_window_ && window_stamp_ > 0.0 && window_stamp_ >= stamp && !given_up_) planner_answers_ = true;
  if (!has_window_ || (window_wait_ > 0 && planner_answers_ && window_stamp_ < stamp)) {
    hold(stamp, wall);
    return false;
  }
  holding_ = false;
  return true;
}

bool WindowPairing::onWindow(double stamp) {
  const bool first = !has_window_;
  const bool fresh = has_window_ && stamp > window_stamp_;
  has_window_ = true;
  window_stamp_ = stamp;
  // A window stamped with the odometry's time (not older than the newest: one lagging behind says nothing
  // new) shows a planner that answers odometry; an unstamped one on a running clock, one that does not. A
  // planner given up on that plans again from newer odometry is waited for again even while it lags: held,
  // the simulator waits and the planner catches up, so the race is in lockstep again
  // (WindowPairing.ARestartedPlannerLaggingBehindIsWaitedForAgain).
  if (!odometry_seen_ || (stamp == 0.0 && newest_odometry_ != 0.0)) {
    planner_answers_ = false;
  } else if (stamp >= newest_odometry_ || (given_up_ && fresh)) {
    planner_answers_ = true;
    given_up_ = false;
  }
  return holding_ && (first || window_stamp_ >= held_stamp_);
}

bool WindowPairing::waitedTooLong(double wall) const {
  return holding_ && has_window_ && wall - held_since_ >= window_wait_;
}

}  // namespace roar::lockstep

#pragma once
// Which trajectory window a controller answers an odometry tick with. While the planner answers odometry
// (its windows carry the stamp of the odometry they were planned from), tick t is answered with the
// window of tick t: the odometry is held until that window comes, or until it has waited `window_wait`
// seconds of wall time (then the latest window does). A planner whose windows are unstamped, or that
// has not yet answered a tick, is not waited for; one given up on (a window missed its wait) is waited
// for again once it plans from newer odometry, so that a restarted planner brings the race back into
// lockstep however far behind it starts. Without any window, odometry is held until the first.
// Times in seconds: stamps are simulated time, `wall` is wall time. ROS-free: the controller node feeds
// it and does what it says.
namespace roar::lockstep {

class WindowPairing {
 public:
  explicit WindowPairing(double window_wait) : window_wait_(window_wait) {}

  // Odometry of simulated time `stamp` arrived. Returns true to answer it now; false: it is held (it
  // replaces any odometry held before, which the simulator went on without).
  bool onOdometry(double stamp, double wall);
  // A window stamped `stamp` (0: unstamped) was taken. Returns true when the held odometry is to be
  // answered now (the first window, or the one planned for it).
  bool onWindow(double stamp);
  // Whether odometry is held and has waited `window_wait` for its window (answer it with the latest).
  bool waitedTooLong(double wall) const;
  // The held odometry was answered with the latest window after waiting window_wait: the planner is no
  // longer waited for until it answers a tick again (a dead planner costs one wait, not one a tick).
  void answeredLate() {
    holding_ = false;
    planner_answers_ = false;
    given_up_ = true;
  }
  // The held odometry was answered (or dropped).
  void answered() { holding_ = false; }
  // Whether the latest window is older than odometry of `stamp` by more than `stale_after` simulated seconds
  // (the planner has stopped: the caller follows the whole racing line instead). Unstamped windows never are.
  bool windowStale(double stamp, double stale_after) const {
    return has_window_ && window_stamp_ > 0.0 && stamp - window_stamp_ > stale_after;
  }

  bool holding() const { return holding_; }
  double heldStamp() const { return held_stamp_; }
  double windowStamp() const { return window_stamp_; }
  bool hasWindow() const { return has_window_; }
  // Whether the planner is taken to answer odometry (and so a tick waits for its window).
  bool plannerAnswersOdometry() const { return planner_answers_; }

 private:
  void hold(double stamp, double wall);

  double window_wait_;
  bool has_window_ = false;
  double window_stamp_ = 0.0;
  bool odometry_seen_ = false;
  double newest_odometry_ = 0.0;
  bool planner_answers_ = false;
  bool given_up_ = false;  // answered late: a fresh stamped window makes the planner answering again
  bool holding_ = false;
  double held_stamp_ = 0.0;
  double held_since_ = 0.0;
};

}  // namespace roar::lockstep

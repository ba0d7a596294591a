#pragma once
// Which cars' odometry the planner node plans a tick from. Every car's window of tick t is planned from
// every car's place at t, as harness::runRace plans (locate them all, then plan each in the race's order):
// planned as each message came, a car's window saw the others at t or t - 1 by which message the node
// happened to take first, and two lockstep runs of one race differed (lap times by up to 23 ms). A tick is
// planned once every car expected has sent its odometry of it, once a later tick begins (a car that
// missed it is planned from where it last was), or once it has waited `wait` seconds of wall time; a car
// that missed a tick so is not waited for again until its odometry comes back (a car removed from the
// world never stalls the others). ROS-free: the node feeds it and plans what it says. Times in seconds:
// stamps are simulated time, `wall` is wall time.
#include <string>
#include <vector>

namespace roar::lockstep {

class TickGathering {
 public:
  // The cars planned for, in the order their windows are planned.
  TickGathering(std::vector<std::string> cars, double wait);

  // A tick to plan: its stamp and the cars whose odometry of it came, in the race's order.
  struct Tick {
    double stamp = 0.0;
    std::vector<std::string> cars;
  };
  // `car`'s odometry stamped `stamp` came. Returns the ticks to plan now, oldest first: the tick before,
  // when this one begins a later tick, and this one, when every car expected has come. Odometry older
  // than the tick gathered (late, out of order) is planned at once, alone. A car not of the race: none.
  std::vector<Tick> arrive(const std::string& car, double stamp, double wall);
  // The tick gathered, if it has waited `wait` since its first odometry (plan it, without the cars
  // missing from it); none otherwise.
  std::vector<Tick> expire(double wall);
  // Wall time at which the tick gathered expires; negative when none is gathered.
  double expiresAt() const { return gathering_ ? first_wall_ + wait_ : -1.0; }

 private:
  Tick take();

  std::vector<std::string> cars_;
  double wait_;
  std::vector<char> absent_;   // per car: missed a tick, not waited for until it comes again
  std::vector<char> arrived_;  // per car: in the tick gathered
  bool gathering_ = false;
  double stamp_ = 0.0;
  double first_wall_ = 0.0;
};

}  // namespace roar::lockstep

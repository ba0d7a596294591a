#pragma once
// The drivers a lockstep tick of the simulator waits for. Each car's driver publishes its control stamped
// with the simulated time of the odometry it answers; the tick after time t goes out once every driver
// that is connected and not lost has answered t, or once the simulator's wait (lockstep_timeout, wall
// time) has run out: the drivers that had not answered are then lost, and not waited for until a control
// of theirs comes again. A driver that drove and whose publisher is gone (a killed driver) is lost at once.
// A car nobody drives (no publisher, never a control) is not waited for. With every driver lost there is
// nobody to race, and the simulator paces time to the wall clock. The rest of the protocol: the planner's
// TickGathering, the controller's WindowPairing, the recorders' RecorderPacing (lockstep_test states it
// whole). ROS-free: stamps are simulated seconds, each as its message's stamp converts to seconds.
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace roar::lockstep {

class DriverRoll {
 public:
  // Whether a car's control topic has a publisher now (the caller's ROS graph).
  using Connected = std::function<bool(const std::string& car)>;
  explicit DriverRoll(Connected connected) : connected_(std::move(connected)) {}

  void add(const std::string& car);  // a car spawned: its driver not seen yet
  void remove(const std::string& car);
  void clear() { drivers_.clear(); }
  // A control stamped `stamp` from the car's driver was applied. Returns true when the driver had been lost
  // and is back (the roll waits for it again).
  bool control(const std::string& car, double stamp);
  // Whether every driver waited for has answered the odometry of simulated time `now`.
  bool answered(double now) const;
  // The drivers waited for that have not answered `now`, in the order of their cars' names.
  std::vector<std::string> silent(double now) const;
  // The drivers that drove, are not lost and have no publisher now, in the order of their cars' names.
  std::vector<std::string> disconnected() const;
  void lose(const std::string& car);
  bool lost(const std::string& car) const;
  // Some driver is lost and none that is connected is not.
  bool everyDriverLost() const;

 private:
  struct Driver {
    bool seen = false;   // a control has come
    double stamp = 0.0;  // the last one's
    bool lost = false;
  };
  // Waited for (connected, not lost) and without its answer to `now` yet.
  bool owes(const std::string& car, const Driver& d, double now) const {
    return !d.lost && connected_(car) && (!d.seen || d.stamp < now);
  }

  Connected connected_;
  std::map<std::string, Driver> drivers_;
};

}  // namespace roar::lockstep

#pragma once
// The planner's view of a field of cars: where each is on the racing line, and the window ahead each one
// is to drive. Either every car follows the car ahead on the line (a procession), or, with overtaking on,
// the OvertakePlanner chooses between the line, following and passing. The planner node and the
// in-process race (stack/race.h) both plan through this class, so the choice of the car to follow lives
// in one place that gtest reaches.
#include <Eigen/Core>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "roar/planning/held_speed.h"
#include "roar/planning/overtaking/planner.h"
#include "roar/planning/trajectory.h"
#include "roar/planning/vehicle_limits.h"
#include "roar/track/track.h"

namespace roar::planning {

struct FieldOptions {
  // m of the line each window covers ahead of the car: at least the 6 s the overtaking planner compares
  // candidates over at the speeds of a straight (250 m: every candidate there reached the window's end, and a
  // pass on a straight could show no gain; doc/traffic_history.md).
  double window_ahead = 400.0;
  double window_behind = 10.0;  // m behind it
  double follow_lateral = 3.5;  // m: without overtaking, a car this close to the line is in the way
  bool overtaking = true;       // true: pass slower cars (OvertakePlanner); false: follow them
  OvertakeOptions overtake;     // its follow_gap is kept behind a car ahead, overtaking or not
};

class FieldPlanner {
 public:
  // line: the closed racing trajectory of `track`, planned with `limits`.
  FieldPlanner(const track::Track& track, Trajectory line, const VehicleLimits& limits, FieldOptions options);

  // Where `car` is at `time` (s): base_link's position (map frame, z the height) and its forward speed
  // (m/s). A car first seen is searched for on the whole line at its height (under a bridge, the branch
  // below), then near its last place. `velocity` (m/s, map frame), where the caller has it: the car's
  // motion across the line this moment (a door closing on a pass), before its places show it.
  void locate(const std::string& car, const Eigen::Vector3d& position, double speed, double time,
              const std::optional<Eigen::Vector2d>& velocity = std::nullopt);
  bool located(const std::string& car) const { return cars_.count(car) > 0; }
  // The share of the line's speeds the car is planned at (0 < pace <= 1; 1: the line's own).
  // Throws std::invalid_argument outside (0, 1].
  void setPace(const std::string& car, double pace);

  // The window ahead of a located car (std::out_of_range for a car never located), given every other
  // located car where it was last located.
  Trajectory window(const std::string& car);
  // What the last window for `car` chose (kRacingLine or kFollow without overtaking).
  RaceDecision decision(const std::string& car) const;
  // What the last window for `car` predicted of the cars near it (none without overtaking).
  std::vector<PredictedPath> predictions(const std::string& car) const;
  // Where the car was last located on the line.
  const TrajectoryProjection& onLine(const std::string& car) const { return cars_.at(car).on_line; }

  const Trajectory& line() const { return line_; }
  const FieldOptions& options() const { return options_; }

 private:
  struct Place {
    long hint = -1;
    TrajectoryProjection on_line;
    double speed = 0.0;
    double line_share = 0.0;  // its speed over the line's, smoothed (OvertakePlanner's prediction)
    double time = std::numeric_limits<double>::quiet_NaN();              // s of the last position
    double lateral_speed = 0.0;                                          // m/s leftwards across the line, smoothed
    double lateral_velocity = std::numeric_limits<double>::quiet_NaN();  // m/s, its velocity's; NaN: unknown
    double progress = 0.0;  // m round the laps since it was first seen (from the first car's place then)
    HeldSpeed held;
  };
  // Without overtaking: the nearest car ahead on the line within the window, if one is in the way.
  void followCarAhead(const std::string& car, const Place& place, Trajectory* window, RaceDecision* decision) const;

  Trajectory line_;
  VehicleLimits limits_;
  FieldOptions options_;
  std::optional<double> progress_origin_;  // line s every car's progress is counted from
  std::unique_ptr<OvertakePlanner> overtaker_;
  std::map<std::string, Place> cars_;
  std::map<std::string, double> pace_;
  std::map<std::string, RaceDecision> follow_decisions_;
};

}  // namespace roar::planning

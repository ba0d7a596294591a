#pragma once
// A racing trajectory: a line with the speed, curvature and acceleration to drive along it. Closed for the
// whole circuit; open for the window ahead of one car.
#include <Eigen/Core>
#include <limits>
#include <stdexcept>
#include <vector>

#include "roar/planning/racing_line.h"
#include "roar/planning/speed_profile.h"

namespace roar::planning {

struct TrajectoryPoint {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // m, map frame
  double z = 0.0;                                      // m, road height (for display)
  double yaw = 0.0;                                    // rad
  double s = 0.0;             // m along the trajectory (a window keeps the circuit's s, unwrapped)
  double curvature = 0.0;     // 1/m, positive left
  double speed = 0.0;         // m/s
  double acceleration = 0.0;  // m/s^2 along the path
  double time = 0.0;          // s from the first point of the lap
  double offset = 0.0;        // m left of the track's centre line
  // The pedal that drove a recorded lap from here (throttle - brake, -1..1), held until the next point; NaN on a
  // planned trajectory. The tracker feeds it forward (TrajectoryTracker.RecordedPedalsAreFedForward).
  double recorded_pedal = std::numeric_limits<double>::quiet_NaN();
};

struct Trajectory {
  std::vector<TrajectoryPoint> points;
  bool closed = true;
  double length = 0.0;    // m; a closed trajectory's last point leads back to the first over length - s.back()
  double lap_time = 0.0;  // s the profile promises for a lap (closed) or for the window (open)
};

class TrajectoryError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Throws TrajectoryError naming the first point and field that is not usable: fewer than 2 points,
// non-finite values, negative speed, s not increasing.
void validate(const Trajectory& trajectory);

struct PlannerOptions {
  RacingLineOptions line;
  SpeedProfileOptions profile;
  // Refine the minimum-curvature line towards minimum time (minimum_time.h): about 1% faster laps,
  // seconds instead of a fraction of one to plan.
  bool minimum_time = false;
};

// Metres before a point-to-point course's road ends where its trajectory has the car stopped.
inline constexpr double kCourseStopMargin = 20.0;

// Racing line and speed profile (the road's grade counted), with each point's road height. A
// point-to-point course's trajectory runs to the road's end, the car stopped kCourseStopMargin before it;
// its lap_time is the time from the start line to the finish line.
Trajectory planRacingTrajectory(const track::Track& track, const VehicleLimits& limits, const PlannerOptions& options);
Trajectory trajectoryOf(const track::Track& track, const RacingLine& line, const SpeedProfile& profile);

// A closed trajectory along a recorded lap (a car's positions at a fixed rate, with its speeds there: CARLA's
// telemetry of a lap): the points a metre or more apart, heading and curvature from the path smoothed over
// +-`smoothing` metres, accelerations from the speeds, times by integration; `pedals` (throttle - brake at each
// sample, or none) become the points' recorded_pedal. Throws TrajectoryError for fewer than 10 distinct points,
// a non-finite or negative value or a pedal outside -1..1, naming the sample.
Trajectory recordedTrajectory(const std::vector<Eigen::Vector2d>& positions, const std::vector<double>& speeds,
                              const std::vector<double>& pedals = {}, double smoothing = 6.0);

// Interpolated at s (wrapped on a closed trajectory, clamped to the ends of an open one).
TrajectoryPoint sampleAt(const Trajectory& trajectory, double s);

// Where a position is along a trajectory: index of the segment, s and signed lateral error (positive left).
struct TrajectoryProjection {
  std::size_t segment = 0;
  double s = 0.0;
  double lateral = 0.0;
};
// Searches every segment, or with `hint` only those within `window` points of it.
TrajectoryProjection project(const Trajectory& trajectory, const Eigen::Vector2d& position, long hint = -1,
                             long window = 40);

// The nearest point of the whole trajectory in 3D, its points' road height counted (track::kProjectionHeightWeight):
// where the course crosses itself on a bridge, the branch at the position's height. For a car's first
// projection; after it, `project` near the last one keeps the car on its branch.
TrajectoryProjection projectAtHeight(const Trajectory& trajectory, const Eigen::Vector3d& position);

// The open stretch from `behind` metres before s to `ahead` metres after it, s unwrapped past the lap.
Trajectory windowAround(const Trajectory& closed, double s, double behind, double ahead);

// Caps an open window's speeds so the car (at `car_s`) stays `gap` metres behind a car at `leader_s` (both
// in the window's s) going `leader_speed`: no faster than the leader from the gap on, braking for it in
// time before, and slower than the leader (1 m/s per metre) while closer than the gap.
// Given the car's speed (`car_speed`, m/s; negative: not given), the window keeps its own acceleration from
// the car on for as long as the car, gaining speed at it, stays below the speeds held: a tracker feeds
// forward the acceleration it reads just ahead, and a car still below the held speed would read the braking
// ramp's there: its throttle would go between full and none each time the car ahead, itself accelerating,
// raised the speed held, and it would fall back down the straight.
void followBehind(Trajectory* window, double car_s, double leader_s, double leader_speed, double gap,
                  const VehicleLimits& limits, double car_speed = -1.0);

// Per point, the sine of the road's slope to the next point (from the points' z and s); the last point of
// an open trajectory: the slope to it. For speed profiles planned on a window.
std::vector<double> slopes(const Trajectory& trajectory);

// How far a is ahead of b round a lap of `length` (both line s), in [-length / 2, length / 2); a - b when
// `length` is 0 (an open line has no lap).
double aheadOnLap(double a, double b, double length);
// The lap aheadOnLap measures along a trajectory: a closed one's length, 0 for an open one.
inline double lapLength(const Trajectory& trajectory) { return trajectory.closed ? trajectory.length : 0.0; }

// The trajectory's speeds times `pace`, its accelerations times pace squared (the same path driven at a
// share of the speed) and its times divided by it.
void scaleSpeeds(Trajectory* trajectory, double pace);

}  // namespace roar::planning

#pragma once
// The minimum-curvature racing line (as TUM's global_racetrajectory_optimization computes it): lateral
// offsets from a reference line, inside the track less half the car and a safety margin, minimising the
// sum of squared second differences of the line's points (its curvature at even spacing). That is a
// quadratic programme with box constraints; after each solve the line is resampled evenly and becomes
// the next reference, until its curvature stops changing.
#include <Eigen/Core>
#include <stdexcept>
#include <vector>

#include "roar/track/track.h"
#include "roar/vehicle/car_size.h"

namespace roar::planning {

struct RacingLineOptions {
  double vehicle_width = vehicle::kDefaultCarWidth;  // m
  double safety_margin = 0.5;                        // m kept between the car's side and the track edge
  double step = 3.0;                                 // m between the line's points
  int max_iterations = 10;
  double curvature_tolerance = 2e-4;  // 1/m: stop when the curvature changes by less than this (RMS over the line)
};

// A line through the track, evenly sampled: closed round a circuit, open from a course's first point to its last.
struct RacingLine {
  bool closed = true;
  std::vector<Eigen::Vector2d> points;
  std::vector<double> s;          // m along the line
  std::vector<double> heading;    // rad
  std::vector<double> curvature;  // 1/m, positive left
  std::vector<double> step;       // m from each point to the next (the last one back to the first; open: 0)
  std::vector<double> track_s;    // progress of each point's projection on the track's centre line
  std::vector<double> offset;     // m left of the centre line
  double length = 0.0;
  int iterations = 0;  // solves it took
  double last_curvature_change = 0.0;
};

class RacingLineError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The track's centre line, resampled every `step` metres.
RacingLine centreLine(const track::Track& track, double step);
// Throws RacingLineError when the track is narrower than the car plus its margins somewhere.
RacingLine minimumCurvatureLine(const track::Track& track, const RacingLineOptions& options);
// Heading, curvature, steps, length and the projection on the track, from the points.
void computeGeometry(const track::Track& track, RacingLine* line);
// Only the shape of a polyline (closed, or open with one-sided ends): steps to the next point, headings and
// curvatures.
void computeShape(const std::vector<Eigen::Vector2d>& points, std::vector<double>* step, std::vector<double>* heading,
                  std::vector<double>* curvature, bool closed = true);

}  // namespace roar::planning

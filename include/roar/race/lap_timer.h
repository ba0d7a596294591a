#pragma once
// Lap and sector timing from a car's positions. A lap counts only when the car crosses the start/finish
// line forwards after having been round the far side of the circuit since its last crossing, so a car
// wobbling back and forth over the line never scores a false lap (the f1tenth_gym failure). On a
// point-to-point course the one "lap" is the run from the start line to the finish line.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "roar/track/track.h"

namespace roar::race {

struct LapTimerOptions {
  // The car must reach progress in [arm_from, arm_to] (fractions of the lap after the line) to arm the next lap.
  double arm_from = 0.3;
  double arm_to = 0.7;
};

struct LapRecord {
  int lap = 0;                       // 1 for the first timed lap
  double lap_time = 0.0;             // s
  double finish_time = 0.0;          // s, simulated time of the crossing
  std::vector<double> sector_times;  // s, one per sector (empty entries never happen: sectors are forced in order)
};

class LapTimer {
 public:
  LapTimer(const track::Track& track, LapTimerOptions options = {});

  // Positions (map frame, z the height) in time order. The first is found on the whole track at its height
  // (under a bridge, the road below), later ones near the last. Returns the lap completed by this update, if any.
  std::optional<LapRecord> update(double time, const Eigen::Vector3d& position);

  bool started() const { return started_; }
  int lapsCompleted() const { return static_cast<int>(laps_.size()); }
  const std::vector<LapRecord>& laps() const { return laps_; }
  std::optional<double> bestLap() const;
  // Metres after the start/finish line, [0, length); on a point-to-point course after the start line,
  // negative before it.
  double progress() const { return progress_; }
  double lapStart() const { return lap_start_; }  // s, when the lap under way began (once started)
  // Distance covered since the first crossing: laps * length + progress (a course: its progress); for
  // gaps between cars.
  double distanceCovered() const;

 private:
  std::optional<LapRecord> updateOnCourse(double time, double progress);

  const track::Track& track_;
  LapTimerOptions options_;
  bool have_previous_ = false;
  double previous_time_ = 0.0;
  double progress_ = 0.0;
  double track_s_ = 0.0;
  bool started_ = false;
  bool armed_ = false;
  double lap_start_ = 0.0;
  int next_sector_ = 1;
  double sector_start_ = 0.0;
  std::vector<double> sector_times_;
  std::vector<LapRecord> laps_;
};

}  // namespace roar::race

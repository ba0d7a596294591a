#include "roar/race/lap_timer.h"

#include <algorithm>

namespace roar::race {

LapTimer::LapTimer(const track::Track& track, LapTimerOptions options) : track_(track), options_(options) {}

std::optional<LapRecord> LapTimer::update(double time, const Eigen::Vector3d& position) {
  const double length = track_.length();
  const track::Projection pr =
      have_previous_ ? track_.projectNear(position.head<2>(), track_s_, 100.0) : track_.projectAtHeight(position);
  track_s_ = pr.s;
  const double progress = track_.raceProgress(pr.s);
  if (!track_.closed()) return updateOnCourse(time, progress);
  if (!have_previous_) {
    have_previous_ = true;
    previous_time_ = time;
    progress_ = progress;
    return std::nullopt;
  }
  const double before = progress_, before_time = previous_time_;
  progress_ = progress;
  previous_time_ = time;

  // A forward crossing: progress wraps from near the end of the lap to near its start.
  const bool crossed = before > 0.75 * length && progress < 0.25 * length;
  const double fraction = progress / length;
  if (fraction >= options_.arm_from && fraction <= options_.arm_to) armed_ = true;

  // Sector boundaries passed forwards since the last update (not the finish line, handled below).
  const int sectors = track_.info().sectors;
  if (started_ && !crossed) {
    while (next_sector_ < sectors && before < next_sector_ * length / sectors &&
           progress >= next_sector_ * length / sectors && progress - before < 0.25 * length) {
      const double boundary = next_sector_ * length / sectors;
      const double t = before_time + (time - before_time) * (boundary - before) / (progress - before);
      sector_times_.push_back(t - sector_start_);
      sector_start_ = t;
      ++next_sector_;
    }
  }
  if (!crossed) return std::nullopt;

  const double travelled = (length - before) + progress;
  const double t_cross = before_time + (time - before_time) * (length - before) / std::max(travelled, 1e-9);
  std::optional<LapRecord> record;
  if (started_ && armed_) {
    while (static_cast<int>(sector_times_.size()) < sectors - 1) sector_times_.push_back(0.0);
    sector_times_.push_back(t_cross - sector_start_);
    LapRecord lap;
    lap.lap = lapsCompleted() + 1;
    lap.lap_time = t_cross - lap_start_;
    lap.finish_time = t_cross;
    lap.sector_times = sector_times_;
    laps_.push_back(lap);
    record = lap;
  }
  if (!started_ || armed_) {
    started_ = true;
    armed_ = false;
    lap_start_ = t_cross;
    sector_start_ = t_cross;
    next_sector_ = 1;
    sector_times_.clear();
  }
  return record;
}

std::optional<LapRecord> LapTimer::updateOnCourse(double time, double progress) {
  const double before = progress_, before_time = previous_time_;
  const bool first = !have_previous_;
  have_previous_ = true;
  progress_ = progress;
  previous_time_ = time;
  if (first) return std::nullopt;
  // When the car crossed `line` (progress) between the last update and this one.
  auto crossing = [&](double line) {
    return before_time + (time - before_time) * (line - before) / std::max(progress - before, 1e-9);
  };
  if (!started_) {
    if (!(before < 0.0 && progress >= 0.0)) return std::nullopt;
    started_ = true;
    lap_start_ = sector_start_ = crossing(0.0);
    next_sector_ = 1;
    sector_times_.clear();
  }
  if (!laps_.empty()) return std::nullopt;  // one run from start to finish
  const double distance = track_.raceDistance();
  const int sectors = track_.info().sectors;
  while (next_sector_ < sectors && before < next_sector_ * distance / sectors &&
         progress >= next_sector_ * distance / sectors) {
    const double t = crossing(next_sector_ * distance / sectors);
    sector_times_.push_back(t - sector_start_);
    sector_start_ = t;
    ++next_sector_;
  }
  if (!(before < distance && progress >= distance)) return std::nullopt;
  const double t_cross = crossing(distance);
  sector_times_.push_back(t_cross - sector_start_);
  LapRecord run;
  run.lap = 1;
  run.lap_time = t_cross - lap_start_;
  run.finish_time = t_cross;
  run.sector_times = sector_times_;
  laps_.push_back(run);
  return run;
}

std::optional<double> LapTimer::bestLap() const {
  if (laps_.empty()) return std::nullopt;
  return std::min_element(laps_.begin(), laps_.end(),
                          [](const LapRecord& a, const LapRecord& b) { return a.lap_time < b.lap_time; })
      ->lap_time;
}

double LapTimer::distanceCovered() const {
  if (!track_.closed()) return progress_;
  return started_ ? lapsCompleted() * track_.length() + progress_ : progress_ - track_.length();
}

}  // namespace roar::race

#include "roar/rl/episode.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace roar::rl {

namespace {
constexpr double kStallDistance = 5.0;  // m of progress that restart the stall clock

}  // namespace

Episode::Episode(const track::Track& track, const RewardOptions& reward, const TerminationOptions& termination)
    : track_(&track), reward_(reward), termination_(termination), progress_(track) {
  validate(reward_);
  validate(termination_);
}

StepInfo Episode::begin(const vehicle::VehicleState& state, double time) {
  const Eigen::Vector3d& at = state.pose.position;
  progress_.reset(at);
  lap_timer_.emplace(*track_);
  lap_timer_->update(time, at);
  start_time_ = time;
  stall_progress_ = 0.0;
  stall_since_ = time;
  info_ = StepInfo();
  info_.track_s = where().s;
  info_.lateral = where().lateral;
  info_.beyond_edge = where().beyondEdge();
  info_.speed = state.speed;
  return info_;
}

StepOutcome Episode::step(const vehicle::VehicleState& state, const std::vector<sim::Contact>& contacts, double time) {
  const Eigen::Vector3d& at = state.pose.position;
  const double advanced = progress_.update(at.head<2>());
  const track::Projection& p = where();
  StepOutcome out;
  StepInfo& info = info_;
  info.progress += advanced;
  info.track_s = p.s;
  info.lateral = p.lateral;
  info.speed = state.speed;
  info.episode_time = time - start_time_;
  info.episode_steps += 1;
  if (auto lap = lap_timer_->update(time, at)) {
    info.laps = lap_timer_->lapsCompleted();
    info.last_lap_time = lap->lap_time;
  }
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();
  for (const auto& c : contacts) impulse += c.impulse;
  info.collision_impulse = impulse.norm();
  const double threshold = termination_.collision_threshold;
  info.collided = threshold > 0.0 && info.collision_impulse >= threshold;
  info.beyond_edge = p.beyondEdge();
  info.off_track = termination_.off_track_margin >= 0.0 && info.beyond_edge > termination_.off_track_margin;
  if (info.progress - stall_progress_ >= kStallDistance) {
    stall_progress_ = info.progress;
    stall_since_ = time;
  }
  info.stalled = termination_.stall_time > 0.0 && time - stall_since_ >= termination_.stall_time;
  info.wrong_way = termination_.max_backwards > 0.0 && info.progress <= -termination_.max_backwards;

  const auto& r = reward_;
  if (info.collided) {
    const double excess = info.collision_impulse - threshold;
    out.reward = -std::min(r.collision_penalty_cap, r.collision_penalty_scale * std::pow(excess, 1.4) / threshold);
  } else if (advanced > 0.0) {
    out.reward = advanced * r.progress_weight / (1.0 + r.centre_weight * std::abs(p.lateral));
  } else {
    out.reward = advanced * r.backwards_weight;
  }
  out.reward -= r.step_penalty;
  if (info.off_track) out.reward -= r.off_track_penalty;

  // A point-to-point course ends at its finish line: the run is done there.
  const bool course_done = !track_->closed() && info.laps >= 1;
  out.terminated = info.collided || info.off_track || info.wrong_way || course_done;
  out.truncated =
      !out.terminated &&
      ((termination_.time_limit > 0.0 && info.episode_time >= termination_.time_limit - 1e-9) || info.stalled);
  info.episode_return += out.reward;
  out.info = info;
  return out;
}

}  // namespace roar::rl

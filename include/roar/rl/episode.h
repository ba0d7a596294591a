#pragma once
// One car's episode as an RL environment judges it: the reward for each step, whether the episode ended
// (terminated: a crash or leaving the track; truncated: the time limit or no progress) and what happened.
// The reward is ROAR_PY_RL's: progress along the centre line, worth less the farther the car is from it,
//   d * progress_weight / (1 + centre_weight * |lateral|)   forwards,   d * backwards_weight   backwards,
// minus a step penalty; a collision above the threshold costs ((J - threshold)^1.4 / threshold) * scale
// (ROAR_PY_RL's shape, capped) instead, and leaving the track costs off_track_penalty.
#include <optional>
#include <vector>

#include "roar/race/lap_timer.h"
#include "roar/rl/episode_options.h"
#include "roar/rl/track_progress.h"
#include "roar/sim/world.h"
#include "roar/track/track.h"

namespace roar::rl {

struct StepInfo {
  double progress = 0.0;           // m along the centre line since the episode began (negative: backwards)
  double track_s = 0.0;            // m, where along the centre line
  double lateral = 0.0;            // m from the centre line, positive left
  double beyond_edge = 0.0;        // m of base_link beyond the nearer road edge (negative: on the road)
  double speed = 0.0;              // m/s
  double collision_impulse = 0.0;  // N s during the step, every body summed
  bool collided = false;           // above the threshold
  bool off_track = false;          // beyond the margin
  bool stalled = false;
  bool wrong_way = false;
  int laps = 0;                // completed, from the car's first crossing of the start/finish line
  double last_lap_time = 0.0;  // s, 0 before the first
  double episode_time = 0.0;   // s since the episode's first observation
  int episode_steps = 0;
  double episode_return = 0.0;
};

struct StepOutcome {
  double reward = 0.0;
  bool terminated = false;
  bool truncated = false;
  StepInfo info;
};

class Episode {
 public:
  Episode(const track::Track& track, const RewardOptions& reward, const TerminationOptions& termination);

  // The episode's first observation is of `state` at `time` (s).
  StepInfo begin(const vehicle::VehicleState& state, double time);
  // After a step: the car's state, the contacts of the step and the time at its end.
  StepOutcome step(const vehicle::VehicleState& state, const std::vector<sim::Contact>& contacts, double time);

  const track::Projection& where() const { return progress_.projection(); }
  const StepInfo& info() const { return info_; }

 private:
  const track::Track* track_;
  RewardOptions reward_;
  TerminationOptions termination_;
  TrackProgress progress_;
  std::optional<race::LapTimer> lap_timer_;  // made anew for every episode
  double start_time_ = 0.0;
  double stall_progress_ = 0.0;  // progress when the stall clock last restarted
  double stall_since_ = 0.0;     // s
  StepInfo info_;
};

}  // namespace roar::rl

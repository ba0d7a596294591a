#pragma once
// How an episode is judged (rl/episode.h judges it): its reward weights and when it ends, readable and
// checked where the simulator is not linked.

namespace roar::rl {

struct RewardOptions {
  double progress_weight = 20.0;   // per metre forwards along the centre line
  double centre_weight = 0.2;      // 1/m: forward progress is divided by 1 + centre_weight * |lateral|
  double backwards_weight = 20.0;  // per metre backwards (a negative reward)
  double step_penalty = 0.0;       // every step
  double collision_penalty_scale = 1.0;
  double collision_penalty_cap = 100.0;  // the most one collision costs
  double off_track_penalty = 10.0;
};

struct TerminationOptions {
  double collision_threshold = 30.0;  // N s of impulse in one step (ROAR_PY_RL's 30) that ends the episode; 0: never
  double off_track_margin = 1.0;      // m of base_link beyond the road edge that ends it (all four wheels are
                                      // off at 0.93 m for the sedan); negative: never
  double time_limit = 120.0;          // s of simulated time, then truncated; 0: none
  double stall_time = 10.0;           // s without 5 m of progress, then truncated; 0: never
  double max_backwards = 50.0;        // m driven backwards from the start that end it (wrong way); 0: never
};

void validate(const RewardOptions& options);
void validate(const TerminationOptions& options);

}  // namespace roar::rl

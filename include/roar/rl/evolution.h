#pragma once
// Evolution strategies (Salimans et al. 2017) for the MLP policy: each generation perturbs the parameters
// along `directions` random directions both ways (antithetic pairs), runs an episode with each candidate
// from the generation's spawn seeds (all candidates meet the same spawns), ranks the returns (centred
// ranks) and moves the parameters along the estimated gradient with Adam. Candidates run in parallel, one environment
// per thread; a run is deterministic for a seed and thread count.
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "roar/rl/policy.h"
#include "roar/rl/racing_env.h"
#include "roar/rl/worker_pool.h"

namespace roar::rl {

struct EvolutionOptions {
  int directions = 16;          // antithetic pairs per generation: 2 * directions candidates
  double sigma = 0.05;          // perturbation size, in parameter units
  double learning_rate = 0.02;  // Adam's step size
  double weight_decay = 0.005;  // pulls every parameter towards zero, per generation, times the learning rate
  int episodes = 1;             // per candidate, from as many spawn seeds
  std::vector<int> hidden = {32};
  int threads = 2;  // the caller's included
  std::uint64_t seed = 1;
};

struct GenerationReport {
  int generation = 0;        // 1 for the first
  double mean_return = 0.0;  // over the candidates
  double best_return = 0.0;
  double mean_progress = 0.0;  // m along the track per episode, over the candidates
  std::int64_t env_steps = 0;  // this generation
};

// How a policy drives one episode from a reset of `env`: its return and what the last step said.
struct Rollout {
  double episode_return = 0.0;
  StepInfo info;
  bool terminated = false, truncated = false;
};
Rollout rollout(RacingEnv& env, const MlpPolicy& policy, std::uint64_t seed);

class EvolutionStrategy {
 public:
  // make_env makes one environment per thread (with the same spaces); the policy observes what they observe.
  EvolutionStrategy(const std::function<std::unique_ptr<RacingEnv>()>& make_env, const EvolutionOptions& options);

  GenerationReport runGeneration();
  const MlpPolicy& policy() const { return policy_; }
  int generation() const { return generation_; }

 private:
  EvolutionOptions options_;
  std::vector<std::unique_ptr<RacingEnv>> envs_;  // one per thread
  WorkerPool pool_;
  MlpPolicy policy_;
  std::vector<double> adam_m_, adam_v_;
  std::mt19937_64 rng_;
  int generation_ = 0;
};

}  // namespace roar::rl

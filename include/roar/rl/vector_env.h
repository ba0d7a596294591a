#pragma once
// N racing environments stepped in parallel threads, Gymnasium's vector-environment way: one action per
// environment in, one result per environment out, and an environment whose episode ended starts its next
// one at once (auto-reset): its result then holds the new episode's first observation, and the last
// observation of the old one is kept in final_observation.
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "roar/rl/racing_env.h"
#include "roar/rl/worker_pool.h"

namespace roar::rl {

struct VectorStepResult {
  // One per environment: reward, terminated, truncated and info of the step (the ended episode's, when
  // one ended), and the observation to act on next (the new episode's first, when one ended).
  std::vector<StepResult> steps;
  std::vector<std::optional<Value>> final_observations;  // set where an episode ended this step
};

class VectorEnv {
 public:
  // Every environment must have the same spaces. threads: workers, the caller's thread included.
  VectorEnv(std::vector<std::unique_ptr<RacingEnv>> envs, int threads);

  std::size_t size() const { return envs_.size(); }
  RacingEnv& env(std::size_t i) { return *envs_[i]; }
  const Space& actionSpace() const { return envs_.front()->actionSpace(); }
  const Space& observationSpace() const { return envs_.front()->observationSpace(); }

  // Environment i is reset with seed + i.
  std::vector<ResetResult> reset(std::uint64_t seed);
  // Called for each environment by the thread that stepped it, as soon as its result is ready: where a
  // caller copies results out (the Python module's NumPy rows) in parallel rather than after the step.
  using RowSink =
      std::function<void(std::size_t env, const StepResult& step, const std::optional<Value>& final_observation)>;
  // Throws SpaceError (for the first bad one) when an action is outside the space; nothing is stepped then.
  // The result stays valid until the next step().
  const VectorStepResult& step(const std::vector<Value>& actions, const RowSink& sink = {});

 private:
  std::vector<std::unique_ptr<RacingEnv>> envs_;
  WorkerPool pool_;
  // Each environment's last result, overwritten by the thread that steps it (shares are fixed), so memory
  // is freed by the thread that allocated it.
  VectorStepResult last_;
};

}  // namespace roar::rl

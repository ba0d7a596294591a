#include "roar/rl/vector_env.h"

#include <stdexcept>

namespace roar::rl {

VectorEnv::VectorEnv(std::vector<std::unique_ptr<RacingEnv>> envs, int threads)
    : envs_(std::move(envs)), pool_(threads) {
  if (envs_.empty()) throw std::invalid_argument("VectorEnv needs at least one environment");
  for (const auto& e : envs_) {
    if (toYaml(e->actionSpace()) != toYaml(actionSpace()) ||
        toYaml(e->observationSpace()) != toYaml(observationSpace())) {
      throw std::invalid_argument("VectorEnv: the environments' spaces differ");
    }
  }
}

std::vector<ResetResult> VectorEnv::reset(std::uint64_t seed) {
  std::vector<ResetResult> out(envs_.size());
  pool_.run(envs_.size(), [&](std::size_t i, int) { out[i] = envs_[i]->reset(seed + i); });
  return out;
}

const VectorStepResult& VectorEnv::step(const std::vector<Value>& actions, const RowSink& sink) {
  if (actions.size() != envs_.size()) {
    throw std::invalid_argument("VectorEnv::step: " + std::to_string(actions.size()) + " actions for " +
                                std::to_string(envs_.size()) + " environments");
  }
  for (std::size_t i = 0; i < actions.size(); ++i)
    check(actionSpace(), actions[i], "actions[" + std::to_string(i) + "]");
  last_.steps.resize(envs_.size());
  last_.final_observations.resize(envs_.size());
  pool_.run(envs_.size(), [&](std::size_t i, int) {
    StepResult& r = last_.steps[i];
    envs_[i]->step(actions[i], &r);
    last_.final_observations[i].reset();
    if (r.done()) {
      last_.final_observations[i] = std::move(r.observation);
      r.observation = envs_[i]->reset().observation;
    }
    if (sink) sink(i, r, last_.final_observations[i]);
  });
  return last_;
}

}  // namespace roar::rl

#include "roar/rl/evolution.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace roar::rl {

namespace {

// Centred ranks (Salimans et al.): the worst return -0.5, the best +0.5, ties broken by position.
std::vector<double> centredRanks(const std::vector<double>& returns) {
  std::vector<std::size_t> order(returns.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return returns[a] < returns[b]; });
  std::vector<double> ranks(returns.size());
  const double n = static_cast<double>(returns.size());
  for (std::size_t r = 0; r < order.size(); ++r) ranks[order[r]] = n > 1 ? r / (n - 1) - 0.5 : 0.0;
  return ranks;
}

void validate(const EvolutionOptions& o) {
  if (o.directions < 1) throw std::invalid_argument("evolution: directions must be at least 1");
  if (!(o.sigma > 0)) throw std::invalid_argument("evolution: sigma must be positive");
  if (!(o.learning_rate > 0)) throw std::invalid_argument("evolution: learning_rate must be positive");
  if (!(o.weight_decay >= 0)) throw std::invalid_argument("evolution: weight_decay must not be negative");
  if (o.episodes < 1) throw std::invalid_argument("evolution: episodes must be at least 1");
  if (o.threads < 1) throw std::invalid_argument("evolution: threads must be at least 1");
}

}  // namespace

Rollout rollout(RacingEnv& env, const MlpPolicy& policy, std::uint64_t seed) {
  Rollout out;
  StepResult step;
  step.observation = env.reset(seed).observation;
  for (;;) {
    env.step(policy.act(env.actionSpace(), step.observation), &step);
    out.episode_return += step.reward;
    out.info = step.info;
    if (step.done()) {
      out.terminated = step.terminated;
      out.truncated = step.truncated;
      return out;
    }
  }
}

EvolutionStrategy::EvolutionStrategy(const std::function<std::unique_ptr<RacingEnv>()>& make_env,
                                     const EvolutionOptions& options)
    : options_(options), pool_(options.threads), rng_(options.seed) {
  validate(options_);
  for (int t = 0; t < options_.threads; ++t) envs_.push_back(make_env());
  policy_ = MlpPolicy(envs_.front()->options().observation, options_.hidden);
  adam_m_.assign(policy_.params().size(), 0.0);
  adam_v_.assign(policy_.params().size(), 0.0);
}

GenerationReport EvolutionStrategy::runGeneration() {
  ++generation_;
  const std::size_t params = policy_.params().size();
  const std::size_t directions = static_cast<std::size_t>(options_.directions);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  std::vector<std::vector<float>> noise(directions, std::vector<float>(params));
  for (auto& eps : noise) {
    for (float& e : eps) e = normal(rng_);
  }
  std::vector<std::uint64_t> seeds(static_cast<std::size_t>(options_.episodes));
  for (auto& s : seeds) s = rng_();

  // Candidate 2k is theta + sigma eps_k, 2k + 1 is theta - sigma eps_k.
  const std::size_t candidates = 2 * directions;
  std::vector<double> returns(candidates, 0.0), progress(candidates, 0.0);
  std::vector<std::int64_t> steps(candidates, 0);
  const float sigma = static_cast<float>(options_.sigma);
  pool_.run(candidates, [&](std::size_t c, int thread) {
    MlpPolicy candidate = policy_;
    const float sign = c % 2 == 0 ? 1.0f : -1.0f;
    const std::vector<float>& eps = noise[c / 2];
    for (std::size_t j = 0; j < params; ++j) candidate.params()[j] += sign * sigma * eps[j];
    for (std::uint64_t seed : seeds) {
      const Rollout r = rollout(*envs_[static_cast<std::size_t>(thread)], candidate, seed);
      returns[c] += r.episode_return / static_cast<double>(seeds.size());
      progress[c] += r.info.progress / static_cast<double>(seeds.size());
      steps[c] += r.info.episode_steps;
    }
  });

  const std::vector<double> ranks = centredRanks(returns);
  std::vector<double> gradient(params, 0.0);
  for (std::size_t k = 0; k < directions; ++k) {
    const double weight = ranks[2 * k] - ranks[2 * k + 1];
    for (std::size_t j = 0; j < params; ++j) gradient[j] += weight * noise[k][j];
  }
  // Adam, ascending.
  constexpr double kBeta1 = 0.9, kBeta2 = 0.999, kEpsilon = 1e-8;
  const double lr = options_.learning_rate;
  const double correction1 = 1.0 - std::pow(kBeta1, generation_), correction2 = 1.0 - std::pow(kBeta2, generation_);
  for (std::size_t j = 0; j < params; ++j) {
    const double g = gradient[j] / (static_cast<double>(candidates) * options_.sigma);
    adam_m_[j] = kBeta1 * adam_m_[j] + (1.0 - kBeta1) * g;
    adam_v_[j] = kBeta2 * adam_v_[j] + (1.0 - kBeta2) * g * g;
    const double step = lr * (adam_m_[j] / correction1) / (std::sqrt(adam_v_[j] / correction2) + kEpsilon);
    float& theta = policy_.params()[j];
    theta = static_cast<float>(theta + step - lr * options_.weight_decay * theta);
  }

  GenerationReport report;
  report.generation = generation_;
  report.mean_return = std::accumulate(returns.begin(), returns.end(), 0.0) / static_cast<double>(candidates);
  report.best_return = *std::max_element(returns.begin(), returns.end());
  report.mean_progress = std::accumulate(progress.begin(), progress.end(), 0.0) / static_cast<double>(candidates);
  report.env_steps = std::accumulate(steps.begin(), steps.end(), std::int64_t{0});
  return report;
}

}  // namespace roar::rl

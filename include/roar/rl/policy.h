#pragma once
// A small feed-forward policy for the racing environment: the flattened observation, normalised by a mean
// and spread, through tanh hidden layers to two tanh outputs, steer and pedal (throttle when positive,
// brake when negative). Evolution strategies train it; the policy_driver node drives with it. A policy file
// (YAML) carries the observation options it was trained with, so whoever loads it observes the same way.
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "roar/rl/observation.h"
#include "roar/rl/space.h"

namespace roar::rl {

class PolicyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class MlpPolicy {
 public:
  MlpPolicy() = default;
  // Zero weights (steer 0, pedal 0); each observed number normalised by its natural scale (speeds by
  // 20 m/s, a waypoint's position by its distance ahead, ...). Throws PolicyError for a hidden layer of size < 1.
  MlpPolicy(const ObservationOptions& observation, std::vector<int> hidden);

  const ObservationOptions& observation() const { return observation_; }
  const Space& observationSpace() const { return observation_space_; }
  const std::vector<int>& hidden() const { return hidden_; }
  std::size_t inputs() const { return mean_.size(); }

  std::vector<float>& params() { return params_; }
  const std::vector<float>& params() const { return params_; }
  std::vector<float>& mean() { return mean_; }
  std::vector<float>& spread() { return spread_; }

  // {steer, pedal}, each in [-1, 1], of a flattened observation.
  std::array<float, 2> outputs(const std::vector<float>& flat_observation) const;
  // The action for `observation` in an action space without manual gears (PolicyError otherwise).
  Value act(const Space& action_space, const Value& observation) const;

  void save(const std::string& path) const;
  // Throws PolicyError naming the file and what is wrong with it.
  static MlpPolicy load(const std::string& path);

 private:
  ObservationOptions observation_;
  Space observation_space_;
  std::vector<int> hidden_;
  std::vector<float> mean_, spread_;  // of the flat observation: input = (x - mean) / spread
  std::vector<float> params_;         // per layer: weights (outputs x inputs, row-major), then biases
};

}  // namespace roar::rl

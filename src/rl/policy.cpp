#include "roar/rl/policy.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "roar/config/text_file.h"
#include "roar/config/yaml_section.h"
#include "roar/rl/env_options.h"

namespace roar::rl {

namespace {

constexpr const char* kFormat = "roar_ros mlp policy 1";

std::vector<int> layerSizes(std::size_t inputs, const std::vector<int>& hidden) {
  std::vector<int> sizes = {static_cast<int>(inputs)};
  sizes.insert(sizes.end(), hidden.begin(), hidden.end());
  sizes.push_back(2);
  return sizes;
}

// Mean and spread that bring each observed number near [-1, 1]: the sizes a racing car meets.
void naturalScales(const ObservationOptions& o, const Space& space, std::vector<float>* mean,
                   std::vector<float>* spread) {
  auto add = [&](std::size_t count, float m, float s) {
    mean->insert(mean->end(), count, m);
    spread->insert(spread->end(), count, s);
  };
  for (const auto& key : space.keys) {  // in the flattening's order
    const Space& entry = space.at(key);
    if (key == "speed") add(1, 0.0f, 20.0f);
    if (key == "velocity") add(3, 0.0f, 20.0f);
    if (key == "angular_velocity") add(3, 0.0f, 0.5f);
    if (key == "imu") add(3, 0.0f, 10.0f), add(3, 0.0f, 0.5f);
    if (key == "waypoints_information") {
      for (const auto& waypoint : entry.keys) {
        double d = 0.0;
        for (double candidate : o.waypoint_distances) {
          if (waypointKey(candidate) == waypoint) d = candidate;
        }
        const float reach = static_cast<float>(std::max(d, 2.0));
        add(1, 0.0f, reach), add(1, 0.0f, reach), add(1, 0.0f, 0.5f), add(1, 10.0f, 5.0f);
      }
    }
    if (key == "lidar")
      add(entry.elements(), 0.5f * static_cast<float>(o.lidar.max_range), 0.5f * static_cast<float>(o.lidar.max_range));
    if (key == "camera_rgb") add(entry.elements(), 127.5f, 127.5f);
    if (key == "camera_depth")
      add(entry.elements(), 0.5f * static_cast<float>(o.camera.max_depth),
          0.5f * static_cast<float>(o.camera.max_depth));
  }
}

std::size_t paramCount(const std::vector<int>& sizes) {
  std::size_t n = 0;
  for (std::size_t l = 0; l + 1 < sizes.size(); ++l) n += static_cast<std::size_t>(sizes[l + 1]) * (sizes[l] + 1);
  return n;
}

}  // namespace

MlpPolicy::MlpPolicy(const ObservationOptions& observation, std::vector<int> hidden)
    : observation_(observation), observation_space_(rl::observationSpace(observation)), hidden_(std::move(hidden)) {
  for (int h : hidden_) {
    if (h < 1 || h > 4096) throw PolicyError("a hidden layer needs 1 to 4096 units, not " + std::to_string(h));
  }
  const std::size_t inputs = observation_space_.flatDim();
  naturalScales(observation_, observation_space_, &mean_, &spread_);
  if (mean_.size() != inputs) throw PolicyError("internal: the natural scales miss an observation key");
  params_.assign(paramCount(layerSizes(inputs, hidden_)), 0.0f);
}

std::array<float, 2> MlpPolicy::outputs(const std::vector<float>& flat) const {
  if (flat.size() != mean_.size()) {
    throw PolicyError("the policy takes " + std::to_string(mean_.size()) + " observation numbers, got " +
                      std::to_string(flat.size()));
  }
  const std::vector<int> sizes = layerSizes(flat.size(), hidden_);
  std::vector<float> x(flat.size()), y;
  for (std::size_t i = 0; i < flat.size(); ++i) x[i] = (flat[i] - mean_[i]) / spread_[i];
  const float* p = params_.data();
  for (std::size_t l = 0; l + 1 < sizes.size(); ++l) {
    const int in = sizes[l], out = sizes[l + 1];
    y.assign(static_cast<std::size_t>(out), 0.0f);
    for (int o = 0; o < out; ++o) {
      float sum = p[static_cast<std::size_t>(out) * in + o];  // bias
      const float* w = p + static_cast<std::size_t>(o) * in;
      for (int i = 0; i < in; ++i) sum += w[i] * x[static_cast<std::size_t>(i)];
      y[static_cast<std::size_t>(o)] = std::tanh(sum);
    }
    p += static_cast<std::size_t>(out) * (in + 1);
    x.swap(y);
  }
  return {x[0], x[1]};
}

Value MlpPolicy::act(const Space& action_space, const Value& observation) const {
  if (action_space.has("target_gear")) throw PolicyError("this policy drives with the automatic gearbox only");
  const auto [steer, pedal] = outputs(flatten(observation_space_, observation));
  Value a;
  a.at("throttle") = Value::of({std::max(0.0f, pedal)});
  a.at("brake") = Value::of({std::max(0.0f, -pedal)});
  a.at("steer") = Value::of({steer});
  a.at("hand_brake") = Value::of({0.0});
  a.at("reverse") = Value::of({0.0});
  return a;
}

void MlpPolicy::save(const std::string& path) const {
  YAML::Emitter out;
  out.SetFloatPrecision(9);  // floats round-trip exactly
  out << YAML::BeginMap;
  out << YAML::Key << "format" << YAML::Value << kFormat;
  out << YAML::Key << "observation" << YAML::Value << YAML::Load(toYaml(observation_));
  out << YAML::Key << "action" << YAML::Value << "steer_pedal";
  out << YAML::Key << "hidden" << YAML::Value << YAML::Flow << hidden_;
  out << YAML::Key << "mean" << YAML::Value << YAML::Flow << mean_;
  out << YAML::Key << "spread" << YAML::Value << YAML::Flow << spread_;
  out << YAML::Key << "params" << YAML::Value << YAML::Flow << params_;
  out << YAML::EndMap;
  std::ofstream file(path);
  file << out.c_str() << "\n";
  if (!file) throw PolicyError(path + ": cannot be written");
}

MlpPolicy MlpPolicy::load(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::Load(config::readTextFile<PolicyError>(path, config::kMaxPolicyBytes));
  } catch (const YAML::Exception& e) {
    throw PolicyError(path + ": " + e.what());
  }
  auto fail = [&](const std::string& what) { throw PolicyError(path + ": " + what); };
  if (!root.IsMap() || !root["format"] || root["format"].as<std::string>("") != kFormat) {
    fail(std::string("not a policy file (format must be '") + kFormat + "')");
  }
  // The one strict reader: a key it does not know is refused naming the nearest one.
  config::YamlSection<PolicyError> file(root, "", path);
  file.require<std::string>("format");
  if (file.require<std::string>("action") != "steer_pedal") fail("action: only steer_pedal policies are known");
  const YAML::Node observation_node = file.raw("observation");
  const auto hidden = file.require<std::vector<int>>("hidden");
  const auto mean = file.require<std::vector<double>>("mean");
  const auto spread = file.require<std::vector<double>>("spread");
  const auto params = file.require<std::vector<double>>("params");
  file.finish();
  MlpPolicy policy;
  try {
    YAML::Emitter observation;
    observation << observation_node;
    const ObservationOptions options = parseObservationOptions(observation.c_str(), path);
    policy = MlpPolicy(options, hidden);
  } catch (const EnvConfigError& e) {
    throw PolicyError(e.what());
  } catch (const PolicyError& e) {
    fail(std::string("hidden: ") + e.what());
  }
  if (mean.size() != policy.mean_.size() || spread.size() != policy.spread_.size()) {
    fail("mean and spread need " + std::to_string(policy.mean_.size()) + " numbers for this observation");
  }
  if (params.size() != policy.params_.size()) {
    fail("params: " + std::to_string(params.size()) + " numbers, the network needs " +
         std::to_string(policy.params_.size()));
  }
  // Finite as floats too (1e300 is a finite double), the spreads positive.
  auto as_floats = [&](const std::vector<double>& v, const char* key, bool positive) {
    std::vector<float> out;
    for (double x : v) {
      const float f = static_cast<float>(x);
      if (!std::isfinite(f) || (positive && !(f > 0))) {
        fail(std::string(key) + ": " + std::to_string(x) +
             (positive ? " is not a positive float" : " is not a finite float"));
      }
      out.push_back(f);
    }
    return out;
  };
  policy.mean_ = as_floats(mean, "mean", false);
  policy.spread_ = as_floats(spread, "spread", true);
  policy.params_ = as_floats(params, "params", false);
  return policy;
}

}  // namespace roar::rl

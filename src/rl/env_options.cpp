#include "roar/rl/env_options.h"

#include "roar/config/text_file.h"
#include "roar/config/yaml_section.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace roar::rl {

namespace {

using Section = config::YamlSection<EnvConfigError>;

void readObservation(Section s, ObservationOptions* o) {
  s.read("speed", &o->speed);
  s.read("velocity", &o->velocity);
  s.read("angular_velocity", &o->angular_velocity);
  s.read("imu", &o->imu);
  s.read("waypoint_distances", &o->waypoint_distances);
  Section lidar = s.child("lidar");
  lidar.read("beams", &o->lidar.beams);
  lidar.read("max_range", &o->lidar.max_range);
  lidar.read("fov", &o->lidar.fov_deg);
  lidar.read("height", &o->lidar.height);
  lidar.finish();
  Section camera = s.child("camera");
  camera.read("width", &o->camera.width);
  camera.read("height", &o->camera.height);
  camera.read("fov", &o->camera.fov_deg);
  camera.read("rgb", &o->camera.rgb);
  camera.read("depth", &o->camera.depth);
  camera.read("max_depth", &o->camera.max_depth);
  camera.finish();
  s.finish();
}

YAML::Node parse(const std::string& yaml_text, const std::string& source) {
  try {
    return YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw EnvConfigError(source + ": " + e.what());
  }
}

template <class F>
void rethrowAs(const std::string& source, F&& check) {
  try {
    check();
  } catch (const std::invalid_argument& e) {
    throw EnvConfigError(source + ": " + e.what());
  }
}

}  // namespace

void validate(const EnvOptions& o) {
  rl::validate(o.observation);
  rl::validate(o.reward);
  rl::validate(o.termination);
  if (!(o.world.physics_dt > 0.0) || !(o.world.control_dt >= o.world.physics_dt)) {
    throw EnvConfigError("physics_dt must be positive and no larger than control_dt");
  }
  if (!(o.spawn_lateral >= 0.0)) throw EnvConfigError("spawn_lateral must not be negative");
  if (!(o.settle_time >= 0.0 && o.settle_time <= 10.0)) throw EnvConfigError("settle_time must be in [0, 10] s");
}

int settleTicks(const EnvOptions& o) { return static_cast<int>(std::lround(o.settle_time / o.world.control_dt)); }

EnvOptions parseEnvOptions(const std::string& yaml_text, const std::string& source) {
  const YAML::Node root = parse(yaml_text, source);
  EnvOptions o;
  // The agent acts every step: a silent driver is its own business, not the simulator's.
  o.world.control_timeout = 0.0;
  Section s(root, "", source);
  s.read("control_dt", &o.world.control_dt);
  s.read("physics_dt", &o.world.physics_dt);
  std::string spawn = "random";
  s.read("spawn", &spawn);
  if (spawn != "random" && spawn != "grid") s.fail("spawn", "must be random or grid, not '" + spawn + "'");
  o.spawn = spawn == "grid" ? SpawnMode::kGrid : SpawnMode::kRandom;
  s.read("spawn_lateral", &o.spawn_lateral);
  s.read("settle_time", &o.settle_time);
  Section action = s.child("action");
  action.read("manual_gears", &o.action.manual_gears);
  action.finish();
  readObservation(s.child("observation"), &o.observation);
  Section reward = s.child("reward");
  reward.read("progress_weight", &o.reward.progress_weight);
  reward.read("centre_weight", &o.reward.centre_weight);
  reward.read("backwards_weight", &o.reward.backwards_weight);
  reward.read("step_penalty", &o.reward.step_penalty);
  reward.read("collision_penalty_scale", &o.reward.collision_penalty_scale);
  reward.read("collision_penalty_cap", &o.reward.collision_penalty_cap);
  reward.read("off_track_penalty", &o.reward.off_track_penalty);
  reward.finish();
  Section termination = s.child("termination");
  termination.read("collision_threshold", &o.termination.collision_threshold);
  termination.read("off_track_margin", &o.termination.off_track_margin);
  termination.read("time_limit", &o.termination.time_limit);
  termination.read("stall_time", &o.termination.stall_time);
  termination.read("max_backwards", &o.termination.max_backwards);
  termination.finish();
  s.finish();
  rethrowAs(source, [&] { validate(o); });
  return o;
}

EnvOptions readEnvOptions(const std::string& path) {
  return parseEnvOptions(config::readTextFile<EnvConfigError>(path, config::kMaxYamlBytes), path);
}

ObservationOptions parseObservationOptions(const std::string& yaml_text, const std::string& source) {
  ObservationOptions o;
  readObservation(Section(parse(yaml_text, source), "observation", source), &o);
  rethrowAs(source, [&] { rl::validate(o); });
  return o;
}

std::string toYaml(const ObservationOptions& o) {
  YAML::Emitter out;
  out << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "speed" << YAML::Value << o.speed;
  out << YAML::Key << "velocity" << YAML::Value << o.velocity;
  out << YAML::Key << "angular_velocity" << YAML::Value << o.angular_velocity;
  out << YAML::Key << "imu" << YAML::Value << o.imu;
  out << YAML::Key << "waypoint_distances" << YAML::Value << YAML::Flow << o.waypoint_distances;
  out << YAML::Key << "lidar" << YAML::Value << YAML::BeginMap << YAML::Key << "beams" << YAML::Value << o.lidar.beams
      << YAML::Key << "max_range" << YAML::Value << o.lidar.max_range << YAML::Key << "fov" << YAML::Value
      << o.lidar.fov_deg << YAML::Key << "height" << YAML::Value << o.lidar.height << YAML::EndMap;
  out << YAML::Key << "camera" << YAML::Value << YAML::BeginMap << YAML::Key << "width" << YAML::Value << o.camera.width
      << YAML::Key << "height" << YAML::Value << o.camera.height << YAML::Key << "fov" << YAML::Value
      << o.camera.fov_deg << YAML::Key << "rgb" << YAML::Value << o.camera.rgb << YAML::Key << "depth" << YAML::Value
      << o.camera.depth << YAML::Key << "max_depth" << YAML::Value << o.camera.max_depth << YAML::EndMap;
  out << YAML::EndMap;
  return out.c_str();
}

}  // namespace roar::rl

#include "roar/ros/rl_msg_conversion.h"

#include <functional>

namespace roar::ros_bridge {

namespace {

// Calls leaf(key, space) for every non-Dict entry, in flattening order.
void forEachLeaf(const rl::Space& space, const std::string& prefix,
                 const std::function<void(const std::string&, const rl::Space&)>& leaf) {
  if (space.kind != rl::Space::Kind::kDict) {
    leaf(prefix, space);
    return;
  }
  for (std::size_t i = 0; i < space.keys.size(); ++i) {
    forEachLeaf(space.entries[i], prefix.empty() ? space.keys[i] : prefix + "/" + space.keys[i], leaf);
  }
}

const rl::Value& leafValue(const rl::Value& value, const std::string& key) {
  const std::size_t slash = key.find('/');
  if (slash == std::string::npos) return value.at(key);
  return leafValue(value.at(key.substr(0, slash)), key.substr(slash + 1));
}

rl::Value& leafValue(rl::Value& value, const std::string& key) {
  const std::size_t slash = key.find('/');
  if (slash == std::string::npos) return value.at(key);
  return leafValue(value.at(key.substr(0, slash)), key.substr(slash + 1));
}

}  // namespace

roar_ros::SpaceDescription toMessage(const rl::Space& space) {
  roar_ros::SpaceDescription msg;
  msg.yaml = rl::toYaml(space);
  msg.flat_dim = static_cast<std::uint32_t>(space.flatDim());
  forEachLeaf(space, "", [&](const std::string& key, const rl::Space& leaf) {
    roar_ros::SpaceEntry e;
    e.key = key;
    e.type = rl::kindName(leaf.kind);
    e.dtype = leaf.kind == rl::Space::Kind::kMultiBinary ? "int8" : rl::dtypeName(leaf.dtype);
    e.shape.assign(leaf.shape.begin(), leaf.shape.end());
    e.low = leaf.low;
    e.high = leaf.high;
    e.n = leaf.n;
    e.start = leaf.start;
    msg.entries.push_back(e);
  });
  return msg;
}

roar_ros::Observation toObservation(const rl::Space& space, const rl::Value& observation, const ros::Time& stamp) {
  roar_ros::Observation msg;
  msg.header.stamp = stamp;
  forEachLeaf(space, "", [&](const std::string& key, const rl::Space&) {
    roar_ros::ObservationEntry e;
    e.key = key;
    const auto& numbers = leafValue(observation, key).numbers;
    e.data.assign(numbers.begin(), numbers.end());
    msg.entries.push_back(std::move(e));
  });
  return msg;
}

rl::Value fromMessage(const rl::Space& space, const roar_ros::Observation& msg) {
  rl::Value value;
  std::size_t next = 0;
  forEachLeaf(space, "", [&](const std::string& key, const rl::Space& leaf) {
    if (next >= msg.entries.size() || msg.entries[next].key != key) {
      throw rl::SpaceError("observation message: entry " + std::to_string(next) + " should be '" + key + "'");
    }
    const auto& data = msg.entries[next++].data;
    if (data.size() != leaf.elements()) {
      throw rl::SpaceError("observation message: '" + key + "' has " + std::to_string(data.size()) + " numbers, not " +
                           std::to_string(leaf.elements()));
    }
    leafValue(value, key).numbers.assign(data.begin(), data.end());
  });
  if (next != msg.entries.size()) throw rl::SpaceError("observation message: more entries than the space has");
  return value;
}

roar_ros::EpisodeStep toEpisodeStep(const rl::StepOutcome& outcome, const ros::Time& stamp) {
  roar_ros::EpisodeStep msg;
  msg.header.stamp = stamp;
  msg.reward = outcome.reward;
  msg.terminated = outcome.terminated;
  msg.truncated = outcome.truncated;
  const rl::StepInfo& i = outcome.info;
  msg.episode_steps = i.episode_steps;
  msg.episode_return = i.episode_return;
  msg.progress = i.progress;
  msg.track_s = i.track_s;
  msg.lateral = i.lateral;
  msg.speed = i.speed;
  msg.collision_impulse = i.collision_impulse;
  msg.collided = i.collided;
  msg.off_track = i.off_track;
  msg.laps = i.laps;
  msg.last_lap_time = i.last_lap_time;
  return msg;
}

}  // namespace roar::ros_bridge

#pragma once
// Follows the map roar_sim simulates (its latched /roar_sim/map): a map loaded or reloaded at run time is
// read and handed on; the start message of the map already in use changes nothing; a map that cannot be
// read is logged and the one in use kept; a map published by any node but roar_sim is ignored, said once
// (test_roar_py_ros test_a_map_published_by_another_node_is_not_followed). waypoint_server and race_control
// follow roar_sim's map so.
#include <roar_ros/MapInfo.h>
#include <ros/ros.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "roar/track/track.h"

namespace roar::ros_bridge {

class SimMapFollower {
 public:
  using OnMap = std::function<void(std::unique_ptr<track::Track>, const roar_ros::MapInfo&)>;
  // folder: the map the node starts with; node: its name, for the log.
  SimMapFollower(ros::NodeHandle& nh, std::string folder, std::string node, OnMap on_map);
  const std::string& folder() const { return folder_; }

 private:
  void onMap(const ros::MessageEvent<const roar_ros::MapInfo>& event);

  std::string folder_, node_;
  std::uint32_t generation_ = 0;
  OnMap on_map_;
  ros::Subscriber sub_;
  bool warned_of_other_publisher_ = false;
};

}  // namespace roar::ros_bridge

#include "roar/ros/sim_map_follower.h"

#include <utility>

#include "roar/track/map_folder.h"

namespace roar::ros_bridge {

SimMapFollower::SimMapFollower(ros::NodeHandle& nh, std::string folder, std::string node, OnMap on_map)
    : folder_(std::move(folder)), node_(std::move(node)), on_map_(std::move(on_map)) {
  sub_ = nh.subscribe("/roar_sim/map", 1, &SimMapFollower::onMap, this);
}

void SimMapFollower::onMap(const roar_ros::MapInfo& info) {
  if (info.folder == folder_ && info.generation <= generation_) return;
  std::unique_ptr<track::Track> track;
  try {
    track = std::make_unique<track::Track>(track::loadMapFolder(info.folder));
  } catch (const std::exception& e) {
    ROS_ERROR("%s: roar_sim's map '%s' (%s) could not be read; the map in use stays: %s", node_.c_str(),
              info.name.c_str(), info.folder.c_str(), e.what());
    return;
  }
  folder_ = info.folder;
  generation_ = info.generation;
  on_map_(std::move(track), info);
}

}  // namespace roar::ros_bridge

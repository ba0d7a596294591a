#include "roar/ros/sim_map_follower.h"

#include <utility>

#include "roar/track/map_folder.h"

namespace roar::ros_bridge {

SimMapFollower::SimMapFollower(ros::NodeHandle& nh, std::string folder, std::string node, OnMap on_map)
    : folder_(std::move(folder)), node_(std::move(node)), on_map_(std::move(on_map)) {
  sub_ = nh.subscribe("/roar_sim/map", 1, &SimMapFollower::onMap, this);
}

namespace {
constexpr char kSimNode[] = "/roar_sim";
}  // namespace

void SimMapFollower::onMap(const ros::MessageEvent<const roar_ros::MapInfo>& event) {
  if (event.getPublisherName() != kSimNode) {
    if (!warned_of_other_publisher_) {
      ROS_WARN("%s: ignoring /roar_sim/map from %s: only roar_sim's map is followed", node_.c_str(),
               event.getPublisherName().c_str());
      warned_of_other_publisher_ = true;
    }
    return;
  }
  const roar_ros::MapInfo& info = *event.getMessage();
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

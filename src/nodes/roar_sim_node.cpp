#include <ros/ros.h>

#include "../ros/sim_node.h"
#include "roar/ros/param_reading.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "roar_sim");
  ros::NodeHandle nh, private_nh("~");
  try {
    roar::ros_bridge::SimNode node(nh, private_nh, roar::ros_bridge::readSimParameters(private_nh));
    roar::ros_bridge::refuseUnknownParameters(private_nh);
    node.run();
  } catch (const std::exception& e) {
    ROS_FATAL("roar_sim: %s", e.what());
    return 1;
  }
  return 0;
}

// car_models: every car of the race as its URDF model, for rviz and for a recording's replay. For each car
// it sets /<car>/robot_description (rviz's RobotModel reads it) and runs robot_state_publisher's own
// RobotStatePublisher on roar_sim's /<car>/joint_states (wheel rotation, steering), publishing the links
// as <car>/<link> frames under <car>/base_link. One node for all cars, because a launch file cannot repeat
// robot_state_publisher for a list of cars that only the scenario file knows.
#include <robot_state_publisher/robot_state_publisher.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <urdf/model.h>
#include <kdl_parser/kdl_parser.hpp>

#include <Eigen/Core>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <sstream>

#include "roar/config/text_file.h"
#include "roar/ros/param_reading.h"
#include "roar/ros/scenario_params.h"
#include "roar/sensors/camera.h"

using namespace roar;

namespace {

struct CarModel {
  std::string name;
  std::string model;
  Eigen::Vector3f colour = Eigen::Vector3f(-1, -1, -1);  // linear RGB of the body; negative: the URDF's
};

struct CarModelsOptions {
  std::vector<CarModel> cars;
  std::string urdf_dir;
  // false: no frames from /<car>/joint_states (a replay, whose bag holds them on /tf: publishing them again
  // makes rviz drop both as TF_REPEATED_DATA).
  bool joint_frames = true;
};

CarModelsOptions readParameters(const ros::NodeHandle& nh) {
  using namespace ros_bridge;
  CarModelsOptions o;
  o.urdf_dir = readString(nh, "urdf_dir", packageLayout().urdf());
  o.joint_frames = readBool(nh, "joint_frames", true);
  for (const auto& car : readRaceCars(nh, readScenario(nh), readString(nh, "model", config::kDefaultModel))) {
    o.cars.push_back({car.name, car.model, car.colour});
  }
  return o;
}

// The URDF with its "body" material painted the car's colour (the colour roar_sim's cameras see).
std::string painted(std::string urdf_text, const Eigen::Vector3f& linear_rgb) {
  if ((linear_rgb.array() < 0).any()) return urdf_text;
  static const std::regex body_colour(R"re(<material\s+name="body"\s*>\s*<color\s+rgba="([^"]*)")re");
  std::smatch match;
  if (!std::regex_search(urdf_text, match, body_colour)) return urdf_text;
  char rgba[64];
  // The cameras' own gamma encoding, so that rviz shows the colour the cameras see.
  auto screen = [](float c) { return sensors::gammaEncode(c) / 255.0; };
  std::snprintf(rgba, sizeof(rgba), "%.3f %.3f %.3f 1", screen(linear_rgb.x()), screen(linear_rgb.y()),
                screen(linear_rgb.z()));
  return urdf_text.replace(static_cast<std::size_t>(match.position(1)), static_cast<std::size_t>(match.length(1)),
                           rgba);
}

std::string readFile(const std::string& path) {
  return config::readTextFile<ros_bridge::ParamError>(path, config::kMaxUrdfBytes);
}

class CarModelsNode {
 public:
  CarModelsNode(ros::NodeHandle& nh, const CarModelsOptions& options) {
    for (const auto& car : options.cars) {
      const std::string path = options.urdf_dir + "/" + car.model + ".urdf";
      const std::string urdf_text = painted(readFile(path), car.colour);
      urdf::Model model;
      KDL::Tree tree;
      if (!model.initString(urdf_text) || !kdl_parser::treeFromUrdfModel(model, tree)) {
        throw ros_bridge::ParamError("car '" + car.name + "': the URDF " + path + " does not parse");
      }
      nh.setParam(car.name + "/robot_description", urdf_text);
      auto publisher = std::make_shared<robot_state_publisher::RobotStatePublisher>(tree, model);
      publisher->publishFixedTransforms(car.name, true);
      publishers_.push_back(publisher);
      ROS_INFO("car_models: %s is a %s (%s)", car.name.c_str(), car.model.c_str(), path.c_str());
      if (!options.joint_frames) continue;
      const std::string prefix = car.name;
      subs_.push_back(nh.subscribe<sensor_msgs::JointState>(
          car.name + "/joint_states", 20, [publisher, prefix](const sensor_msgs::JointState::ConstPtr& msg) {
            std::map<std::string, double> positions;
            for (std::size_t i = 0; i < msg->name.size() && i < msg->position.size(); ++i) {
              positions[msg->name[i]] = msg->position[i];
            }
            publisher->publishTransforms(positions, msg->header.stamp, prefix);
          }));
    }
  }

 private:
  std::vector<std::shared_ptr<robot_state_publisher::RobotStatePublisher>> publishers_;
  std::vector<ros::Subscriber> subs_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "car_models");
  ros::NodeHandle nh, private_nh("~");
  try {
    CarModelsNode node(nh, readParameters(private_nh));
    ros_bridge::refuseUnknownParameters(private_nh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("car_models: %s", e.what());
    return 1;
  }
  return 0;
}

#pragma once
// Every parameter of the roar_sim node, read and validated in one place.
#include <ros/node_handle.h>

#include <string>
#include <vector>

#include "roar/config/package_layout.h"
#include "roar/ros/frames.h"
#include "roar/sim/world.h"

namespace roar::ros_bridge {

enum class SteppingMode {
  kAsync,     // free run at real_time_factor (0: as fast as possible)
  kStep,      // time advances only through the ~step service
  kLockstep,  // each tick waits for a control stamped with the previous tick's time from every connected driver
};

struct VehicleSpawn {
  std::string name;
  std::string model;
  int spawn_point = 0;
  std::string sensor_set;                                // a set in sensors_dir or a YAML path; empty: no sensors
  Eigen::Vector3f colour = Eigen::Vector3f(-1, -1, -1);  // linear RGB; negative: the n-th of a palette
  std::string agent;   // an RL environment file: an agent drives the car through the RL interface
  bool driven = true;  // the racing stack (its controller, or a policy_driver in its place) drives it
};

struct SimNodeOptions {
  std::string map_folder;
  std::string maps_dir;  // where /roar_sim/load_map and list_maps look maps up by name
  std::string urdf_dir;
  std::string vehicle_config_dir;
  std::string default_model = config::kDefaultModel;
  std::string sensors_dir;
  std::string default_sensor_set;  // for vehicles that name none
  std::string rl_dir;              // RL environments named by a vehicle's agent
  std::string map_frame = kMapFrame;
  sim::WorldOptions world;
  SteppingMode mode = SteppingMode::kAsync;
  double real_time_factor = 1.0;
  double start_wait = 0.5;  // wall seconds between start-up and the first state
  // Nodes (rosbag recorders) that must subscribe to /clock and every car's odom, vehicle_status and
  // control before the first tick, so a recording starts at tick 0.
  std::vector<std::string> wait_for_recorders;
  // Nodes that must subscribe to /clock and every car's odom before the first tick (race_control), so that
  // they see the race from its start: a node that came late began its race at the tick it first heard.
  std::vector<std::string> wait_for_listeners;
  // Lockstep: before the first tick, wait for a driver of every driven car (a publisher on its control
  // topic) and for every subscriber of its odometry to connect, so a race starts alike every time: a
  // driver that came late missed the first tick and its car stood still until lockstep_timeout.
  bool wait_for_drivers = false;
  double lockstep_timeout = 5.0;  // wall seconds a tick waits for a connected driver before going on without it
  std::vector<VehicleSpawn> vehicles;
};

// Throws ParamError naming the parameter.
SimNodeOptions readSimParameters(const ros::NodeHandle& private_nh);

}  // namespace roar::ros_bridge

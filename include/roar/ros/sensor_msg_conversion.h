#pragma once
// Sensor readings and the simulator's contacts (ROS-free core types) -> standard ROS messages.
#include <geometry_msgs/PointStamped.h>
#include <geometry_msgs/TwistStamped.h>
#include <geometry_msgs/Vector3Stamped.h>
#include <roar_ros/BlueprintInfo.h>
#include <roar_ros/CollisionEvent.h>
#include <roar_ros/VehicleInfo.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/NavSatFix.h>
#include <sensor_msgs/PointCloud2.h>

#include "roar/sensors/camera.h"
#include "roar/sensors/inertial.h"
#include "roar/sensors/lidar.h"
#include "roar/sensors/occupancy_map.h"
#include "roar/sensors/radar.h"
#include "roar/sensors/sensor_spec.h"
#include "roar/sim/world.h"
#include "roar/vehicle/vehicle_config.h"

namespace roar::ros_bridge {

// One channel of a camera frame: rgb8, mono8 (grey), 32FC1 (depth, metres) or mono8 (semantic class ids).
sensor_msgs::Image toImage(const sensors::CameraFrame& frame, sensors::SensorType type, const ros::Time& stamp,
                           const std::string& optical_frame);
sensor_msgs::CameraInfo toCameraInfo(const sensors::CameraIntrinsics& k, const ros::Time& stamp,
                                     const std::string& optical_frame);
// x, y, z, intensity as float32, 16 bytes a point, in the sensor's frame.
sensor_msgs::PointCloud2 toPointCloud2(const std::vector<sensors::LidarPoint>& points, const ros::Time& stamp,
                                       const std::string& frame);
// CARLA's radar measurement as a cloud: velocity, azimuth, altitude, depth as float32, 16 bytes a detection.
sensor_msgs::PointCloud2 toRadarCloud(const std::vector<sensors::RadarDetection>& detections, const ros::Time& stamp,
                                      const std::string& frame);
sensor_msgs::Imu toImu(const sensors::ImuSample& sample, const sensors::ImuSpec& spec, const ros::Time& stamp,
                       const std::string& frame);
sensor_msgs::NavSatFix toNavSatFix(const sensors::GnssFix& fix, const sensors::GnssSpec& spec, const ros::Time& stamp,
                                   const std::string& frame);
geometry_msgs::TwistStamped toTwist(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular,
                                    const ros::Time& stamp, const std::string& frame);
// Accelerometer, gyroscope and roll-pitch-yaw readings; a location is a point.
geometry_msgs::Vector3Stamped toVector3Stamped(const Eigen::Vector3d& v, const ros::Time& stamp,
                                               const std::string& frame);
Eigen::Vector3d fromMessage(const geometry_msgs::Vector3Stamped& msg);
geometry_msgs::PointStamped toPointStamped(const Eigen::Vector3d& p, const ros::Time& stamp, const std::string& frame);
Eigen::Vector3d fromMessage(const geometry_msgs::PointStamped& msg);
// The occupancy map as a mono8 image, row 0 the farthest ahead.
sensor_msgs::Image toImage(const sensors::OccupancyFrame& frame, const ros::Time& stamp, const std::string& frame_id);
sensors::OccupancyFrame occupancyFromImage(const sensor_msgs::Image& image);  // throws for another encoding
// A contact of the car's body as CARLA's collision sensor reports it.
roar_ros::CollisionEvent toCollisionEvent(const sim::Contact& contact, const ros::Time& stamp,
                                          const std::string& map_frame);
// A spawned car as /roar_sim/get_world_info lists it: its model, blueprint, half extents, gears, sensors and
// the RL environment of the agent that drives it ("": none).
roar_ros::VehicleInfo toVehicleInfo(const std::string& name, const vehicle::VehicleParams& params,
                                    const std::vector<sensors::SensorSpec>& sensors, const std::string& agent);
roar_ros::BlueprintInfo toBlueprintInfo(const vehicle::VehicleModelInfo& model);

}  // namespace roar::ros_bridge

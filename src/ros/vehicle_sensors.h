#pragma once
// The sensors of one simulated car on ROS (or the world's own, AttachSensor's WORLD in place of <vehicle>):
// its SensorRig, and the publishers its readings go to.
//   cameras   <vehicle>/camera/<name>/image (+ camera_info), frame <vehicle>/<name>_optical (image_transport);
//             an on-demand camera publishes only while its topic has a subscriber (/roar_sim/render_sensor
//             renders its frames for the asking)
//   lidar     <vehicle>/lidar/<name>/points, frame <vehicle>/<name>
//   imu, gnss <vehicle>/<name>, frame <vehicle>/<name>
//   velocimeter <vehicle>/<name>/twist (sensor frame) and <vehicle>/<name>/twist_map (map frame)
//   accelerometer, gyroscope  <vehicle>/<name> (geometry_msgs/Vector3Stamped, sensor frame or map)
//   roll_pitch_yaw            <vehicle>/<name> (geometry_msgs/Vector3Stamped: roll, pitch, yaw in rad, of the
//                             sensor frame in map)
//   location                  <vehicle>/<name> (geometry_msgs/PointStamped, map frame)
//   occupancy_map             <vehicle>/occupancy_map/<name>/image (mono8), frame <vehicle>/<name>
//   radar     <vehicle>/radar/<name>/detections (velocity, azimuth, altitude, depth), frame <vehicle>/<name>
#include <geometry_msgs/TransformStamped.h>
#include <image_transport/image_transport.h>
#include <ros/ros.h>

#include <map>
#include <string>

#include "roar/sensors/sensor_rig.h"

namespace roar::ros_bridge {

class VehicleSensors : public sensors::SensorSink {
 public:
  // `host` names the topics and frames (a car, or AttachSensor's WORLD); the mounts are in parent_frame
  // (the car's base frame, or the map's), within `bounds`.
  VehicleSensors(ros::NodeHandle nh, std::string host, std::string parent_frame, const sensors::RigTiming& timing,
                 const track::GeoOrigin& origin, std::string map_frame,
                 const sensors::MountBounds& bounds = sensors::kOnACar);

  // Throws sensors::SensorSpecError naming the sensor and field.
  void attach(const sensors::SensorSpec& spec, double now);
  bool detach(const std::string& name);
  // base_link -> sensor frames (and camera optical frames), for the static tf broadcaster.
  std::vector<geometry_msgs::TransformStamped> staticTransforms() const;
  bool empty() const { return publishers_.empty(); }

  sensors::SensorRig& rig() { return rig_; }
  const sensors::MountBounds& bounds() const { return rig_.bounds(); }
  const sensors::SensorRig& rig() const { return rig_; }

  void camera(const sensors::SensorSpec& spec, double stamp, const sensors::CameraFrame& frame,
              const sensors::CameraIntrinsics& k) override;
  void lidar(const sensors::SensorSpec& spec, double stamp, const std::vector<sensors::LidarPoint>& points) override;
  void imu(const sensors::SensorSpec& spec, double stamp, const sensors::ImuSample& sample) override;
  void gnss(const sensors::SensorSpec& spec, double stamp, const sensors::GnssFix& fix) override;
  void velocity(const sensors::SensorSpec& spec, double stamp, const sensors::Velocity& v) override;
  void vector(const sensors::SensorSpec& spec, double stamp, const Eigen::Vector3d& reading) override;
  void occupancy(const sensors::SensorSpec& spec, double stamp, const sensors::OccupancyFrame& frame) override;
  void radar(const sensors::SensorSpec& spec, double stamp,
             const std::vector<sensors::RadarDetection>& detections) override;
  // An on-demand camera is rendered at its tick when its topic has a subscriber (rviz, rosbag).
  bool wanted(const sensors::SensorSpec& spec) override;
  void deferred(const sensors::SensorSpec& spec, double stamp) override;
  // The stamp of each sensor's newest reading (0 before its first), by sensor name.
  const std::map<std::string, double>& lastStamps() const { return last_stamps_; }

 private:
  struct Publishers {
    image_transport::CameraPublisher camera;
    image_transport::Publisher image;
    ros::Publisher main, second;
  };
  std::string frameOf(const sensors::SensorSpec& spec) const { return host_ + "/" + spec.name; }

  ros::NodeHandle nh_;
  image_transport::ImageTransport it_;
  std::string host_;
  std::string parent_frame_;
  std::string map_frame_;
  sensors::SensorRig rig_;
  std::map<std::string, Publishers> publishers_;
  std::map<std::string, double> last_stamps_;
};

}  // namespace roar::ros_bridge

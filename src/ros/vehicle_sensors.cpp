#include "vehicle_sensors.h"

#include <geometry_msgs/TwistStamped.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/NavSatFix.h>
#include <sensor_msgs/PointCloud2.h>

#include "roar/ros/frames.h"
#include "roar/ros/msg_conversion.h"
#include "roar/ros/queues.h"
#include "roar/ros/sensor_msg_conversion.h"

namespace roar::ros_bridge {

namespace {

geometry_msgs::TransformStamped transformMsg(const Eigen::Isometry3d& t, const std::string& parent,
                                             const std::string& child) {
  track::Pose pose;
  pose.position = t.translation();
  pose.orientation = Eigen::Quaterniond(t.linear());
  return toTransform(pose, ros::Time(0), parent, child);
}

}  // namespace

VehicleSensors::VehicleSensors(ros::NodeHandle nh, std::string host, std::string parent_frame,
                               const sensors::RigTiming& timing, const track::GeoOrigin& origin, std::string map_frame,
                               const sensors::MountBounds& bounds)
    : nh_(nh),
      it_(nh),
      host_(std::move(host)),
      parent_frame_(std::move(parent_frame)),
      map_frame_(std::move(map_frame)),
      rig_({}, timing, origin, 0.0, bounds) {}

void VehicleSensors::attach(const sensors::SensorSpec& spec, double now) {
  rig_.add(spec, now);  // validates first: nothing is advertised for a sensor the rig refuses
  Publishers p;
  const std::string base = host_ + "/";
  const int queue = ros_bridge::sensorQueue(spec.rate);
  switch (spec.type) {
    case sensors::SensorType::kLidar:
      p.main = nh_.advertise<sensor_msgs::PointCloud2>(base + "lidar/" + spec.name + "/points", queue);
      break;
    case sensors::SensorType::kRadar:
      p.main = nh_.advertise<sensor_msgs::PointCloud2>(base + "radar/" + spec.name + "/detections", queue);
      break;
    case sensors::SensorType::kImu:
      p.main = nh_.advertise<sensor_msgs::Imu>(base + spec.name, queue);
      break;
    case sensors::SensorType::kGnss:
      p.main = nh_.advertise<sensor_msgs::NavSatFix>(base + spec.name, queue);
      break;
    case sensors::SensorType::kVelocimeter:
      p.main = nh_.advertise<geometry_msgs::TwistStamped>(base + spec.name + "/twist", queue);
      p.second = nh_.advertise<geometry_msgs::TwistStamped>(base + spec.name + "/twist_map", queue);
      break;
    case sensors::SensorType::kAccelerometer:
    case sensors::SensorType::kGyroscope:
    case sensors::SensorType::kRollPitchYaw:
      p.main = nh_.advertise<geometry_msgs::Vector3Stamped>(base + spec.name, queue);
      break;
    case sensors::SensorType::kLocation:
      p.main = nh_.advertise<geometry_msgs::PointStamped>(base + spec.name, queue);
      break;
    case sensors::SensorType::kOccupancyMap:
      p.image = it_.advertise(base + "occupancy_map/" + spec.name + "/image", queue);
      break;
    default:
      p.camera = it_.advertiseCamera(base + "camera/" + spec.name + "/image", queue);
      break;
  }
  publishers_[spec.name] = p;
  last_stamps_[spec.name] = 0.0;
}

bool VehicleSensors::detach(const std::string& name) {
  if (!rig_.remove(name)) return false;
  publishers_.erase(name);
  last_stamps_.erase(name);
  return true;
}

std::vector<geometry_msgs::TransformStamped> VehicleSensors::staticTransforms() const {
  std::vector<geometry_msgs::TransformStamped> out;
  for (const auto& spec : rig_.specs()) {
    out.push_back(transformMsg(sensors::mountTransform(spec.mount), parent_frame_, frameOf(spec)));
    if (sensors::isCamera(spec.type)) {
      Eigen::Isometry3d optical = Eigen::Isometry3d::Identity();
      optical.linear() = sensors::opticalFromBody().transpose();
      out.push_back(transformMsg(optical, frameOf(spec), frameOf(spec) + "_optical"));
    }
  }
  return out;
}

void VehicleSensors::camera(const sensors::SensorSpec& spec, double stamp, const sensors::CameraFrame& frame,
                            const sensors::CameraIntrinsics& k) {
  auto& pub = publishers_.at(spec.name).camera;
  last_stamps_[spec.name] = stamp;
  if (pub.getNumSubscribers() == 0) return;  // converting 800x600 frames nobody reads is wasted time
  const ros::Time t = toRosTime(stamp);
  const std::string optical = frameOf(spec) + "_optical";
  pub.publish(toImage(frame, spec.type, t, optical), toCameraInfo(k, t, optical));
}

bool VehicleSensors::wanted(const sensors::SensorSpec& spec) {
  return publishers_.at(spec.name).camera.getNumSubscribers() > 0;
}

void VehicleSensors::deferred(const sensors::SensorSpec& spec, double stamp) { last_stamps_[spec.name] = stamp; }

void VehicleSensors::lidar(const sensors::SensorSpec& spec, double stamp,
                           const std::vector<sensors::LidarPoint>& points) {
  last_stamps_[spec.name] = stamp;
  publishers_.at(spec.name).main.publish(toPointCloud2(points, toRosTime(stamp), frameOf(spec)));
}

void VehicleSensors::radar(const sensors::SensorSpec& spec, double stamp,
                           const std::vector<sensors::RadarDetection>& detections) {
  last_stamps_[spec.name] = stamp;
  publishers_.at(spec.name).main.publish(toRadarCloud(detections, toRosTime(stamp), frameOf(spec)));
}

void VehicleSensors::imu(const sensors::SensorSpec& spec, double stamp, const sensors::ImuSample& sample) {
  last_stamps_[spec.name] = stamp;
  publishers_.at(spec.name).main.publish(toImu(sample, spec.imu, toRosTime(stamp), frameOf(spec)));
}

void VehicleSensors::gnss(const sensors::SensorSpec& spec, double stamp, const sensors::GnssFix& fix) {
  last_stamps_[spec.name] = stamp;
  publishers_.at(spec.name).main.publish(toNavSatFix(fix, spec.gnss, toRosTime(stamp), frameOf(spec)));
}

void VehicleSensors::velocity(const sensors::SensorSpec& spec, double stamp, const sensors::Velocity& v) {
  const ros::Time t = toRosTime(stamp);
  last_stamps_[spec.name] = stamp;
  auto& p = publishers_.at(spec.name);
  p.main.publish(toTwist(v.linear_body, v.angular_body, t, frameOf(spec)));
  p.second.publish(toTwist(v.linear_world, v.angular_world, t, map_frame_));
}

void VehicleSensors::vector(const sensors::SensorSpec& spec, double stamp, const Eigen::Vector3d& reading) {
  const ros::Time t = toRosTime(stamp);
  last_stamps_[spec.name] = stamp;
  auto& pub = publishers_.at(spec.name).main;
  if (spec.type == sensors::SensorType::kLocation) {
    pub.publish(toPointStamped(reading, t, map_frame_));
  } else {
    const bool in_map = spec.type == sensors::SensorType::kRollPitchYaw || spec.vector.map_frame;
    pub.publish(toVector3Stamped(reading, t, in_map ? map_frame_ : frameOf(spec)));
  }
}

void VehicleSensors::occupancy(const sensors::SensorSpec& spec, double stamp, const sensors::OccupancyFrame& frame) {
  last_stamps_[spec.name] = stamp;
  auto& pub = publishers_.at(spec.name).image;
  if (pub.getNumSubscribers() == 0) return;
  pub.publish(toImage(frame, toRosTime(stamp), frameOf(spec)));
}

}  // namespace roar::ros_bridge

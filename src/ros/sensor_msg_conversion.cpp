#include "roar/ros/sensor_msg_conversion.h"

#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <cstring>

namespace roar::ros_bridge {

namespace {

void fill(geometry_msgs::Vector3& out, const Eigen::Vector3d& v) {
  out.x = v.x();
  out.y = v.y();
  out.z = v.z();
}

// Ground truth has no variance; a tiny one keeps consumers that invert covariances finite.
double variance(double std) { return std > 0 ? std * std : 1e-9; }

}  // namespace

sensor_msgs::Image toImage(const sensors::CameraFrame& frame, sensors::SensorType type, const ros::Time& stamp,
                           const std::string& optical_frame) {
  namespace enc = sensor_msgs::image_encodings;
  sensor_msgs::Image img;
  img.header.stamp = stamp;
  img.header.frame_id = optical_frame;
  img.width = static_cast<unsigned>(frame.width);
  img.height = static_cast<unsigned>(frame.height);
  img.is_bigendian = 0;
  const std::uint8_t* data = nullptr;
  std::size_t bytes = 0;
  switch (type) {
    case sensors::SensorType::kCameraRgb:
      img.encoding = enc::RGB8;
      img.step = 3 * img.width;
      data = frame.rgb.data();
      bytes = frame.rgb.size();
      break;
    case sensors::SensorType::kCameraGrey:
      img.encoding = enc::MONO8;
      img.step = img.width;
      data = frame.grey.data();
      bytes = frame.grey.size();
      break;
    case sensors::SensorType::kCameraDepth:
      img.encoding = enc::TYPE_32FC1;
      img.step = 4 * img.width;
      data = reinterpret_cast<const std::uint8_t*>(frame.depth.data());
      bytes = frame.depth.size() * sizeof(float);
      break;
    default:
      img.encoding = enc::MONO8;
      img.step = img.width;
      data = frame.semantic.data();
      bytes = frame.semantic.size();
      break;
  }
  img.data.assign(data, data + bytes);
  return img;
}

sensor_msgs::CameraInfo toCameraInfo(const sensors::CameraIntrinsics& k, const ros::Time& stamp,
                                     const std::string& optical_frame) {
  sensor_msgs::CameraInfo info;
  info.header.stamp = stamp;
  info.header.frame_id = optical_frame;
  info.width = static_cast<unsigned>(k.width);
  info.height = static_cast<unsigned>(k.height);
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {k.fx, 0, k.cx, 0, 0, k.fy, k.cy, 0, 0, 0, 1, 0};
  return info;
}

sensor_msgs::PointCloud2 toPointCloud2(const std::vector<sensors::LidarPoint>& points, const ros::Time& stamp,
                                       const std::string& frame) {
  static_assert(sizeof(sensors::LidarPoint) == 16, "x, y, z, intensity as four packed floats");
  sensor_msgs::PointCloud2 cloud;
  cloud.header.stamp = stamp;
  cloud.header.frame_id = frame;
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2Fields(4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32,
                                "z", 1, sensor_msgs::PointField::FLOAT32, "intensity", 1,
                                sensor_msgs::PointField::FLOAT32);
  modifier.resize(points.size());
  cloud.height = 1;
  cloud.width = static_cast<unsigned>(points.size());
  cloud.is_dense = true;
  if (!points.empty()) std::memcpy(cloud.data.data(), points.data(), points.size() * sizeof(sensors::LidarPoint));
  return cloud;
}

sensor_msgs::PointCloud2 toRadarCloud(const std::vector<sensors::RadarDetection>& detections, const ros::Time& stamp,
                                      const std::string& frame) {
  static_assert(sizeof(sensors::RadarDetection) == 16, "velocity, azimuth, altitude, depth as four packed floats");
  sensor_msgs::PointCloud2 cloud;
  cloud.header.stamp = stamp;
  cloud.header.frame_id = frame;
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2Fields(4, "velocity", 1, sensor_msgs::PointField::FLOAT32, "azimuth", 1,
                                sensor_msgs::PointField::FLOAT32, "altitude", 1, sensor_msgs::PointField::FLOAT32,
                                "depth", 1, sensor_msgs::PointField::FLOAT32);
  modifier.resize(detections.size());
  cloud.height = 1;
  cloud.width = static_cast<unsigned>(detections.size());
  cloud.is_dense = true;
  if (!detections.empty())
    std::memcpy(cloud.data.data(), detections.data(), detections.size() * sizeof(sensors::RadarDetection));
  return cloud;
}

sensor_msgs::Imu toImu(const sensors::ImuSample& s, const sensors::ImuSpec& spec, const ros::Time& stamp,
                       const std::string& frame) {
  sensor_msgs::Imu imu;
  imu.header.stamp = stamp;
  imu.header.frame_id = frame;
  imu.orientation.w = s.orientation.w();
  imu.orientation.x = s.orientation.x();
  imu.orientation.y = s.orientation.y();
  imu.orientation.z = s.orientation.z();
  fill(imu.angular_velocity, s.angular_velocity);
  fill(imu.linear_acceleration, s.linear_acceleration);
  for (int i = 0; i < 3; ++i) {
    imu.orientation_covariance[i * 4] = 1e-9;
    imu.angular_velocity_covariance[i * 4] = variance(spec.gyro_noise_std);
    imu.linear_acceleration_covariance[i * 4] = variance(spec.accel_noise_std);
  }
  return imu;
}

sensor_msgs::NavSatFix toNavSatFix(const sensors::GnssFix& fix, const sensors::GnssSpec& spec, const ros::Time& stamp,
                                   const std::string& frame) {
  sensor_msgs::NavSatFix msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frame;
  msg.status.status = sensor_msgs::NavSatStatus::STATUS_FIX;
  msg.status.service = sensor_msgs::NavSatStatus::SERVICE_GPS;
  msg.latitude = fix.latitude;
  msg.longitude = fix.longitude;
  msg.altitude = fix.altitude;
  msg.position_covariance = {variance(spec.horizontal_noise_std), 0, 0, 0, variance(spec.horizontal_noise_std), 0, 0, 0,
                             variance(spec.vertical_noise_std)};
  msg.position_covariance_type = sensor_msgs::NavSatFix::COVARIANCE_TYPE_DIAGONAL_KNOWN;
  return msg;
}

geometry_msgs::TwistStamped toTwist(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular,
                                    const ros::Time& stamp, const std::string& frame) {
  geometry_msgs::TwistStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = frame;
  fill(t.twist.linear, linear);
  fill(t.twist.angular, angular);
  return t;
}

geometry_msgs::Vector3Stamped toVector3Stamped(const Eigen::Vector3d& v, const ros::Time& stamp,
                                               const std::string& frame) {
  geometry_msgs::Vector3Stamped msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frame;
  fill(msg.vector, v);
  return msg;
}

Eigen::Vector3d fromMessage(const geometry_msgs::Vector3Stamped& msg) {
  return {msg.vector.x, msg.vector.y, msg.vector.z};
}

geometry_msgs::PointStamped toPointStamped(const Eigen::Vector3d& p, const ros::Time& stamp, const std::string& frame) {
  geometry_msgs::PointStamped msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frame;
  msg.point.x = p.x();
  msg.point.y = p.y();
  msg.point.z = p.z();
  return msg;
}

Eigen::Vector3d fromMessage(const geometry_msgs::PointStamped& msg) { return {msg.point.x, msg.point.y, msg.point.z}; }

sensor_msgs::Image toImage(const sensors::OccupancyFrame& frame, const ros::Time& stamp, const std::string& frame_id) {
  sensor_msgs::Image img;
  img.header.stamp = stamp;
  img.header.frame_id = frame_id;
  img.width = static_cast<unsigned>(frame.width);
  img.height = static_cast<unsigned>(frame.height);
  img.encoding = sensor_msgs::image_encodings::MONO8;
  img.is_bigendian = 0;
  img.step = img.width;
  img.data = frame.pixels;
  return img;
}

sensors::OccupancyFrame occupancyFromImage(const sensor_msgs::Image& image) {
  if (image.encoding != sensor_msgs::image_encodings::MONO8 || image.step != image.width ||
      image.data.size() != static_cast<std::size_t>(image.width) * image.height) {
    throw std::invalid_argument("an occupancy map is a mono8 image without row padding, got " + image.encoding);
  }
  sensors::OccupancyFrame frame;
  frame.width = static_cast<int>(image.width);
  frame.height = static_cast<int>(image.height);
  frame.pixels = image.data;
  return frame;
}

roar_ros::CollisionEvent toCollisionEvent(const sim::Contact& contact, const ros::Time& stamp,
                                          const std::string& map_frame) {
  roar_ros::CollisionEvent msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = map_frame;
  msg.other = contact.other;
  msg.impulse.x = contact.impulse.x();
  msg.impulse.y = contact.impulse.y();
  msg.impulse.z = contact.impulse.z();
  msg.position.x = contact.position.x();
  msg.position.y = contact.position.y();
  msg.position.z = contact.position.z();
  return msg;
}

roar_ros::VehicleInfo toVehicleInfo(const std::string& name, const vehicle::VehicleParams& params,
                                    const std::vector<sensors::SensorSpec>& sensors, const std::string& agent) {
  roar_ros::VehicleInfo info;
  info.name = name;
  info.model = params.model;
  info.blueprint = params.blueprint;
  info.extent.x = params.chassis.box_size.x() / 2;
  info.extent.y = params.chassis.box_size.y() / 2;
  info.extent.z = params.chassis.box_size.z() / 2;
  info.gears = static_cast<int>(params.gearbox.ratios.size());
  for (const auto& spec : sensors) {
    info.sensor_names.push_back(spec.name);
    info.sensor_types.push_back(sensors::typeName(spec.type));
  }
  info.agent = agent;
  return info;
}

roar_ros::BlueprintInfo toBlueprintInfo(const vehicle::VehicleModelInfo& model) {
  roar_ros::BlueprintInfo info;
  info.blueprint = model.blueprint;
  info.model = model.model;
  info.description = model.description;
  return info;
}

}  // namespace roar::ros_bridge

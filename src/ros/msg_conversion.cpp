#include "roar/ros/msg_conversion.h"

#include "roar/ros/car_label.h"
#include "roar/ros/frames.h"

#include <cmath>

namespace roar::ros_bridge {

vehicle::VehicleControl fromMessage(const roar_ros::VehicleControl& msg) {
  vehicle::VehicleControl c;
  c.throttle = msg.throttle;
  c.steer = msg.steer;
  c.brake = msg.brake;
  c.hand_brake = msg.hand_brake;
  c.reverse = msg.reverse;
  c.manual_gear_shift = msg.manual_gear_shift;
  c.gear = msg.gear;
  return c;
}

roar_ros::VehicleControl toMessage(const vehicle::VehicleControl& c) {
  roar_ros::VehicleControl msg;
  msg.throttle = static_cast<float>(c.throttle);
  msg.steer = static_cast<float>(c.steer);
  msg.brake = static_cast<float>(c.brake);
  msg.hand_brake = c.hand_brake;
  msg.reverse = c.reverse;
  msg.manual_gear_shift = c.manual_gear_shift;
  msg.gear = c.gear;
  return msg;
}

track::Pose fromMessage(const geometry_msgs::Pose& msg) {
  track::Pose pose;
  pose.position = Eigen::Vector3d(msg.position.x, msg.position.y, msg.position.z);
  const Eigen::Quaterniond q(msg.orientation.w, msg.orientation.x, msg.orientation.y, msg.orientation.z);
  if (!q.coeffs().allFinite()) {
    pose.orientation = q;  // NaN or infinite: kept so, for the caller's finite check to refuse
    return pose;
  }
  // Scaled by its largest component first, so that a quaternion of 1e300s normalises instead of
  // overflowing to a zero one. An all-zero quaternion (a default-constructed message) means "no rotation".
  const double largest = q.coeffs().cwiseAbs().maxCoeff();
  pose.orientation = largest > 1e-9 ? Eigen::Quaterniond(Eigen::Vector4d(q.coeffs() / largest)).normalized()
                                    : Eigen::Quaterniond::Identity();
  return pose;
}

geometry_msgs::Pose toMessage(const track::Pose& pose) {
  geometry_msgs::Pose msg;
  msg.position.x = pose.position.x();
  msg.position.y = pose.position.y();
  msg.position.z = pose.position.z();
  msg.orientation.w = pose.orientation.w();
  msg.orientation.x = pose.orientation.x();
  msg.orientation.y = pose.orientation.y();
  msg.orientation.z = pose.orientation.z();
  return msg;
}

geometry_msgs::Pose toMessage(const track::TrackPose& pose) { return toMessage(track::poseOnTrack(pose)); }

ros::Time toRosTime(double seconds) {
  ros::Time t;
  t.fromSec(seconds);
  return t;
}

nav_msgs::Odometry toOdometry(const vehicle::VehicleState& state, const ros::Time& stamp, const std::string& map_frame,
                              const std::string& base_frame) {
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = map_frame;
  odom.child_frame_id = base_frame;
  odom.pose.pose = toMessage(state.pose);
  odom.twist.twist.linear.x = state.body_linear_velocity.x();
  odom.twist.twist.linear.y = state.body_linear_velocity.y();
  odom.twist.twist.linear.z = state.body_linear_velocity.z();
  odom.twist.twist.angular.x = state.body_angular_velocity.x();
  odom.twist.twist.angular.y = state.body_angular_velocity.y();
  odom.twist.twist.angular.z = state.body_angular_velocity.z();
  // Ground truth: tiny variances, so consumers that invert covariances stay finite.
  for (int i = 0; i < 6; ++i) {
    odom.pose.covariance[i * 7] = 1e-9;
    odom.twist.covariance[i * 7] = 1e-9;
  }
  return odom;
}

vehicle::VehicleState fromOdometry(const nav_msgs::Odometry& odom) {
  vehicle::VehicleState s;
  s.pose = fromMessage(odom.pose.pose);
  const auto& v = odom.twist.twist.linear;
  const auto& w = odom.twist.twist.angular;
  s.body_linear_velocity = Eigen::Vector3d(v.x, v.y, v.z);
  s.body_angular_velocity = Eigen::Vector3d(w.x, w.y, w.z);
  s.linear_velocity = s.pose.orientation * s.body_linear_velocity;
  s.angular_velocity = s.pose.orientation * s.body_angular_velocity;
  s.body_acceleration.setZero();
  s.speed = s.body_linear_velocity.norm();
  s.forward_speed = s.body_linear_velocity.x();
  return s;
}

roar_ros::VehicleStatus toStatus(const vehicle::VehicleState& state, const ros::Time& stamp,
                                 const std::string& base_frame) {
  roar_ros::VehicleStatus msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = base_frame;
  msg.speed = state.speed;
  msg.forward_speed = state.forward_speed;
  msg.gear = state.gear;
  msg.engine_rpm = state.engine_rpm;
  msg.steering_angle = state.steering_angle;
  for (int i = 0; i < 4; ++i) msg.wheel_speeds[i] = state.wheels[i].angular_velocity;
  msg.on_track = state.on_track;
  msg.drag_share = state.drag_share;
  msg.applied_control = toMessage(state.applied_control);
  msg.applied_control.header.stamp = stamp;
  return msg;
}

geometry_msgs::TransformStamped toTransform(const track::Pose& pose, const ros::Time& stamp, const std::string& parent,
                                            const std::string& child) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  const auto p = toMessage(pose);
  t.transform.translation.x = p.position.x;
  t.transform.translation.y = p.position.y;
  t.transform.translation.z = p.position.z;
  t.transform.rotation = p.orientation;
  return t;
}

double yawOf(const geometry_msgs::Quaternion& q) {
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

// The URDF's joints: <wheel>_joint turns about the axle, steer_<front wheel>_joint about z.
sensor_msgs::JointState toJointState(const vehicle::VehicleState& state, const vehicle::VehicleParams& params,
                                     const std::array<double, 4>& wheel_angles, const ros::Time& stamp) {
  sensor_msgs::JointState msg;
  msg.header.stamp = stamp;
  for (std::size_t i = 0; i < 4; ++i) {
    const std::string& wheel = params.wheels[i].name;  // wheel_front_left, ...
    msg.name.push_back(wheel + "_joint");
    msg.position.push_back(wheel_angles[i]);
    msg.velocity.push_back(state.wheels[i].angular_velocity);
    if (params.wheels[i].front) {
      msg.name.push_back("steer_" + wheel.substr(wheel.find('_') + 1) + "_joint");  // steer_front_left_joint
      msg.position.push_back(state.wheels[i].steer_angle);
      msg.velocity.push_back(0.0);
    }
  }
  return msg;
}

visualization_msgs::Marker carLabel(const std::string& car, double height, double size, const ros::Time& stamp) {
  visualization_msgs::Marker m;
  m.header.frame_id = baseFrame(car);
  m.header.stamp = stamp;
  m.frame_locked = true;
  m.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.position.z = height;
  m.pose.orientation.w = 1.0;
  m.scale.z = size;
  return m;
}

}  // namespace roar::ros_bridge

#include <gtest/gtest.h>

#include <boost/make_shared.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <thread>

#include <roar_ros/ControllerConfig.h>

#include "roar/control/tracker_option_table.h"

#include "roar/control/trajectory_tracker.h"
#include "roar/ros/car_label.h"
#include "roar/ros/msg_conversion.h"
#include "roar/ros/planning_msg_conversion.h"
#include "roar/ros/race_msg_conversion.h"
#include "roar/ros/track_msg_conversion.h"
#include "roar/ros/waking_queue.h"
#include "roar/track/bridges.h"
#include "roar/track/map_folder.h"
#include "test_support.h"

using namespace roar;

TEST(MsgConversion, ControlRoundTrip) {
  vehicle::VehicleControl c;
  c.throttle = 0.25;
  c.steer = -0.5;
  c.brake = 0.75;
  c.hand_brake = true;
  c.reverse = true;
  c.manual_gear_shift = true;
  c.gear = 3;
  const auto back = ros_bridge::fromMessage(ros_bridge::toMessage(c));
  EXPECT_EQ(back.throttle, c.throttle);
  EXPECT_EQ(back.steer, c.steer);
  EXPECT_EQ(back.brake, c.brake);
  EXPECT_EQ(back.hand_brake, c.hand_brake);
  EXPECT_EQ(back.reverse, c.reverse);
  EXPECT_EQ(back.manual_gear_shift, c.manual_gear_shift);
  EXPECT_EQ(back.gear, c.gear);
}

TEST(MsgConversion, PoseRoundTripAndZeroQuaternion) {
  track::Pose p;
  p.position = {1.5, -2.5, 0.25};
  p.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  const auto back = ros_bridge::fromMessage(ros_bridge::toMessage(p));
  EXPECT_EQ(back.position, p.position);
  EXPECT_NEAR(back.orientation.angularDistance(p.orientation), 0.0, 1e-12);
  EXPECT_NEAR(ros_bridge::yawOf(ros_bridge::toMessage(p).orientation), 0.7, 1e-12);
  geometry_msgs::Pose zero;  // all-zero quaternion
  EXPECT_TRUE(ros_bridge::fromMessage(zero).orientation.isApprox(Eigen::Quaterniond::Identity()));
  // Huge components normalise (not overflow to a zero quaternion); NaN and inf stay, for callers to refuse.
  geometry_msgs::Pose huge;
  huge.orientation.z = 1e300;
  huge.orientation.w = 1e300;
  const auto normalised = ros_bridge::fromMessage(huge).orientation;
  EXPECT_NEAR(normalised.norm(), 1.0, 1e-12);
  EXPECT_NEAR(normalised.angularDistance(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()))),
              0.0, 1e-12);
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    geometry_msgs::Pose broken;
    broken.orientation.w = 1.0;
    broken.orientation.x = bad;
    EXPECT_FALSE(ros_bridge::fromMessage(broken).orientation.coeffs().allFinite()) << bad;
  }
}

TEST(MsgConversion, OdometryUsesBodyTwistAndFrames) {
  vehicle::VehicleState s;
  s.pose.position = {10, 20, 0};
  s.body_linear_velocity = {5, 0.5, 0};
  s.body_angular_velocity = {0, 0, 0.2};
  const auto odom = ros_bridge::toOdometry(s, ros_bridge::toRosTime(12.35), "map", "ego/base_link");
  EXPECT_EQ(odom.header.frame_id, "map");
  EXPECT_EQ(odom.child_frame_id, "ego/base_link");
  EXPECT_EQ(odom.pose.pose.position.y, 20);
  EXPECT_EQ(odom.twist.twist.linear.x, 5);
  EXPECT_EQ(odom.twist.twist.angular.z, 0.2);
  EXPECT_NEAR(odom.header.stamp.toSec(), 12.35, 1e-9);
}

TEST(MsgConversion, JointStatesNameTheUrdfsJoints) {
  const vehicle::VehicleParams sedan = test::sedan();
  vehicle::VehicleState s;
  for (std::size_t i = 0; i < 4; ++i) {
    s.wheels[i].angular_velocity = 10.0 + i;
    s.wheels[i].steer_angle = sedan.wheels[i].front ? 0.1 * (i + 1) : 0.0;
  }
  const auto joints = ros_bridge::toJointState(s, sedan, {0.5, 1.0, 1.5, 2.0}, ros_bridge::toRosTime(1.0));
  std::map<std::string, double> position;
  for (std::size_t k = 0; k < joints.name.size(); ++k) position[joints.name[k]] = joints.position[k];
  // The joints of urdf/sedan.urdf, each once: four wheels turning, two front wheels steering.
  ASSERT_EQ(position.size(), 6u);
  ASSERT_EQ(joints.name.size(), 6u);
  for (std::size_t i = 0; i < 4; ++i) {
    const std::string& wheel = sedan.wheels[i].name;
    EXPECT_EQ(position.at(wheel + "_joint"), 0.5 * (i + 1)) << wheel;
    if (sedan.wheels[i].front) {
      EXPECT_EQ(position.at("steer_" + wheel.substr(std::string("wheel_").size()) + "_joint"), 0.1 * (i + 1)) << wheel;
    }
  }
  EXPECT_EQ(position.count("steer_front_left_joint"), 1u);
  EXPECT_EQ(position.count("steer_front_right_joint"), 1u);
}

TEST(MsgConversion, OdometryGivesBackPoseAndVelocities) {
  vehicle::VehicleState s;
  s.pose.position = {10, 20, 0.5};
  s.pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  s.body_linear_velocity = {5, 0.5, 0};
  s.body_angular_velocity = {0, 0, 0.2};
  const vehicle::VehicleState back =
      ros_bridge::fromOdometry(ros_bridge::toOdometry(s, ros_bridge::toRosTime(1.0), "map", "b"));
  EXPECT_EQ(back.pose.position, s.pose.position);
  EXPECT_EQ(back.body_linear_velocity, s.body_linear_velocity);
  EXPECT_EQ(back.body_angular_velocity, s.body_angular_velocity);
  EXPECT_NEAR(back.linear_velocity.x(), -0.5, 1e-12) << "facing north: body left is map west";
  EXPECT_NEAR(back.linear_velocity.y(), 5.0, 1e-12);
  EXPECT_NEAR(back.speed, std::hypot(5.0, 0.5), 1e-12);
  EXPECT_EQ(back.forward_speed, 5.0);
}

TEST(MsgConversion, StatusCarriesTheDrivetrainAndTheSlipstream) {
  vehicle::VehicleState state;
  state.speed = 31.5;
  state.forward_speed = 31.0;
  state.gear = 4;
  state.engine_rpm = 5200.0;
  state.steering_angle = -0.1;
  for (int i = 0; i < 4; ++i) state.wheels[i].angular_velocity = 90.0 + i;
  state.on_track = true;
  state.drag_share = 0.73;
  state.applied_control.throttle = 0.6;
  const auto msg = ros_bridge::toStatus(state, ros::Time(12, 500000000), "ego/base_link");
  EXPECT_EQ(msg.header.frame_id, "ego/base_link");
  EXPECT_EQ(msg.header.stamp, ros::Time(12, 500000000));
  EXPECT_EQ(msg.speed, 31.5);
  EXPECT_EQ(msg.forward_speed, 31.0);
  EXPECT_EQ(msg.gear, 4);
  EXPECT_EQ(msg.engine_rpm, 5200.0);
  EXPECT_EQ(msg.steering_angle, -0.1);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(msg.wheel_speeds[i], 90.0 + i);
  EXPECT_TRUE(msg.on_track);
  EXPECT_EQ(msg.drag_share, 0.73) << "the tow the car is in";
  EXPECT_NEAR(ros_bridge::fromMessage(msg.applied_control).throttle, 0.6, 1e-6);
  EXPECT_EQ(msg.applied_control.header.stamp, msg.header.stamp);
}

TEST(MsgConversion, TimeIsExactForControlTicks) {
  // 0.05 s ticks: tick 7 and 7 * 0.05 agree to the nanosecond.
  EXPECT_EQ(ros_bridge::toRosTime(7 * 0.05).toNSec(), 350000000u);
  EXPECT_EQ(ros_bridge::toRosTime(123456 * 0.05).toNSec(), 6172800000000u);
}

TEST(MsgConversion, TrajectoryRoundTrip) {
  planning::Trajectory t;
  t.closed = true;
  t.length = 30.0;
  t.lap_time = 3.5;
  for (int i = 0; i < 3; ++i) {
    planning::TrajectoryPoint p;
    p.position = {1.0 * i, 2.0 * i};
    p.z = 0.5;
    p.yaw = 0.1 * i;
    p.s = 10.0 * i;
    p.curvature = 0.01 * i;
    p.speed = 20.0 + i;
    p.acceleration = -1.0 * i;
    p.time = 0.4 * i;
    p.offset = -0.3 * i;
    t.points.push_back(p);
  }
  const auto msg = ros_bridge::toMessage(t, "map", "Ring");
  EXPECT_EQ(msg.header.frame_id, "map");
  EXPECT_EQ(msg.map_name, "Ring");
  const auto back = ros_bridge::fromMessage(msg);
  EXPECT_EQ(back.closed, t.closed);
  EXPECT_EQ(back.length, t.length);
  EXPECT_EQ(back.lap_time, t.lap_time);
  ASSERT_EQ(back.points.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const auto &a = t.points[i], &b = back.points[i];
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.z, b.z);
    EXPECT_EQ(a.yaw, b.yaw);
    EXPECT_EQ(a.s, b.s);
    EXPECT_EQ(a.curvature, b.curvature);
    EXPECT_EQ(a.speed, b.speed);
    EXPECT_EQ(a.acceleration, b.acceleration);
    EXPECT_EQ(a.time, b.time);
    EXPECT_EQ(a.offset, b.offset);
  }
  EXPECT_EQ(ros_bridge::toPath(t, "map").poses.size(), 4u) << "a closed path returns to its start";
}

TEST(MsgConversion, WaypointArraysThatAreNoCircuitAreRefused) {
  roar_ros::WaypointArray msg;
  msg.closed = true;
  msg.friction = 1.0;
  auto error = [&] { return test::errorOf([&] { ros_bridge::trackFromMessage(msg); }); };
  EXPECT_NE(error().find("empty"), std::string::npos);
  for (int i = 0; i < 60; ++i) {
    roar_ros::Waypoint w;
    w.location.x = 50.0 * std::cos(2 * M_PI * i / 60);
    w.location.y = 50.0 * std::sin(2 * M_PI * i / 60);
    w.yaw = 2 * M_PI * i / 60 + M_PI / 2;
    w.lane_width = 10.0;
    msg.waypoints.push_back(w);
  }
  EXPECT_EQ(error(), "");
  EXPECT_NEAR(ros_bridge::trackFromMessage(msg).info().friction, 1.0, 0.0);
  // An open list is a point-to-point course, whose start and finish lines must lie on it.
  msg.closed = false;
  EXPECT_NE(error().find("a point-to-point course needs its start line"), std::string::npos) << error();
  msg.closed = true;
  msg.friction = std::nan("");
  EXPECT_NE(error().find("friction"), std::string::npos);
  msg.friction = 1.0;
  msg.waypoints[5].lane_width = std::numeric_limits<double>::infinity();
  EXPECT_NE(error().find("waypoint 5"), std::string::npos);
}

// cfg/Controller.cfg repeats the tracker's defaults for dynamic_reconfigure: they must agree.
// rviz's track markers lie on the road: up a bridge's ramps and over its deck, parapets at the deck's edge.
// A point-to-point course goes over /waypoints as one: open, with its start and finish lines; its path and
// its edges do not return to the start.
TEST(MsgConversion, ACourseCrossesAsACourse) {
  const auto course = track::loadMapFolder(test::sourceDir() + "/maps/roar_hillclimb");
  const auto msg = ros_bridge::toWaypointArray(course, "map");
  EXPECT_FALSE(msg.closed);
  EXPECT_EQ(msg.start_s, course.info().start_finish_s);
  EXPECT_EQ(msg.finish_s, course.finishLine());
  const auto back = ros_bridge::trackFromMessage(msg);
  EXPECT_FALSE(back.closed());
  EXPECT_EQ(back.info().start_finish_s, course.info().start_finish_s);
  EXPECT_EQ(back.info().finish_s, course.info().finish_s);
  EXPECT_NEAR(back.length(), course.length(), 1.0);
  EXPECT_EQ(ros_bridge::toPath(course, "map").poses.size(), course.size()) << "no way back to the start";
  const auto markers = ros_bridge::trackMarkers(course, "map");
  int lines_across = 0;
  for (const auto& m : markers.markers) {
    if (m.ns == "edges") {
      EXPECT_EQ(m.points.size(), course.size());
    }
    if (m.ns == "start_finish") ++lines_across;
  }
  EXPECT_EQ(lines_across, 2) << "the start line and the finish line";
  // A circuit's still closes.
  const auto circuit = ros_bridge::toWaypointArray(test::circleTrack(50.0), "map");
  EXPECT_TRUE(circuit.closed);
  EXPECT_TRUE(ros_bridge::trackFromMessage(circuit).closed());
}

TEST(TrackMarkers, FollowTheRoadOverABridge) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_eight");
  const auto markers = ros_bridge::trackMarkers(track, "map");
  std::map<std::string, std::pair<double, double>> heights;  // lowest and highest point of each kind
  for (const auto& m : markers.markers) {
    auto& [lo, hi] = heights.try_emplace(m.ns, 1e9, -1e9).first->second;
    for (const auto& p : m.points) lo = std::min(lo, p.z), hi = std::max(hi, p.z);
  }
  for (const std::string ns : {"road", "edges", "centre_line", "barriers"}) {
    SCOPED_TRACE(ns);
    ASSERT_TRUE(heights.count(ns));
    EXPECT_LT(heights[ns].first, 0.1) << "on the ground away from the bridge";
    EXPECT_GT(heights[ns].second, track::kBridgeRise - 0.1) << "over the deck";
  }
  // Over the deck, the barrier lines run at the parapet, half a metre out from the road's edge.
  const auto deck = track::bridgeDeckPoints(track);
  int on_deck = 0;
  for (const auto& m : markers.markers) {
    if (m.ns != "barriers") continue;
    for (std::size_t i = 0; i < track.size(); ++i) {
      if (!deck[i]) continue;
      ++on_deck;
      const auto& p = m.points[i];
      const auto pr = track.projectAtHeight(Eigen::Vector3d(p.x, p.y, p.z));
      EXPECT_NEAR(pr.beyondEdge(), track::kParapetOffset, 0.05) << "point " << i;
      EXPECT_NEAR(p.z, track.point(i).z + 0.02, 0.05);
    }
  }
  EXPECT_GT(on_deck, 0);
}

TEST(ControllerConfig, DefaultsAreTheTrackersDefaults) {
  const auto config = roar_ros::ControllerConfig::__getDefault__();
  const control::TrackerOptions t;
  EXPECT_EQ(config.lateral_control, control::lateralMethodName(t.lateral));
  EXPECT_EQ(config.lookahead_min, t.lookahead_min);
  EXPECT_EQ(config.lookahead_time, t.lookahead_time);
  EXPECT_EQ(config.stanley_gain, t.stanley_gain);
  EXPECT_EQ(config.yaw_rate_gain, t.yaw_rate_gain);
  EXPECT_EQ(config.speed_gain, t.speed_gain);
  EXPECT_EQ(config.speed_preview, t.speed_preview);
  EXPECT_EQ(config.max_speed, t.max_speed);
}

// A batch's or the binding's tracker options take the names and ranges the node's live settings take.
TEST(ControllerConfig, RangesAreTheTrackerTables) {
  const auto low = roar_ros::ControllerConfig::__getMin__();
  const auto high = roar_ros::ControllerConfig::__getMax__();
  control::TrackerOptions t;
  const auto table = control::trackerOptionTable(&t);
  std::vector<std::string> names;
  for (const auto& entry : table) names.push_back(entry.name);
  std::vector<std::string> config_names;
  for (const auto& param : roar_ros::ControllerConfig::__getParamDescriptions__()) {
    if (param->name != "lateral_control") config_names.push_back(param->name);
  }
  EXPECT_EQ(names, config_names);
  for (const auto& param : roar_ros::ControllerConfig::__getParamDescriptions__()) {
    boost::any lo, hi;
    param->getValue(low, lo);
    param->getValue(high, hi);
    for (const auto& entry : table) {
      if (entry.name != param->name) continue;
      EXPECT_EQ(entry.low, boost::any_cast<double>(lo)) << entry.name;
      EXPECT_EQ(entry.high, boost::any_cast<double>(hi)) << entry.name;
    }
  }
}

// The timing (race_control) and the decision (planner) float above the same car from two processes with
// their own lags: drawn in the car's frame and frame-locked, they stay where the car is, one above the other.
TEST(MsgConversion, CarLabelsRideInTheCarsFrame) {
  const auto timing = ros_bridge::carLabel("rival", ros_bridge::kTimingLabelHeight, 0.8, ros::Time(3.0));
  const auto decision = ros_bridge::carLabel("rival", ros_bridge::kManoeuvreLabelHeight, 0.7, ros::Time(3.0));
  for (const auto& m : {timing, decision}) {
    EXPECT_EQ(m.header.frame_id, "rival/base_link");
    EXPECT_TRUE(m.frame_locked);
    EXPECT_EQ(m.type, visualization_msgs::Marker::TEXT_VIEW_FACING);
    EXPECT_EQ(m.pose.position.x, 0.0);
    EXPECT_EQ(m.pose.position.y, 0.0);
  }
  // Two timing lines below their centre must clear one decision line above its own, with 0.2 m between.
  EXPECT_GE((timing.pose.position.z - timing.scale.z) - (decision.pose.position.z + decision.scale.z / 2), 0.2);
  EXPECT_GE(decision.pose.position.z - decision.scale.z / 2, 1.8) << "above the roof";
}

TEST(MsgConversion, ManoeuvreMarkersShowTheDecisionAndEachPrediction) {
  const planning::RaceDecision decision{planning::RaceMode::kPass, -1, "pace"};
  std::vector<planning::PredictedPath> predictions(2);
  predictions[0] = {"pace", 0.5, {{10.0, 1.0}, {15.0, 1.0}, {20.0, 1.5}}};
  predictions[1] = {"rival", 0.5, {{-5.0, 0.0}, {0.0, 0.0}}};
  const auto m = ros_bridge::manoeuvreMarkers("ego", decision, predictions, "map", ros::Time(12.5));
  ASSERT_EQ(m.markers.size(), 2u + 2u * predictions.size());
  EXPECT_EQ(m.markers[0].action, visualization_msgs::Marker::DELETEALL) << "stale predictions cleared first";
  const auto& text = m.markers[1];
  EXPECT_EQ(text.type, visualization_msgs::Marker::TEXT_VIEW_FACING);
  EXPECT_EQ(text.text, "pass pace on the right");
  EXPECT_EQ(text.header.frame_id, "ego/base_link") << "rides with the car";
  EXPECT_EQ(text.pose.position.z, ros_bridge::kManoeuvreLabelHeight);
  EXPECT_EQ(text.header.stamp, ros::Time(12.5));
  EXPECT_EQ(m.markers[2].header.frame_id, "map") << "predictions are where the cars will be on the map";
  EXPECT_EQ(text.ns.rfind("ego/", 0), 0u) << "namespaced by the car: " << text.ns;
  for (std::size_t k = 0; k < predictions.size(); ++k) {
    const auto& line = m.markers[2 + 2 * k];
    const auto& dots = m.markers[3 + 2 * k];
    EXPECT_EQ(line.type, visualization_msgs::Marker::LINE_STRIP);
    EXPECT_EQ(dots.type, visualization_msgs::Marker::SPHERE_LIST);
    ASSERT_EQ(line.points.size(), predictions[k].positions.size());
    ASSERT_EQ(dots.points.size(), predictions[k].positions.size());
    for (std::size_t i = 0; i < line.points.size(); ++i) {
      EXPECT_EQ(line.points[i].x, predictions[k].positions[i].x());
      EXPECT_EQ(line.points[i].y, predictions[k].positions[i].y());
    }
  }
  EXPECT_NE(m.markers[2].id, m.markers[4].id) << "one marker per predicted car";
}

// roar_sim waits on its topics' queue; a service request arriving in its own queue ends that wait at once
// rather than at the wait's end.
TEST(WakingCallbackQueue, ServiceRequestsWakeTheTopicsWait) {
  ros::CallbackQueue topics;
  roar::ros_bridge::WakingCallbackQueue services(&topics);
  struct Counted : ros::CallbackInterface {
    int* calls;
    explicit Counted(int* c) : calls(c) {}
    CallResult call() override {
      ++*calls;
      return Success;
    }
  };
  int calls = 0;
  std::thread request([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    services.addCallback(boost::make_shared<Counted>(&calls));
  });
  const ros::WallTime start = ros::WallTime::now();
  topics.callAvailable(ros::WallDuration(60.0));  // returns once something arrives
  const double waited = (ros::WallTime::now() - start).toSec();
  request.join();
  EXPECT_LT(waited, 30.0) << "the topics' wait ran its full length";
  EXPECT_EQ(calls, 0) << "the request is answered from its own queue, not the topics'";
  services.callAvailable(ros::WallDuration(0));
  EXPECT_EQ(calls, 1);
}

TEST(MsgConversion, RaceStatusHasEveryCarsStanding) {
  const auto track = test::circleTrack(100.0);
  race::RaceRules rules;
  rules.laps = 2;
  race::RaceControl race(track, rules, {"slow", "fast"});
  double t = 0.0;
  for (; t < 40.0; t += 0.05) {
    race.updatePosition("fast", t, test::onCircleTrack(-5 + 20.0 * t));
    race.updatePosition("slow", t, test::onCircleTrack(-10 + 10.0 * t));
  }
  const roar_ros::RaceStatus msg = ros_bridge::toRaceStatus(race, t);
  EXPECT_DOUBLE_EQ(msg.header.stamp.toSec(), ros_bridge::toRosTime(t).toSec());
  EXPECT_EQ(msg.laps, 2);
  EXPECT_FALSE(msg.finished);
  ASSERT_EQ(msg.cars.size(), 2u);
  EXPECT_EQ(msg.cars[0].name, "fast") << "in the standings' order";
  EXPECT_EQ(msg.cars[0].position, 1);
  EXPECT_EQ(msg.cars[0].laps_completed, 1);
  EXPECT_DOUBLE_EQ(msg.cars[0].best_lap, *race.car("fast").timer.bestLap());
  EXPECT_DOUBLE_EQ(msg.cars[0].last_lap, msg.cars[0].best_lap);
  EXPECT_GT(msg.cars[0].current_lap_time, 0.0);
  EXPECT_GE(msg.cars[0].sector, 1);
  EXPECT_EQ(msg.cars[1].name, "slow");
  EXPECT_EQ(msg.cars[1].laps_completed, 0);
  EXPECT_GT(msg.cars[1].gap_to_leader, 0.0);
  EXPECT_NEAR(msg.cars[1].distance, race.car("slow").timer.distanceCovered(), 1e-9);
}

TEST(MsgConversion, APlaceOnTheRoadIsThePoseOnItsSurface) {
  const auto track = test::circleTrack(100.0);
  const track::TrackPose place = track.poseAt(50.0);
  const geometry_msgs::Pose msg = ros_bridge::toMessage(place);
  const track::Pose pose = track::poseOnTrack(place);
  EXPECT_DOUBLE_EQ(msg.position.x, pose.position.x());
  EXPECT_DOUBLE_EQ(msg.position.y, pose.position.y());
  EXPECT_DOUBLE_EQ(msg.position.x, place.position.x());
  EXPECT_DOUBLE_EQ(msg.position.z, place.height) << "on the road's surface";
  EXPECT_NEAR(ros_bridge::yawOf(msg.orientation), place.heading, 1e-9);
}

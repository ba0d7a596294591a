// race_control: runs the race by its rules (race::RaceControl) from every car's odometry and collisions:
// prints a line per lap and per incident, publishes /race_status, respawns cars through
// /roar_sim/reset_vehicle when the rules say so, writes the results and shuts down when every car has
// done its laps (mark it required="true" in a launch file to end the race there). Exit code 0 when every
// car finished, 1 on a time-out.
#include <nav_msgs/Odometry.h>
#include <roar_ros/CollisionEvent.h>
#include <roar_ros/MapInfo.h>
#include <roar_ros/RaceStatus.h>
#include <roar_ros/ResetVehicle.h>
#include <roar_ros/Trajectory.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <std_msgs/String.h>
#include <visualization_msgs/MarkerArray.h>

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>

#include "roar/race/race_control.h"
#include "roar/report/race_report.h"
#include "roar/ros/car_label.h"
#include "roar/ros/msg_conversion.h"
#include "roar/ros/param_reading.h"
#include "roar/ros/race_msg_conversion.h"
#include "roar/ros/scenario_params.h"
#include "roar/ros/sim_map_follower.h"
#include "roar/track/map_folder.h"
#include "roar/track/pose.h"

using namespace roar;

namespace {

constexpr double kRecorderPatience = 5.0;  // s of wall time for the recorder to catch up at the end

struct RaceControlOptions {
  std::string map_folder;
  std::vector<std::string> vehicles;
  race::RaceRules rules;
  double max_sim_time = 0.0;
  double sim_silence = 10.0;  // s of wall time without odometry before roar_sim is probed (dead: aborted)
  std::string output_dir;
  // The race's recorder (race_recorder's node name; empty: none): results.yaml says whether its bag reached
  // the finish.
  std::string recorder;
  // At a finished race, end the roslaunch that started this node as Ctrl-C would (race.launch's
  // end_with_race), not by exiting as a required node: roslaunch prints that as "REQUIRED process has died".
  bool end_launch = false;
};

// Sends the roslaunch that started this process (its parent) what Ctrl-C sends; false when the parent is
// no roslaunch (rosrun, rostest, a shell), which is left alone.
bool askRoslaunchToEnd() {
  const pid_t parent = getppid();
  std::ifstream cmdline("/proc/" + std::to_string(parent) + "/cmdline");
  std::string args((std::istreambuf_iterator<char>(cmdline)), std::istreambuf_iterator<char>());
  std::replace(args.begin(), args.end(), '\0', ' ');
  if (parent <= 1 || args.find("/roslaunch ") == std::string::npos) return false;
  return kill(parent, SIGINT) == 0;
}

race::IncidentRule readRule(const ros::NodeHandle& nh, const std::string& name, const std::string& fallback) {
  const std::string rule = ros_bridge::readChoice(nh, name, fallback, {"ignore", "penalty", "respawn"});
  return rule == "ignore"    ? race::IncidentRule::kIgnore
         : rule == "respawn" ? race::IncidentRule::kRespawn
                             : race::IncidentRule::kPenalty;
}

RaceControlOptions readParameters(const ros::NodeHandle& nh) {
  using namespace ros_bridge;
  RaceControlOptions o;
  const auto scenario = readScenario(nh);
  o.map_folder = readMapFolder(nh, scenario);
  for (const auto& car : readRaceCars(nh, scenario, readString(nh, "model", config::kDefaultModel)))
    o.vehicles.push_back(car.name);
  auto& r = o.rules;
  r.laps = readInt(nh, "laps", scenario ? scenario->laps : 3, 1, 1000);
  r.collision = readRule(nh, "collision_rule", "penalty");
  r.collision_penalty = readDouble(nh, "collision_penalty", r.collision_penalty, 0.0, 3600.0);
  r.track_limits = readRule(nh, "track_limits_rule", "penalty");
  r.track_limits_penalty = readDouble(nh, "track_limits_penalty", r.track_limits_penalty, 0.0, 3600.0);
  r.track_limits_margin = readDouble(nh, "track_limits_margin", r.track_limits_margin, 0.0, 50.0);
  r.driver_grace = readDouble(nh, "driver_grace", r.driver_grace, 0.0, 3600.0);
  o.max_sim_time = readDouble(nh, "max_sim_time", 0.0, 0.0, 1e7);
  o.sim_silence = readDouble(nh, "sim_silence", o.sim_silence, 1.0, 3600.0);
  o.output_dir = readString(nh, "output_dir", "");
  o.end_launch = readBool(nh, "end_launch", o.end_launch);
  o.recorder = readString(nh, "recorder", "");
  // One spelling of the folder in what is printed and written ("a/../b/" is "b").
  if (!o.output_dir.empty()) {
    o.output_dir = std::filesystem::absolute(o.output_dir).lexically_normal().string();
    if (o.output_dir.size() > 1 && o.output_dir.back() == '/') o.output_dir.pop_back();
  }
  return o;
}

class RaceControlNode {
 public:
  RaceControlNode(ros::NodeHandle& nh, track::Track track, const RaceControlOptions& options)
      : options_(options),
        track_(std::make_unique<track::Track>(std::move(track))),
        race_(std::make_unique<race::RaceControl>(*track_, options.rules, options.vehicles)) {
    status_pub_ = nh.advertise<roar_ros::RaceStatus>("race_status", 10);
    markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("race_status/markers", 10);
    reset_ = nh.serviceClient<roar_ros::ResetVehicle>("/roar_sim/reset_vehicle");
    for (const auto& name : options.vehicles) {
      subs_.push_back(nh.subscribe<nav_msgs::Odometry>(
          name + "/odom", 100, [this, name](const nav_msgs::Odometry::ConstPtr& m) { onOdometry(name, *m); }));
      subs_.push_back(nh.subscribe<roar_ros::CollisionEvent>(
          name + "/collision", 100,
          [this, name](const roar_ros::CollisionEvent::ConstPtr& m) { onCollision(name, *m); }));
    }
    // The planner's promise, for the report's speed plots.
    line_sub_ = nh.subscribe<roar_ros::Trajectory>(
        "racing_line", 1, [this](const roar_ros::Trajectory::ConstPtr& m) { onRacingLine(*m); });
    map_follower_ = std::make_unique<ros_bridge::SimMapFollower>(
        nh, options.map_folder, "race_control",
        [this](std::unique_ptr<track::Track> track, const roar_ros::MapInfo& info) {
          onSimMap(std::move(track), info);
        });
    // A car whose driver is lost (roar_sim stops waiting for it and brings it to a stop) waits ~driver_grace
    // for it: back in time, it races on having lost the time it stood; not, it is retired.
    lost_sub_ =
        nh.subscribe<std_msgs::String>("/roar_sim/driver_lost", 10, [this](const std_msgs::String::ConstPtr& m) {
          if (!race_->cars().count(m->data)) return;
          race_->driverLost(m->data, now_);
          std::printf("%s: driver lost at t = %.2f s: retired unless it is back within %.0f s\n", m->data.c_str(), now_,
                      race_->rules().driver_grace);
          std::fflush(stdout);
        });
    back_sub_ =
        nh.subscribe<std_msgs::String>("/roar_sim/driver_back", 10, [this](const std_msgs::String::ConstPtr& m) {
          if (!race_->cars().count(m->data) || race_->car(m->data).driver_lost_at < 0) return;
          race_->driverBack(m->data);
          std::printf("%s: driver back at t = %.2f s\n", m->data.c_str(), now_);
          std::fflush(stdout);
        });
    if (!options.recorder.empty()) {
      recorded_sub_ = nh.subscribe<rosgraph_msgs::Clock>(
          ros::names::resolve(options.recorder) + "/recorded", 10, [this](const rosgraph_msgs::Clock::ConstPtr& m) {
            recorded_until_ = std::max(recorded_until_, m->clock.toSec());
          });
    }
    // Simulated time: the status stops with the simulator.
    status_timer_ = nh.createTimer(ros::Duration(0.1), [this](const ros::TimerEvent&) { publishStatus(); });
  }

  double now() const { return now_; }
  // How far the recorder got, once it has had up to `patience` s of wall time to reach now() (it runs a few
  // ticks behind); none without a recorder.
  std::optional<race::RecordingState> recording(double patience) {
    if (recorded_sub_.getTopic().empty()) return std::nullopt;
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(patience);
    while (recorded_until_ < now_ - 1e-6 && ros::ok() && ros::WallTime::now() < until) {
      ros::spinOnce();
      ros::WallDuration(0.01).sleep();
    }
    return race::RecordingState{recorded_until_, recorded_until_ >= now_ - 1e-6};
  }
  // Wall time of the last odometry message (zero: none yet).
  ros::WallTime lastMessage() const { return last_message_; }
  const race::RaceControl& race() const { return *race_; }
  const report::Telemetry& telemetry() const { return telemetry_; }
  const std::vector<report::ProfilePoint>& profile() const { return profile_; }

 private:
  // A map loaded or reloaded at run time ends the race on the old one: its results so far are written
  // (status interrupted) and a new race starts on the new map with the same cars and rules.
  void onSimMap(std::unique_ptr<track::Track> track, const roar_ros::MapInfo& info) {
    ++interruptions_;
    std::printf("race_control: roar_sim %s map '%s' at t = %.2f s: the race on '%s' is interrupted\n",
                info.reason == "reload" ? "reloaded" : "loaded", info.name.c_str(), info.header.stamp.toSec(),
                track_->info().name.c_str());
    if (!options_.output_dir.empty()) {
      const std::string dir = options_.output_dir + "/interrupted_" + std::to_string(interruptions_);
      race::writeResults(dir, *race_, race::RaceOutcome::kInterrupted, ros::param::param<std::string>("/run_id", ""));
      report::writeRaceReport(dir, *race_, telemetry_, profile_);
      std::printf("race_control: the interrupted race's results are in %s\n", dir.c_str());
    }
    std::fflush(stdout);
    race_ = std::make_unique<race::RaceControl>(*track, options_.rules, options_.vehicles);
    track_ = std::move(track);  // after: the old race referred to the old track
    telemetry_.clear();
    profile_.clear();
    now_ = std::max(now_, info.header.stamp.toSec());
    publishStatus();
  }

  void onOdometry(const std::string& name, const nav_msgs::Odometry& odom) {
    last_message_ = ros::WallTime::now();
    const double t = odom.header.stamp.toSec();
    now_ = std::max(now_, t);
    for (const auto& car : race_->retireLostDrivers(now_)) {
      std::printf("%s: retired at t = %.2f s (driver lost)\n", car.c_str(), race_->car(car).retire_time);
      std::fflush(stdout);
    }
    if (!race_->car(name).finished) {
      const auto& v = odom.twist.twist.linear;
      telemetry_[name].push_back(
          {t, Eigen::Vector2d(odom.pose.pose.position.x, odom.pose.pose.position.y), std::sqrt(v.x * v.x + v.y * v.y)});
    }
    const auto& q = odom.pose.pose.orientation;
    const double yaw = std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
    // The twist is in base_link: turned into the map frame for judging contacts.
    const auto& body = odom.twist.twist.linear;
    const Eigen::Vector2d velocity(std::cos(yaw) * body.x - std::sin(yaw) * body.y,
                                   std::sin(yaw) * body.x + std::cos(yaw) * body.y);
    race_->updateMotion(name, Eigen::Vector2d(odom.pose.pose.position.x, odom.pose.pose.position.y), yaw, velocity);
    std::optional<race::Incident> incident;
    const std::size_t passes = race_->overtakes().size();
    const auto lap = race_->updatePosition(
        name, t, Eigen::Vector3d(odom.pose.pose.position.x, odom.pose.pose.position.y, odom.pose.pose.position.z),
        &incident);
    if (incident) report(name, *incident);
    for (std::size_t k = passes; k < race_->overtakes().size(); ++k) {
      const race::Overtake& o = race_->overtakes()[k];
      std::printf("%s passed %s on lap %d at s = %.0f m (t = %.2f s)\n", o.passer.c_str(), o.passed.c_str(), o.lap, o.s,
                  o.time);
      std::fflush(stdout);
    }
    if (!lap) return;
    std::string sectors;
    for (double s : lap->sector_times) {
      char buf[32];
      std::snprintf(buf, sizeof(buf), "%s%.3f", sectors.empty() ? "" : " / ", s);
      sectors += buf;
    }
    std::printf("%s lap %d: %.3f s (sectors %s)\n", name.c_str(), lap->lap, lap->lap_time, sectors.c_str());
    std::fflush(stdout);
    publishStatus();
  }

  void onRacingLine(const roar_ros::Trajectory& line) {
    const track::Track& track = race_->track();
    if (line.map_name != track.info().name) return;  // the line of the map before a change
    profile_.clear();
    double near = track.info().start_finish_s;
    for (std::size_t i = 0; i < line.points.size(); ++i) {
      const auto& p = line.points[i];
      const Eigen::Vector3d position(p.position.x, p.position.y, p.position.z);
      const auto pr = i == 0 ? track.projectAtHeight(position) : track.projectNear(position.head<2>(), near, 100.0);
      near = pr.s;
      profile_.push_back({track.raceProgress(pr.s), p.speed});
    }
    std::sort(profile_.begin(), profile_.end(),
              [](const report::ProfilePoint& a, const report::ProfilePoint& b) { return a.progress < b.progress; });
  }

  void onCollision(const std::string& name, const roar_ros::CollisionEvent& event) {
    if (auto incident = race_->updateContact(name, event.header.stamp.toSec(), event.other)) report(name, *incident);
  }

  void report(const std::string& name, const race::Incident& incident) {
    std::printf(
        "%s: %s%s at t = %.2f s%s\n", name.c_str(), incident.kind.c_str(),
        incident.contact.empty()
            ? ""
            : (" (" + incident.contact + ", " +
               (incident.at_fault.empty() ? std::string("racing incident") : incident.at_fault + " at fault") + ")")
                  .c_str(),
        incident.time,
        incident.penalty > 0 ? (" (+" + std::to_string(incident.penalty) + " s penalty)").c_str()
        : incident.respawn   ? " (respawned at the last waypoint)"
                             : "");
    std::fflush(stdout);
    if (!incident.respawn) return;
    roar_ros::ResetVehicle srv;
    srv.request.name = name;
    srv.request.spawn_point = -1;
    srv.request.pose = ros_bridge::toMessage(incident.respawn_pose);
    if (!reset_.call(srv) || !srv.response.success) {
      ROS_ERROR("race_control: respawning '%s' through %s failed: %s", name.c_str(), reset_.getService().c_str(),
                srv.response.message.c_str());
    }
  }

  void publishStatus() {
    const roar_ros::RaceStatus status = ros_bridge::toRaceStatus(*race_, now_);
    status_pub_.publish(status);
    if (markers_pub_.getNumSubscribers() > 0) markers_pub_.publish(timingMarkers(status));
  }

  // For rviz: each car's place, lap and times as text floating above it.
  visualization_msgs::MarkerArray timingMarkers(const roar_ros::RaceStatus& status) const {
    visualization_msgs::MarkerArray markers;
    for (const auto& car : status.cars) {
      auto samples = telemetry_.find(car.name);
      if (samples == telemetry_.end() || samples->second.empty()) continue;
      visualization_msgs::Marker m =
          ros_bridge::carLabel(car.name, ros_bridge::kTimingLabelHeight, 0.8, status.header.stamp);
      m.ns = "timing";
      m.id = static_cast<int>(markers.markers.size());
      m.color.r = m.color.g = m.color.b = m.color.a = 1.0;
      auto seconds = [](double t) {
        char buf[32] = "-";
        if (t > 0.0) std::snprintf(buf, sizeof(buf), "%.2f", t);
        return std::string(buf);
      };
      char text[256];
      std::snprintf(text, sizeof(text), "P%d %s  lap %d/%d  S%d  %.1f s\nlast %s  best %s  %.0f km/h", car.position,
                    car.name.c_str(), std::min(car.laps_completed + 1, status.laps), status.laps, car.sector,
                    car.current_lap_time, seconds(car.last_lap).c_str(), seconds(car.best_lap).c_str(),
                    samples->second.back().speed * 3.6);
      m.text = text;
      markers.markers.push_back(m);
    }
    return markers;
  }

  RaceControlOptions options_;
  int interruptions_ = 0;
  std::unique_ptr<track::Track> track_;
  std::unique_ptr<race::RaceControl> race_;
  std::unique_ptr<ros_bridge::SimMapFollower> map_follower_;
  ros::Subscriber lost_sub_, back_sub_, recorded_sub_;
  double recorded_until_ = -1.0;
  ros::WallTime last_message_;
  ros::Publisher status_pub_, markers_pub_;
  ros::ServiceClient reset_;
  std::vector<ros::Subscriber> subs_;
  ros::Subscriber line_sub_;
  report::Telemetry telemetry_;
  std::vector<report::ProfilePoint> profile_;
  ros::Timer status_timer_;
  double now_ = 0.0;
};

}  // namespace

// SIGTERM (a kill, a system shutting down) ends the race as Ctrl-C does: results written, status aborted.
void shutDownOnTerm(int) { ros::requestShutdown(); }

// The laps every car has completed, summed: results are rewritten when it grows.
int lapsTimed(const race::RaceControl& race) {
  int laps = 0;
  for (const auto& [name, car] : race.cars()) laps += car.timer.lapsCompleted();
  return laps;
}

int main(int argc, char** argv) {
  ros::init(argc, argv, "race_control");
  signal(SIGTERM, shutDownOnTerm);
  ros::NodeHandle nh, pnh("~");
  try {
    const RaceControlOptions options = readParameters(pnh);
    RaceControlNode node(nh, track::loadMapFolder(options.map_folder), options);
    ros_bridge::refuseUnknownParameters(pnh);
    // Read now: at the end the master may be gone with the launch.
    const std::string run_id = ros::param::param<std::string>("/run_id", "");
    const track::Track& track = node.race().track();
    if (track.closed()) {
      std::printf("race_control: %d lap(s) of %s (%.0f m) for %zu car(s)\n", options.rules.laps,
                  track.info().name.c_str(), track.length(), options.vehicles.size());
    } else {
      // A point-to-point course is raced once, whatever ~laps says.
      std::printf(
          "race_control: one run of %s, a point-to-point course (%.0f m from its start line to its finish "
          "line), for %zu car(s)\n",
          track.info().name.c_str(), track.raceDistance(), options.vehicles.size());
    }
    if (!options.output_dir.empty())
      std::printf("race_control: results will be written to %s\n", options.output_dir.c_str());
    std::fflush(stdout);

    // Wall-time loop: the race ends on simulated events, not on a clock of ours; but a simulator that has
    // gone silent and no longer answers (killed) ends it as aborted.
    bool simulator_lost = false;
    ros::WallTime last_probe = ros::WallTime::now();
    int laps_written = 0;
    while (ros::ok()) {
      ros::spinOnce();
      if (node.race().finished() || (options.max_sim_time > 0 && node.now() > options.max_sim_time)) break;
      // Every lap timed is on disk at once (status running): a race_control killed mid-race loses none.
      if (!options.output_dir.empty() && lapsTimed(node.race()) > laps_written) {
        laps_written = lapsTimed(node.race());
        race::writeResults(options.output_dir, node.race(), race::RaceOutcome::kRunning, run_id);
      }
      const ros::WallTime wall = ros::WallTime::now();
      if (!node.lastMessage().isZero() && (wall - node.lastMessage()).toSec() > options.sim_silence &&
          (wall - last_probe).toSec() > 1.0) {
        last_probe = wall;
        if (!ros::service::exists("/roar_sim/spawn_vehicle", false)) {
          simulator_lost = true;
          std::printf("race_control: no odometry for %.0f s of wall time and roar_sim does not answer: race aborted\n",
                      (wall - node.lastMessage()).toSec());
          break;
        }
      }
      ros::WallDuration(0.002).sleep();
    }
    race::RaceEnd end;
    end.complete = node.race().finished();
    end.any_finisher = node.race().anyFinisher();
    end.out_of_time = options.max_sim_time > 0 && node.now() > options.max_sim_time;
    end.simulator_lost = simulator_lost;
    const race::RaceVerdict verdict = race::judgeRaceEnd(end);
    std::printf("race_control: race %s at t = %.2f s%s\n", race::outcomeWords(verdict.outcome), node.now(),
                verdict.reason.empty() ? "" : (": " + verdict.reason).c_str());
    for (const auto& standing : node.race().standings())
      std::printf("  %s\n", race::standingLine(node.race(), standing).c_str());
    if (!options.output_dir.empty()) {
      const auto recording = node.recording(kRecorderPatience);
      if (recording && !recording->complete) {
        std::printf(
            "race_control: the recorder %s stopped at t = %.2f s, before the end of the race (%.2f s): its bag is "
            "short and, if it was killed, left .active (rosbag reindex, or replay.launch, recovers it)\n",
            options.recorder.c_str(), recording->recorded_until, node.now());
      }
      race::writeResults(options.output_dir, node.race(), verdict.outcome, run_id, recording);
      report::writeRaceReport(options.output_dir, node.race(), node.telemetry(), node.profile());
      std::printf(
          "race_control: results in %s: results.yaml, laps.csv, sectors.csv, laps.md, trajectories.png, "
          "speed_<car>.png\n",
          options.output_dir.c_str());
    }
    std::fflush(stdout);
    if (end.complete && options.end_launch && askRoslaunchToEnd()) {
      // roslaunch stops every node, this one too (its SIGINT shuts ROS down); a while at most.
      const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(15.0);
      while (ros::ok() && ros::WallTime::now() < until) ros::WallDuration(0.05).sleep();
      return 0;
    }
    ros::shutdown();
    return verdict.outcome == race::RaceOutcome::kFinished ? 0 : 1;
  } catch (const std::exception& e) {
    ROS_FATAL("race_control: %s", e.what());
    return 1;
  }
}

// race_control: times laps and sectors of every car from its odometry, counts barrier contacts, prints a
// line per lap and a summary, and shuts down when every car has done its laps (mark it required="true"
// in a launch file to end the race there). Exit code 0 when every car finished, 1 on a time-out.
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <roar_ros/CollisionEvent.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>

#include "roar/race/lap_timer.h"
#include "roar/ros/param_reading.h"
#include "roar/track/map_folder.h"

using namespace roar;

namespace {

struct Car {
  std::unique_ptr<race::LapTimer> timer;
  ros::Subscriber odom, collision;
  int barrier_contacts = 0;
  int car_contacts = 0;
  double last_contact_time = -1e9;
  bool finished = false;
};

void writeResults(const std::string& dir, const std::string& map_name, const std::map<std::string, Car>& cars,
                  bool complete) {
  std::filesystem::create_directories(dir);
  std::ofstream yaml(dir + "/results.yaml"), csv(dir + "/laps.csv");
  yaml << std::setprecision(10);
  csv << std::setprecision(10);
  yaml << "map: " << map_name << "\nstatus: " << (complete ? "finished" : "timed_out") << "\ncars:\n";
  csv << "car,lap,lap_time_s,sector_times_s\n";
  for (const auto& [name, car] : cars) {
    yaml << "  - name: " << name << "\n    laps_completed: " << car.timer->lapsCompleted()
         << "\n    barrier_contacts: " << car.barrier_contacts << "\n    car_contacts: " << car.car_contacts;
    if (auto best = car.timer->bestLap()) yaml << "\n    best_lap_s: " << *best;
    yaml << "\n    laps:\n";
    for (const auto& lap : car.timer->laps()) {
      yaml << "      - {lap: " << lap.lap << ", time_s: " << lap.lap_time << ", sectors_s: [";
      std::string sectors;
      for (std::size_t k = 0; k < lap.sector_times.size(); ++k) {
        yaml << (k ? ", " : "") << lap.sector_times[k];
        sectors += (k ? ";" : "") + std::to_string(lap.sector_times[k]);
      }
      yaml << "]}\n";
      csv << name << "," << lap.lap << "," << lap.lap_time << "," << sectors << "\n";
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "race_control");
  ros::NodeHandle nh, pnh("~");
  try {
    using namespace ros_bridge;
    const std::string pkg = packagePath();
    std::string folder;
    try {
      folder = track::resolveMapFolder(readString(pnh, "map", "roar_ring"), readString(pnh, "maps_dir", pkg + "/maps"));
    } catch (const track::MapError& e) {
      throw ParamError("parameter " + pnh.resolveName("map") + ": " + e.what());
    }
    const track::Track track = track::loadMapFolder(folder);
    const std::vector<std::string> names = readStringList(pnh, "vehicles", {"ego"});
    const int laps = readInt(pnh, "laps", 3, 1, 1000);
    const double max_time = readDouble(pnh, "max_sim_time", 0.0, 0.0, 1e7);
    const std::string output_dir = readString(pnh, "output_dir", "");

    std::map<std::string, Car> cars;
    double now = 0.0;
    for (const auto& name : names) {
      Car& car = cars[name];
      car.timer = std::make_unique<race::LapTimer>(track);
      car.odom = nh.subscribe<nav_msgs::Odometry>(name + "/odom", 100, [&, name](const nav_msgs::Odometry::ConstPtr& odom) {
        Car& c = cars[name];
        now = std::max(now, odom->header.stamp.toSec());
        if (c.finished) return;
        const auto lap = c.timer->update(odom->header.stamp.toSec(),
                                         Eigen::Vector2d(odom->pose.pose.position.x, odom->pose.pose.position.y));
        if (!lap) return;
        std::string sectors;
        for (double s : lap->sector_times) {
          char buf[32];
          std::snprintf(buf, sizeof(buf), "%s%.3f", sectors.empty() ? "" : " / ", s);
          sectors += buf;
        }
        std::printf("%s lap %d: %.3f s (sectors %s)\n", name.c_str(), lap->lap, lap->lap_time, sectors.c_str());
        std::fflush(stdout);
        if (lap->lap >= laps) c.finished = true;
      });
      car.collision = nh.subscribe<roar_ros::CollisionEvent>(name + "/collision", 100,
                                                             [&, name](const roar_ros::CollisionEvent::ConstPtr& ev) {
        Car& c = cars[name];
        // One contact lasting several ticks counts once.
        const double t = ev->header.stamp.toSec();
        if (t - c.last_contact_time > 0.5) {
          if (ev->other == "barrier") ++c.barrier_contacts;
          else if (ev->other != "ground") ++c.car_contacts;
        }
        c.last_contact_time = t;
      });
    }
    std::printf("race_control: %d lap(s) of %s (%.0f m) for %zu car(s)\n", laps, track.info().name.c_str(), track.length(),
                cars.size());
    std::fflush(stdout);

    bool complete = false;
    // Wall-time loop: the race ends on simulated events, not on a clock of ours.
    while (ros::ok()) {
      ros::spinOnce();
      complete = std::all_of(cars.begin(), cars.end(), [](const auto& kv) { return kv.second.finished; });
      if (complete || (max_time > 0 && now > max_time)) break;
      ros::WallDuration(0.002).sleep();
    }
    std::printf("race_control: race %s at t = %.2f s\n", complete ? "finished" : "timed out", now);
    for (const auto& [name, car] : cars) {
      const auto best = car.timer->bestLap();
      std::printf("  %s: %d/%d laps, best lap %s s, barrier contacts %d, car contacts %d\n", name.c_str(),
                  car.timer->lapsCompleted(), laps, best ? std::to_string(*best).c_str() : "-", car.barrier_contacts,
                  car.car_contacts);
    }
    if (!output_dir.empty()) {
      writeResults(output_dir, track.info().name, cars, complete);
      std::printf("race_control: results in %s/results.yaml and laps.csv\n", output_dir.c_str());
    }
    std::fflush(stdout);
    ros::shutdown();
    return complete ? 0 : 1;
  } catch (const std::exception& e) {
    ROS_FATAL("race_control: %s", e.what());
    return 1;
  }
}

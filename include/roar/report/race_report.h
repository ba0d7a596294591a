#pragma once
// The race report for people: a top-down PNG of every car's path coloured by speed, a speed-over-distance
// plot of each car's best lap against the planner's profile, and a lap-time table in Markdown.
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "roar/race/race_control.h"

namespace roar::report {

struct TelemetrySample {
  double time = 0.0;  // s
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  double speed = 0.0;  // m/s
};
using Telemetry = std::map<std::string, std::vector<TelemetrySample>>;

// The planner's promise: speed by distance from the start/finish line along the track's centre line.
struct ProfilePoint {
  double progress = 0.0;  // m
  double speed = 0.0;     // m/s
};

struct Series {
  std::string label;
  std::vector<double> x, y;
  Eigen::Vector3i bgr = Eigen::Vector3i(255, 255, 255);
};

// A line plot with axes, grid and a legend; the y axis starts at zero or below the lowest value. Throws
// std::runtime_error when the file cannot be written.
void renderPlot(const std::string& png_path, const std::string& title, const std::string& x_label,
                const std::string& y_label, const std::vector<Series>& series, int width_px = 1200,
                int height_px = 520);

// trajectories.png, speed_<car>.png for every car with a lap, laps.md; returns the files written.
std::vector<std::string> writeRaceReport(const std::string& dir, const race::RaceControl& race,
                                         const Telemetry& telemetry, const std::vector<ProfilePoint>& profile);

}  // namespace roar::report

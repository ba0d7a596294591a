#include "roar/report/race_report.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "roar/track/track_preview.h"

namespace roar::report {

namespace {

// A round step for axis ticks: 1, 2 or 5 times a power of ten, about `span / 8`.
double tickStep(double span) {
  const double raw = span / 8.0;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10.0 * power;
}

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, v);
  return buf;
}

}  // namespace

void renderPlot(const std::string& png_path, const std::string& title, const std::string& x_label,
                const std::string& y_label, const std::vector<Series>& series, int width_px, int height_px) {
  double x_lo = 1e300, x_hi = -1e300, y_lo = 0.0, y_hi = -1e300;
  for (const auto& s : series) {
    for (double x : s.x) x_lo = std::min(x_lo, x), x_hi = std::max(x_hi, x);
    for (double y : s.y) y_lo = std::min(y_lo, y), y_hi = std::max(y_hi, y);
  }
  if (!(x_hi > x_lo)) x_lo = 0, x_hi = 1;
  if (!(y_hi > y_lo)) y_hi = y_lo + 1;
  const double margin = 0.08 * (y_hi - y_lo);
  y_hi += margin;
  if (y_lo < 0) y_lo -= margin;
  cv::Mat image(height_px, width_px, CV_8UC3, cv::Scalar(30, 30, 30));
  // The legend has a row of its own under the x axis's label: it covers no curve.
  const int left = 80, right = 20, top = 50, legend_row = 30, bottom = 60 + legend_row;
  auto px = [&](double x, double y) {
    return cv::Point(left + static_cast<int>((x - x_lo) / (x_hi - x_lo) * (width_px - left - right)),
                     height_px - bottom - static_cast<int>((y - y_lo) / (y_hi - y_lo) * (height_px - top - bottom)));
  };
  const cv::Scalar grid(70, 70, 70), text(230, 230, 230);
  const double dx = tickStep(x_hi - x_lo), dy = tickStep(y_hi - y_lo);
  for (double x = std::ceil(x_lo / dx) * dx; x <= x_hi; x += dx) {
    cv::line(image, px(x, y_lo), px(x, y_hi), grid, 1);
    cv::putText(image, format("%.0f", x), px(x, y_lo) + cv::Point(-15, 22), cv::FONT_HERSHEY_SIMPLEX, 0.5, text, 1,
                cv::LINE_AA);
  }
  for (double y = std::ceil(y_lo / dy) * dy; y <= y_hi; y += dy) {
    cv::line(image, px(x_lo, y), px(x_hi, y), grid, 1);
    cv::putText(image, format("%.0f", y), px(x_lo, y) + cv::Point(-45, 5), cv::FONT_HERSHEY_SIMPLEX, 0.5, text, 1,
                cv::LINE_AA);
  }
  cv::putText(image, title, {left, 26}, cv::FONT_HERSHEY_SIMPLEX, 0.8, text, 2, cv::LINE_AA);
  cv::putText(image, x_label, {width_px / 2 - 60, height_px - 15 - legend_row}, cv::FONT_HERSHEY_SIMPLEX, 0.6, text, 1,
              cv::LINE_AA);
  cv::putText(image, y_label, {8, top - 6}, cv::FONT_HERSHEY_SIMPLEX, 0.5, text, 1, cv::LINE_AA);
  int legend_x = left;
  const int legend_y = height_px - 12;
  for (const auto& s : series) {
    const cv::Scalar colour(s.bgr.x(), s.bgr.y(), s.bgr.z());
    std::vector<cv::Point> pts;
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) pts.push_back(px(s.x[i], s.y[i]));
    if (pts.size() > 1) cv::polylines(image, pts, false, colour, 2, cv::LINE_AA);
    cv::line(image, {legend_x, legend_y - 5}, {legend_x + 30, legend_y - 5}, colour, 3);
    cv::putText(image, s.label, {legend_x + 38, legend_y}, cv::FONT_HERSHEY_SIMPLEX, 0.55, text, 1, cv::LINE_AA);
    legend_x += 70 + 11 * static_cast<int>(s.label.size());
  }
  if (!cv::imwrite(png_path, image)) throw std::runtime_error(png_path + ": cannot write the plot");
}

std::vector<std::string> writeRaceReport(const std::string& dir, const race::RaceControl& race,
                                         const Telemetry& telemetry, const std::vector<ProfilePoint>& profile) {
  std::filesystem::create_directories(dir);
  const track::Track& track = race.track();
  std::vector<std::string> written;

  std::vector<track::ValuedPath> paths;
  for (const auto& [name, samples] : telemetry) {
    track::ValuedPath path;
    path.label = name;
    for (const auto& sample : samples) {
      path.points.push_back(sample.position);
      path.values.push_back(sample.speed * 3.6);
    }
    paths.push_back(std::move(path));
  }
  // Every pass where the passer was when it got by.
  std::vector<track::MapMark> passes;
  for (const auto& o : race.overtakes()) {
    const auto samples = telemetry.find(o.passer);
    if (samples == telemetry.end() || samples->second.empty()) continue;
    const auto at = std::lower_bound(samples->second.begin(), samples->second.end(), o.time,
                                     [](const TelemetrySample& sample, double t) { return sample.time < t; });
    const TelemetrySample& where = at == samples->second.end() ? samples->second.back() : *at;
    passes.push_back({where.position, o.passer + " > " + o.passed + " (lap " + std::to_string(o.lap) +
                                          format(", t = %.1f s)", o.time)});
  }
  track::renderTrackPreview(track, dir + "/trajectories.png", 1400, paths, "speed km/h", passes);
  written.push_back(dir + "/trajectories.png");

  for (const auto& [name, car] : race.cars()) {
    const auto& laps = car.timer.laps();
    if (laps.empty() || !telemetry.count(name)) continue;
    const race::LapRecord& best =
        *std::min_element(laps.begin(), laps.end(),
                          [](const race::LapRecord& a, const race::LapRecord& b) { return a.lap_time < b.lap_time; });
    Series driven{name + " lap " + std::to_string(best.lap) + format(" (%.2f s)", best.lap_time),
                  {},
                  {},
                  Eigen::Vector3i(255, 160, 40)};
    double near = track.info().start_finish_s;
    for (const auto& sample : telemetry.at(name)) {
      if (sample.time < best.finish_time - best.lap_time || sample.time > best.finish_time) continue;
      const auto pr = track.projectNear(sample.position, near, 100.0);
      near = pr.s;
      const double progress = track.raceProgress(pr.s);
      // Just after the line the progress of the lap's first samples can read as a whole lap.
      if (!driven.x.empty() && progress < driven.x.back() - 0.5 * track.length()) break;
      driven.x.push_back(progress);
      driven.y.push_back(sample.speed * 3.6);
    }
    std::vector<Series> series = {driven};
    if (!profile.empty()) {
      Series promised{"planner's profile", {}, {}, Eigen::Vector3i(80, 220, 80)};
      for (const auto& p : profile) {
        promised.x.push_back(p.progress);
        promised.y.push_back(p.speed * 3.6);
      }
      series.insert(series.begin(), promised);
    }
    const std::string png = dir + "/speed_" + name + ".png";
    renderPlot(png, name + ": speed over the best lap, " + track.info().name, "distance from the line (m)", "km/h",
               series);
    written.push_back(png);
  }

  std::ofstream md(dir + "/laps.md");
  md << "# " << track.info().name << ": " << race.rules().laps
     << " laps\n\n| position | car | laps | best lap (s) | penalties (s) | in traffic (s) | lost in traffic (s) |";
  int most = 0;
  for (const auto& [name, car] : race.cars()) most = std::max(most, car.timer.lapsCompleted());
  for (int k = 1; k <= most; ++k) md << " lap " << k << " (s) |";
  md << "\n| --- | --- | --- | --- | --- | --- | --- |";
  for (int k = 1; k <= most; ++k) md << " --- |";
  md << "\n";
  for (const auto& standing : race.standings()) {
    const auto& car = race.car(standing.name);
    const auto best = car.timer.bestLap();
    const double lost = race.timeLostInTraffic(standing.name);
    md << "| " << standing.position << " | " << standing.name << " | " << car.timer.lapsCompleted() << " | "
       << (best ? format("%.3f", *best) : "-") << " | " << format("%.1f", car.penalties) << " | "
       << format("%.1f", car.time_in_traffic) << " | " << (std::isfinite(lost) ? format("%.1f", lost) : "-") << " |";
    for (int k = 0; k < most; ++k) {
      md << " " << (k < car.timer.lapsCompleted() ? format("%.3f", car.timer.laps()[k].lap_time) : "-") << " |";
    }
    md << "\n";
  }
  if (!md) throw std::runtime_error(dir + "/laps.md: cannot write the lap table");
  written.push_back(dir + "/laps.md");
  return written;
}

}  // namespace roar::report

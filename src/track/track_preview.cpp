#include "roar/track/track_preview.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace roar::track {

void renderTrackPreview(const Track& track, const std::string& png_path, int width_px,
                        const std::vector<ValuedPath>& paths, const std::string& value_name,
                        const std::vector<MapMark>& marks) {
  const double margin = 40.0 + track.info().barrier_offset;
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (std::size_t i = 0; i < track.size(); ++i) {
    lo = lo.cwiseMin(track.position(i));
    hi = hi.cwiseMax(track.position(i));
  }
  lo.array() -= margin;
  hi.array() += margin;
  const double scale = width_px / (hi.x() - lo.x());
  const int height_px = static_cast<int>((hi.y() - lo.y()) * scale) + 60;
  cv::Mat image(height_px, width_px, CV_8UC3, cv::Scalar(70, 130, 60));  // grass (BGR)
  auto px = [&](const Eigen::Vector2d& p) {
    return cv::Point(static_cast<int>((p.x() - lo.x()) * scale), static_cast<int>((hi.y() - p.y()) * scale) + 60);
  };
  auto polygon = [&](auto&& edge) {
    std::vector<cv::Point> pts;
    for (std::size_t i = 0; i < track.size(); ++i) pts.push_back(px(edge(i)));
    return pts;
  };
  const double offset = track.info().barrier_offset;
  const auto barrier_l = polygon([&](std::size_t i) { return track.leftEdge(i, offset); });
  const auto barrier_r = polygon([&](std::size_t i) { return track.rightEdge(i, offset); });
  // The road as one quad per segment (works for either winding of the circuit).
  for (std::size_t i = 0; i < track.size(); ++i) {
    const std::size_t j = (i + 1) % track.size();
    std::vector<cv::Point> quad = {px(track.leftEdge(i)), px(track.leftEdge(j)), px(track.rightEdge(j)), px(track.rightEdge(i))};
    cv::fillConvexPoly(image, quad, cv::Scalar(85, 85, 85), cv::LINE_AA);
  }
  cv::polylines(image, barrier_l, true, cv::Scalar(220, 220, 220), 2, cv::LINE_AA);
  cv::polylines(image, barrier_r, true, cv::Scalar(220, 220, 220), 2, cv::LINE_AA);
  cv::polylines(image, polygon([&](std::size_t i) { return track.position(i); }), true, cv::Scalar(200, 200, 200), 1,
                cv::LINE_AA);
  auto line_across = [&](double s, const cv::Scalar& colour, int thickness) {
    const TrackPose pose = track.poseAt(s);
    const Eigen::Vector2d normal(-std::sin(pose.heading), std::cos(pose.heading));
    cv::line(image, px(pose.position + normal * pose.width_left), px(pose.position - normal * pose.width_right), colour,
             thickness, cv::LINE_AA);
  };
  const int sectors = track.info().sectors;
  for (int k = 1; k < sectors; ++k) {
    line_across(track.info().start_finish_s + k * track.length() / sectors, cv::Scalar(0, 200, 255), 3);
  }
  line_across(track.info().start_finish_s, cv::Scalar(255, 255, 255), 5);
  // Direction arrow just after the line.
  const TrackPose a = track.poseAt(track.info().start_finish_s + 20), b = track.poseAt(track.info().start_finish_s + 60);
  cv::arrowedLine(image, px(a.position), px(b.position), cv::Scalar(0, 0, 255), 3, cv::LINE_AA, 0, 0.3);
  char title[256];
  std::snprintf(title, sizeof(title), "%s  %.0f m  %d sectors  (100 m = %d px)", track.info().name.c_str(),
                track.length(), sectors, static_cast<int>(100 * scale));
  cv::putText(image, title, cv::Point(12, 38), cv::FONT_HERSHEY_SIMPLEX, 0.9, cv::Scalar(255, 255, 255), 2, cv::LINE_AA);
  if (!paths.empty()) {
    double v_lo = 1e300, v_hi = -1e300;
    for (const auto& path : paths) {
      for (double v : path.values) v_lo = std::min(v_lo, v), v_hi = std::max(v_hi, v);
    }
    if (!(v_hi > v_lo)) v_hi = v_lo + 1.0;
    cv::Mat ramp(1, 256, CV_8UC1), colours;
    for (int k = 0; k < 256; ++k) ramp.at<uchar>(0, k) = static_cast<uchar>(k);
    cv::applyColorMap(ramp, colours, cv::COLORMAP_JET);
    auto colourOf = [&](double v) {
      const int k = std::clamp(static_cast<int>((v - v_lo) / (v_hi - v_lo) * 255.0), 0, 255);
      const cv::Vec3b c = colours.at<cv::Vec3b>(0, k);
      return cv::Scalar(c[0], c[1], c[2]);
    };
    for (const auto& path : paths) {
      for (std::size_t i = 0; i + 1 < path.points.size(); ++i) {
        cv::line(image, px(path.points[i]), px(path.points[i + 1]), colourOf(path.values[i]), 3, cv::LINE_AA);
      }
    }
    // The scale, bottom left.
    const int x0 = 20, y0 = image.rows - 40, w = 300;
    for (int k = 0; k < w; ++k) cv::line(image, {x0 + k, y0}, {x0 + k, y0 + 16}, colourOf(v_lo + (v_hi - v_lo) * k / w));
    char label[96];
    std::snprintf(label, sizeof(label), "%s %.1f .. %.1f", value_name.c_str(), v_lo, v_hi);
    cv::putText(image, label, {x0, y0 - 8}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  }
  // Marks: a numbered ring on the map, the numbers listed top right (labels on the map would overlap).
  int list_y = 70;
  for (std::size_t k = 0; k < marks.size(); ++k) {
    const cv::Point at = px(marks[k].position);
    const std::string number = std::to_string(k + 1);
    cv::circle(image, at, 11, cv::Scalar(255, 255, 255), 2, cv::LINE_AA);
    cv::putText(image, number, at + cv::Point(13, -10), cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(255, 255, 255), 2,
                cv::LINE_AA);
    if (list_y < image.rows - 80) {
      cv::putText(image, number + "  " + marks[k].label, {image.cols - 330, list_y}, cv::FONT_HERSHEY_SIMPLEX, 0.55,
                  cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
      list_y += 22;
    }
  }
  if (!cv::imwrite(png_path, image)) throw std::runtime_error(png_path + ": cannot write the preview image");
}

}  // namespace roar::track

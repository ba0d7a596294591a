#include "roar/track/track_preview.h"

#include <algorithm>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "roar/track/bridges.h"
#include "roar/track/heading.h"

namespace roar::track {

namespace {
constexpr std::size_t kMaxListedMarks = 40;  // the rest are counted
}  // namespace

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
  const int map_bottom = static_cast<int>((hi.y() - lo.y()) * scale) + 60;
  // Below the map, a band for the legend (the scale, or each car's colour) and the marks' list: nothing
  // drawn there covers a path.
  const std::size_t listed = std::min<std::size_t>(marks.size(), kMaxListedMarks);
  const int band = (paths.empty() ? 0 : 44) + (marks.empty() ? 0 : 22 * static_cast<int>(listed + 1));
  cv::Mat image(map_bottom + band, width_px, CV_8UC3, cv::Scalar(70, 130, 60));  // grass (BGR)
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
  for (std::size_t i = 0; i < track.segments(); ++i) {
    const std::size_t j = (i + 1) % track.size();
    std::vector<cv::Point> quad = {px(track.leftEdge(i)), px(track.leftEdge(j)), px(track.rightEdge(j)),
                                   px(track.rightEdge(i))};
    cv::fillConvexPoly(image, quad, cv::Scalar(85, 85, 85), cv::LINE_AA);
  }
  cv::polylines(image, barrier_l, track.closed(), cv::Scalar(220, 220, 220), 2, cv::LINE_AA);
  cv::polylines(image, barrier_r, track.closed(), cv::Scalar(220, 220, 220), 2, cv::LINE_AA);
  cv::polylines(image, polygon([&](std::size_t i) { return track.position(i); }), track.closed(),
                cv::Scalar(200, 200, 200), 1, cv::LINE_AA);
  // A bridge's deck over the road below it, its parapets at the road's edge.
  const std::vector<bool> deck = bridgeDeckPoints(track);
  for (std::size_t i = 0; i < track.segments(); ++i) {
    const std::size_t j = (i + 1) % track.size();
    if (!deck[i] || !deck[j]) continue;
    std::vector<cv::Point> quad = {px(track.leftEdge(i, kParapetOffset)), px(track.leftEdge(j, kParapetOffset)),
                                   px(track.rightEdge(j, kParapetOffset)), px(track.rightEdge(i, kParapetOffset))};
    cv::fillConvexPoly(image, quad, cv::Scalar(95, 95, 95), cv::LINE_AA);
    for (double side : {+1.0, -1.0}) {
      auto edge = [&](std::size_t k) {
        return side > 0 ? track.leftEdge(k, kParapetOffset) : track.rightEdge(k, kParapetOffset);
      };
      cv::line(image, px(edge(i)), px(edge(j)), cv::Scalar(220, 220, 220), 2, cv::LINE_AA);
    }
    cv::line(image, px(track.position(i)), px(track.position(j)), cv::Scalar(200, 200, 200), 1, cv::LINE_AA);
  }
  auto line_across = [&](double s, const cv::Scalar& colour, int thickness) {
    const TrackPose pose = track.poseAt(s);
    const Eigen::Vector2d normal = track::leftOf(pose.heading);
    cv::line(image, px(pose.position + normal * pose.width_left), px(pose.position - normal * pose.width_right), colour,
             thickness, cv::LINE_AA);
  };
  const int sectors = track.info().sectors;
  for (int k = 1; k < sectors; ++k) {
    line_across(track.info().start_finish_s + k * track.raceDistance() / sectors, cv::Scalar(0, 200, 255), 3);
  }
  line_across(track.info().start_finish_s, cv::Scalar(255, 255, 255), 5);
  if (!track.closed()) {  // a course's finish line, chequered black and white
    line_across(track.finishLine(), cv::Scalar(255, 255, 255), 7);
    line_across(track.finishLine(), cv::Scalar(0, 0, 0), 3);
  }
  // The direction of travel: an arrow beside the road just after the line, 30 px outside the barrier at
  // any scale, where it covers neither a path nor a mark, labelled on the map.
  const auto beside = [&](double s) {
    const TrackPose pose = track.poseAt(track.info().start_finish_s + s);
    return Eigen::Vector2d(pose.position + track::leftOf(pose.heading) * (pose.width_left + offset + 30.0 / scale));
  };
  const double arrow_length = 100.0 / scale;  // m: 100 px on any map
  cv::arrowedLine(image, px(beside(10)), px(beside(10 + arrow_length)), cv::Scalar(0, 0, 255), 3, cv::LINE_AA, 0, 0.25);
  cv::putText(image, "direction", px(beside(10 + arrow_length / 2)) + cv::Point(-40, -12), cv::FONT_HERSHEY_SIMPLEX,
              0.5, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  char title[256];
  std::snprintf(title, sizeof(title), "%s  %.0f m%s  %d sectors  (100 m = %d px)", track.info().name.c_str(),
                track.raceDistance(), track.closed() ? "" : " start to finish", sectors, static_cast<int>(100 * scale));
  cv::putText(image, title, cv::Point(12, 38), cv::FONT_HERSHEY_SIMPLEX, 0.9, cv::Scalar(255, 255, 255), 2,
              cv::LINE_AA);
  const cv::Scalar white(255, 255, 255);
  int band_y = map_bottom + 28;
  if (paths.size() == 1) {
    // One car: coloured by its value (speed), with the scale.
    double v_lo = 1e300, v_hi = -1e300;
    for (double v : paths.front().values) v_lo = std::min(v_lo, v), v_hi = std::max(v_hi, v);
    if (!(v_hi > v_lo)) v_hi = v_lo + 1.0;
    cv::Mat ramp(1, 256, CV_8UC1), colours;
    for (int k = 0; k < 256; ++k) ramp.at<uchar>(0, k) = static_cast<uchar>(k);
    cv::applyColorMap(ramp, colours, cv::COLORMAP_JET);
    auto colourOf = [&](double v) {
      const int k = std::clamp(static_cast<int>((v - v_lo) / (v_hi - v_lo) * 255.0), 0, 255);
      const cv::Vec3b c = colours.at<cv::Vec3b>(0, k);
      return cv::Scalar(c[0], c[1], c[2]);
    };
    const auto& path = paths.front();
    for (std::size_t i = 0; i + 1 < path.points.size(); ++i) {
      cv::line(image, px(path.points[i]), px(path.points[i + 1]), colourOf(path.values[i]), 3, cv::LINE_AA);
    }
    char label[160];
    std::snprintf(label, sizeof(label), "%s: %s %.1f .. %.1f", path.label.c_str(), value_name.c_str(), v_lo, v_hi);
    cv::putText(image, label, {20, band_y}, cv::FONT_HERSHEY_SIMPLEX, 0.6, white, 1, cv::LINE_AA);
    const int x0 = 40 + 11 * static_cast<int>(std::string(label).size()), w = 300;
    for (int k = 0; k < w; ++k)
      cv::line(image, {x0 + k, band_y - 14}, {x0 + k, band_y + 2}, colourOf(v_lo + (v_hi - v_lo) * k / w));
    band_y += 22;
  } else if (!paths.empty()) {
    // Several cars: each its own colour (the speeds are in each car's speed plot), named in the legend. The
    // first is drawn widest and each next one narrower, so cars on the same line show as nested stripes
    // (RaceReport.CarsOnTheSameLineEachShowTheirColour).
    static const cv::Scalar kPalette[] = {{255, 140, 30}, {14, 127, 255},  {40, 39, 214}, {189, 103, 148},
                                          {230, 220, 40}, {194, 119, 227}, {0, 215, 255}, {245, 245, 245},
                                          {75, 86, 140},  {34, 189, 188}};
    constexpr std::size_t kColours = sizeof(kPalette) / sizeof(kPalette[0]);
    int x = 20;
    for (std::size_t k = 0; k < paths.size(); ++k) {
      const cv::Scalar colour = kPalette[k % kColours];
      const auto& path = paths[k];
      const int width = 2 + 4 * static_cast<int>(std::min<std::size_t>(paths.size() - 1 - k, 5));
      for (std::size_t i = 0; i + 1 < path.points.size(); ++i) {
        cv::line(image, px(path.points[i]), px(path.points[i + 1]), colour, width, cv::LINE_AA);
      }
      cv::line(image, {x, band_y - 6}, {x + 30, band_y - 6}, colour, 4, cv::LINE_AA);
      cv::putText(image, path.label, {x + 38, band_y}, cv::FONT_HERSHEY_SIMPLEX, 0.6, white, 1, cv::LINE_AA);
      x += 60 + 12 * static_cast<int>(path.label.size());
    }
    band_y += 22;
  }
  // Marks: a numbered ring on the map, listed with their numbers in the band below it.
  for (std::size_t k = 0; k < marks.size(); ++k) {
    const cv::Point at = px(marks[k].position);
    const std::string number = std::to_string(k + 1);
    cv::circle(image, at, 11, white, 2, cv::LINE_AA);
    cv::putText(image, number, at + cv::Point(13, -10), cv::FONT_HERSHEY_SIMPLEX, 0.6, white, 2, cv::LINE_AA);
    if (k < listed) {
      cv::putText(image, number + "  " + marks[k].label, {20, band_y}, cv::FONT_HERSHEY_SIMPLEX, 0.55, white, 1,
                  cv::LINE_AA);
      band_y += 22;
    }
  }
  if (marks.size() > listed) {
    cv::putText(image, "... and " + std::to_string(marks.size() - listed) + " more", {20, band_y},
                cv::FONT_HERSHEY_SIMPLEX, 0.55, white, 1, cv::LINE_AA);
  }
  if (!cv::imwrite(png_path, image)) throw std::runtime_error(png_path + ": cannot write the preview image");
}

}  // namespace roar::track

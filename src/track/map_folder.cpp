#include "roar/track/map_folder.h"

#include "roar/track/waypoints.h"

#include "roar/config/number.h"
#include "roar/config/text_file.h"
#include "roar/config/yaml_section.h"
#include "roar/track/circuit_builder.h"
#include "roar/track/npz.h"
#include "roar/track/waypoints.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "roar/track/bridges.h"
#include "roar/track/segment_intersection.h"

namespace roar::track {
namespace fs = std::filesystem;

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string f;
  while (std::getline(ss, f, ',')) out.push_back(trim(f));
  return out;
}

}  // namespace

namespace {

std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

constexpr const char* kCentreLineColumns[] = {"x_m", "y_m", "w_tr_right_m", "w_tr_left_m", "z_m", "banking_rad"};

// A line before the first point whose every field is a word (x_m,y_m,...) is a header written without '#';
// any other line must be a point, so a row without commas is an error rather than a skipped header.
bool isHeader(const std::vector<std::string>& fields) {
  double v;
  return fields.size() >= 4 &&
         std::none_of(fields.begin(), fields.end(), [&](const std::string& f) { return config::parseNumber(f, &v); });
}

CentreLinePoint parseCentreLineRow(const std::vector<std::string>& fields, const std::string& where) {
  double v[6] = {0, 0, 0, 0, 0, 0};
  for (std::size_t k = 0; k < fields.size(); ++k) {
    if (!config::parseNumber(fields[k], &v[k]))
      throw MapError(where + ": column " + kCentreLineColumns[k] + " is not a number");
    if (!std::isfinite(v[k])) throw MapError(where + ": column " + kCentreLineColumns[k] + " is not finite");
  }
  for (int k = 2; k < 4; ++k) {
    if (v[k] <= 0) throw MapError(where + ": " + kCentreLineColumns[k] + " must be positive, got " + fields[k]);
  }
  const CentreLinePoint point{v[0], v[1], v[2], v[3], v[4], v[5]};
  // The Track takes any positive width (a planner test may want a road narrower than its car); a map may not.
  if (point.width_right + point.width_left < kMinRoadWidth) {
    throw MapError(where + ": the road is " + shortNumber(point.width_right + point.width_left) +
                   " m wide (w_tr_right_m + w_tr_left_m), less than " + shortNumber(kMinRoadWidth) + " m");
  }
  if (std::abs(point.banking) >= M_PI / 4) throw MapError(where + ": banking_rad must be within (-pi/4, pi/4)");
  const std::string problem = centreLinePointProblem(point);
  if (!problem.empty()) throw MapError(where + ": " + problem);
  return point;
}

// A rise no road has between two points is a typo (a stray column, a decimal comma), not a deck.
void checkGrades(const CentreLineFile& file, const std::string& path) {
  for (std::size_t i = 1; i < file.points.size(); ++i) {
    const auto& a = file.points[i - 1];
    const auto& b = file.points[i];
    const double grade = std::abs(b.z - a.z) / std::hypot(b.x - a.x, b.y - a.y);
    if (grade > kMaxGrade) {
      throw MapError(path + ":" + std::to_string(file.lines[i]) + ": z_m rises " + std::to_string(b.z - a.z) +
                     " m over " + std::to_string(std::hypot(b.x - a.x, b.y - a.y)) + " m from the previous point, " +
                     "a grade above " + std::to_string(kMaxGrade));
    }
  }
}

}  // namespace

CentreLineFile readCentreLineCsv(const std::string& path) {
  std::istringstream in(config::readTextFile<MapError>(path, config::kMaxTableBytes));
  CentreLineFile file;
  std::size_t columns = 0;  // fixed by the first point: every row has as many
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    const auto fields = splitFields(text);
    const std::string where = path + ":" + std::to_string(line_no);
    if (file.points.empty() && columns == 0 && isHeader(fields)) continue;
    if (columns == 0) {
      if (fields.size() < 4 || fields.size() > 6) {
        throw MapError(where + ": expected 4 columns x_m,y_m,w_tr_right_m,w_tr_left_m (then z_m,banking_rad), found " +
                       std::to_string(fields.size()));
      }
      columns = fields.size();
    } else if (fields.size() != columns) {
      throw MapError(where + ": expected " + std::to_string(columns) + " columns as the first point has, found " +
                     std::to_string(fields.size()) + " (a stray comma, or a decimal comma?)");
    }
    const CentreLinePoint point = parseCentreLineRow(fields, where);
    if (!file.points.empty() && std::hypot(point.x - file.points.back().x, point.y - file.points.back().y) < 1e-6)
      throw MapError(where + ": point repeats the previous one");
    if (file.points.size() >= kMaxCentreLinePoints)
      throw MapError(where + ": more than " + std::to_string(kMaxCentreLinePoints) + " centre-line points");
    file.points.push_back(point);
    file.lines.push_back(line_no);
  }
  // A closed loop written with its first point repeated at the end is the same circuit.
  if (file.points.size() > 3 &&
      std::hypot(file.points.front().x - file.points.back().x, file.points.front().y - file.points.back().y) < 1e-6) {
    file.points.pop_back();
    file.lines.pop_back();
  }
  if (file.points.size() < 3) {
    throw MapError(path + ": a circuit needs at least 3 centre-line points, found " +
                   std::to_string(file.points.size()));
  }
  checkGrades(file, path);
  return file;
}

void writeCentreLineCsv(const std::string& path, const std::vector<CentreLinePoint>& points) {
  std::ofstream out(path);
  if (!out) throw MapError(path + ": cannot write the centre-line file");
  const bool relief =
      std::any_of(points.begin(), points.end(), [](const auto& p) { return p.z != 0 || p.banking != 0; });
  out << "# x_m,y_m,w_tr_right_m,w_tr_left_m" << (relief ? ",z_m,banking_rad" : "") << "\n" << std::setprecision(17);
  for (const auto& p : points) {
    out << p.x << "," << p.y << "," << p.width_right << "," << p.width_left;
    if (relief) out << "," << p.z << "," << p.banking;
    out << "\n";
  }
}

void checkEdges(const Track& track, const std::string& path, const std::vector<int>& lines) {
  const std::size_t n = track.size();
  // Closure: the way back from the last point to the first is no longer than the other steps.
  const LoopGap gap = loopGap(track.points());
  if (track.closed() && gap.open()) {
    throw MapError(path + ": the centre line does not close: its last point is " + std::to_string(gap.gap) +
                   " m from its first (a circuit's last point should be about one step from the first; a "
                   "point-to-point course says `course: point_to_point` in its track.yaml)");
  }
  std::vector<Eigen::Vector2d> left(n), right(n);
  for (std::size_t i = 0; i < n; ++i) {
    left[i] = track.leftEdge(i);
    right[i] = track.rightEdge(i);
  }
  auto where = [&](std::size_t i) {
    return lines.empty() ? "centre-line point " + std::to_string(i) : "line " + std::to_string(lines[i]);
  };
  // An edge offset further than the corner's radius runs backwards there: the corner is too tight for the width.
  const std::size_t segments = track.closed() ? n : n - 1;
  for (std::size_t i = 0; i < segments; ++i) {
    const std::size_t j = (i + 1) % n;
    const Eigen::Vector2d centre = track.position(j) - track.position(i);
    for (const auto* edge : {&left, &right}) {
      if (((*edge)[j] - (*edge)[i]).dot(centre) <= 0) {
        const double radius = std::abs(track.curvature(i)) > 0 ? 1.0 / std::abs(track.curvature(i)) : 0.0;
        throw MapError(path + ":" + (lines.empty() ? "" : std::to_string(lines[i]) + ":") + " the " +
                       (edge == &left ? "left" : "right") + " edge runs backwards after " + where(i) +
                       ": a corner of radius " + std::to_string(radius) + " m is too tight for the width");
      }
    }
  }
  const struct {
    const std::vector<Eigen::Vector2d>* a;
    const std::vector<Eigen::Vector2d>* b;
    const char* what;
  } pairs[] = {{&left, &left, "the left edge crosses itself"},
               {&right, &right, "the right edge crosses itself"},
               {&left, &right, "the left edge crosses the right edge"}};
  // Where the circuit crosses itself, one branch passes over the other on a bridge (bridges.h).
  auto apart = [&](std::size_t i, std::size_t j) { return std::abs(track.point(i).z - track.point(j).z); };
  auto bridged = [&](std::size_t i, std::size_t j) {
    // A course's edges end at its last point: nothing joins it to its first.
    if (!track.closed() && (i == n - 1 || j == n - 1)) return true;
    return apart(i, j) >= kBridgeClearance;
  };
  for (const auto& pair : pairs) {
    if (auto hit = findClosedPolylineCrossing(*pair.a, *pair.b, bridged)) {
      char heights[200];
      std::snprintf(heights, sizeof heights,
                    "; where a circuit crosses itself one branch must pass %.1f m over the other (track_tool import "
                    "and build raise it), and these are %.2f m apart in height",
                    kBridgeClearance, apart(hit->first, hit->second));
      throw MapError(path + ":" + (lines.empty() ? "" : std::to_string(lines[hit->first]) + ":") + " " + pair.what +
                     " between " + where(hit->first) + " and " + where(hit->second) +
                     " (a corner too tight for the width, or the centre line crosses itself" + heights + ")");
    }
  }
}

TrackInfo readTrackYaml(const std::string& path, std::string* centreline, std::string* waypoints) {
  YAML::Node root;
  try {
    root = YAML::Load(config::readTextFile<MapError>(path, config::kMaxYamlBytes));
  } catch (const YAML::Exception& e) {
    throw MapError(path + ": " + e.what());
  }
  if (!root.IsMap()) throw MapError(path + ": expected a mapping of track properties");
  // The one strict reader: a misspelt key (`frcition:`) is refused, naming the nearest known one.
  config::YamlSection<MapError> top(root, "", path);
  TrackInfo info;
  info.name = fs::path(path).parent_path().filename().string();
  top.read("name", &info.name);
  std::string file = "centerline.csv";
  top.read("centerline", &file);
  if (file.empty()) top.fail("centerline", "must name the centre-line file");
  // A map reads its own files only, whoever asks roar_sim to load it (map_folder_test FilesOutsideTheFolder).
  auto ownFile = [&](const char* field, const std::string& name) {
    if (name.find('/') != std::string::npos || name == "." || name == "..")
      top.fail(field, "must be a file name in the map folder, without '/'");
  };
  ownFile("centerline", file);
  if (centreline) *centreline = file;
  std::string waypoint_file;
  top.read("waypoints", &waypoint_file);
  if (!waypoint_file.empty()) ownFile("waypoints", waypoint_file);
  if (waypoints) *waypoints = waypoint_file;
  auto origin = top.child("origin");
  origin.read("latitude", &info.origin.latitude);
  origin.read("longitude", &info.origin.longitude);
  origin.read("altitude", &info.origin.altitude);
  origin.finish();
  auto inRange = [&](const std::string& field, double v, double lo, double hi, bool lo_open, const std::string& unit) {
    if (lo_open ? v > lo && v <= hi : v >= lo && v <= hi) return;
    top.fail(field, std::to_string(v) + unit + " is outside " + (lo_open ? "(" : "[") + std::to_string(lo) + ", " +
                        std::to_string(hi) + "]");
  };
  inRange("origin.latitude", info.origin.latitude, -90, 90, false, " degrees");
  inRange("origin.longitude", info.origin.longitude, -180, 180, false, " degrees");
  inRange("origin.altitude", info.origin.altitude, -500, 9000, false, " m");
  top.read("friction", &info.friction);
  top.read("ground_friction", &info.ground_friction);
  inRange("friction", info.friction, 0, 3, true, "");
  inRange("ground_friction", info.ground_friction, 0, 3, true, "");
  std::string course = "circuit";
  top.read("course", &course);
  if (course != "circuit" && course != "point_to_point") {
    top.fail("course", "'" + course + "' is neither 'circuit' nor 'point_to_point'");
  }
  info.closed = course == "circuit";
  auto start_finish = top.child("start_finish");
  start_finish.read("s", &info.start_finish_s);
  start_finish.finish();
  if (top.has("finish") && info.closed) top.fail("finish", "a circuit finishes on its start_finish line");
  if (!info.closed) {
    if (!top.has("finish")) top.fail("finish", "a point-to-point course needs its finish line: finish: {s: <metres>}");
    auto finish = top.child("finish");
    finish.read("s", &info.finish_s);
    finish.finish();
  }
  top.read("sectors", &info.sectors);
  inRange("sectors", info.sectors, 1, 100, false, "");
  top.read("barrier_offset", &info.barrier_offset);
  top.read("barrier_height", &info.barrier_height);
  inRange("barrier_offset", info.barrier_offset, 0, 100, false, " m");
  inRange("barrier_height", info.barrier_height, 0, 20, true, " m");
  top.finish();
  return info;
}

void writeTrackYaml(const std::string& path, const TrackInfo& info, const std::string& centreline) {
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << info.name;
  out << YAML::Key << "centerline" << YAML::Value << centreline;
  out << YAML::Key << "origin" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "latitude" << YAML::Value
      << info.origin.latitude << YAML::Key << "longitude" << YAML::Value << info.origin.longitude << YAML::Key
      << "altitude" << YAML::Value << info.origin.altitude << YAML::EndMap;
  out << YAML::Key << "friction" << YAML::Value << info.friction;
  out << YAML::Key << "ground_friction" << YAML::Value << info.ground_friction;
  if (!info.closed) out << YAML::Key << "course" << YAML::Value << "point_to_point";
  out << YAML::Key << "start_finish" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "s" << YAML::Value
      << info.start_finish_s << YAML::EndMap;
  if (!info.closed) {
    out << YAML::Key << "finish" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "s" << YAML::Value
        << info.finish_s << YAML::EndMap;
  }
  out << YAML::Key << "sectors" << YAML::Value << info.sectors;
  out << YAML::Key << "barrier_offset" << YAML::Value << info.barrier_offset;
  out << YAML::Key << "barrier_height" << YAML::Value << info.barrier_height << YAML::EndMap;
  std::ofstream file(path);
  if (!file) throw MapError(path + ": cannot write");
  file << out.c_str() << "\n";
}

void writeMapFolder(const std::string& folder, const std::vector<CentreLinePoint>& points, const TrackInfo& info) {
  const Track track(points, info);  // validates before anything is written
  // An existing map keeps its track.yaml, so the centre line goes to the file that track.yaml names.
  const fs::path yaml = fs::path(folder) / "track.yaml";
  std::string centreline = "centerline.csv";
  if (fs::exists(yaml)) readTrackYaml(yaml.string(), &centreline);
  const std::string csv = (fs::path(folder) / centreline).string();
  checkEdges(track, "the centre line for " + csv + " (nothing written)", {});
  fs::create_directories(folder);
  writeCentreLineCsv(csv, points);
  if (!fs::exists(yaml)) writeTrackYaml(yaml.string(), info);
}

std::vector<CentreLinePoint> readPointList(const std::string& path, double width) {
  if (!(width >= kMinRoadWidth))
    throw MapError(path + ": the road width must be at least " + shortNumber(kMinRoadWidth) + " m");
  std::istringstream in(config::readTextFile<MapError>(path, config::kMaxTableBytes));
  std::vector<CentreLinePoint> points;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    std::replace(text.begin(), text.end(), ',', ' ');
    std::stringstream ss(text);
    double x, y;
    if (!(ss >> x >> y) || !std::isfinite(x) || !std::isfinite(y)) {
      throw MapError(path + ":" + std::to_string(line_no) + ": expected two numbers x,y");
    }
    points.push_back({x, y, 0.5 * width, 0.5 * width});
  }
  if (points.size() < 3)
    throw MapError(path + ": a circuit needs at least 3 points, found " + std::to_string(points.size()));
  return points;
}

Track loadMapFolder(const std::string& folder) {
  const fs::path yaml_path = fs::path(folder) / "track.yaml";
  if (!fs::exists(yaml_path)) throw MapError(yaml_path.string() + ": no such file (is '" + folder + "' a map folder?)");
  std::string centreline, waypoints;
  TrackInfo info = readTrackYaml(yaml_path.string(), &centreline, &waypoints);
  const std::string csv_path = (fs::path(folder) / centreline).string();
  CentreLineFile file = readCentreLineCsv(csv_path);
  auto made = [&]() {
    try {
      return Track(std::move(file.points), std::move(info));
    } catch (const std::invalid_argument& e) {
      throw MapError(yaml_path.string() + " with " + csv_path + ": " + e.what());
    }
  };
  Track track = made();
  if (track.info().start_finish_s < 0 || track.info().start_finish_s >= track.length()) {
    throw MapError(yaml_path.string() + ": field 'start_finish.s' must be in [0, track length " +
                   std::to_string(track.length()) + ")");
  }
  checkEdges(track, csv_path, file.lines);
  if (!waypoints.empty()) {
    const std::string npz = (fs::path(folder) / waypoints).string();
    try {
      track.setRecordedWaypoints(readRoarWaypoints(npz));
    } catch (const NpzError& e) {
      throw MapError(std::string(e.what()) + " (the waypoints " + yaml_path.string() + " names)");
    } catch (const std::invalid_argument& e) {
      throw MapError(npz + " (the waypoints " + yaml_path.string() + " names) with " + csv_path + ": " + e.what());
    }
  }
  return track;
}

std::string resolveMapFolder(const std::string& map, const std::string& maps_dir) {
  if (fs::exists(fs::path(map) / "track.yaml")) return map;
  const fs::path named = fs::path(maps_dir) / map;
  if (fs::exists(named / "track.yaml")) return named.string();
  const auto maps = listMaps(maps_dir);
  std::string known;
  for (const auto& name : maps) known += (known.empty() ? "" : ", ") + name;
  const std::string near = config::nearestKey(map, maps);
  throw MapError("unknown map '" + map + "': not a map folder and not in " + maps_dir +
                 (near.empty() ? "" : " (did you mean '" + near + "'?)") + " (available: " + known + ")");
}

std::vector<std::string> listMaps(const std::string& maps_dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(maps_dir, ec)) {
    if (entry.is_directory() && fs::exists(entry.path() / "track.yaml"))
      names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace roar::track

// track_tool: what ROAR_PY users do in notebooks, from the command line: import, export, resample,
// spawn points, build, check and preview circuits.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "roar/config/number.h"
#include "roar/config/text_file.h"
#include "roar/track/bridges.h"
#include "roar/track/circuit_builder.h"
#include "roar/track/map_folder.h"
#include "roar/track/track_preview.h"
#include "roar/track/waypoints.h"

using namespace roar::track;
namespace fs = std::filesystem;

namespace {

// On `out`; returns the exit status: 0 when asked for, 2 after a wrong command line.
int usage(std::ostream& out = std::cerr) {
  out << "usage: track_tool COMMAND ...\n"
         "  import SOURCE MAP_FOLDER [--name NAME] [--spacing M] [--width M] [--close-gap]\n"
         "         [--point-to-point [--start M] [--finish M]]\n"
         "      SOURCE: a TUMFTM centre-line CSV (x_m,y_m,w_tr_right_m,w_tr_left_m), a ROAR_PY waypoint file (.npz),\n"
         "      or a list of x,y points (--width, default 12 m); resampled when --spacing is given;\n"
         "      --point-to-point: an open course from its first point to its last (start line --start metres along\n"
         "      it, default the grid's length; finish line --finish, default 200 m before its end)\n"
         "  export MAP_FOLDER OUT.npz                 ROAR_PY waypoints (locations, rotations, lane_widths)\n"
         "  resample MAP_FOLDER --spacing M           rewrites the centre line at an even spacing\n"
         "  spawn MAP_FOLDER N OUT.npz                N spawn points evenly round the lap, as a ROAR_PY spawn file\n"
         "  build CONTROL_POINTS.csv MAP_FOLDER [--spacing M]\n"
         "      smooth closed circuit through control points (x_m,y_m,width_m)\n"
         "      (import and build raise one branch onto a bridge where the course crosses itself)\n"
         "  check MAP_FOLDER                          validates; prints length, widths, the tightest corner\n"
         "  preview MAP_FOLDER OUT.png                top-down picture with start/finish and sector lines\n";
  return &out == &std::cout ? 0 : 2;
}

// --flag value pairs after the positional arguments.
std::string option(int argc, char** argv, const std::string& flag, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (argv[i] == flag) return argv[i + 1];
  }
  return fallback;
}

// A numeric option: the whole value one finite number ("--spacing 2x" is refused, not read as 2).
double numberOption(int argc, char** argv, const std::string& name, const std::string& fallback) {
  return roar::config::numberArgument(name, option(argc, argv, name, fallback));
}

bool flag(int argc, char** argv, const std::string& name) {
  for (int i = 1; i < argc; ++i) {
    if (argv[i] == name) return true;
  }
  return false;
}

int check(const std::string& folder) {
  const Track track = loadMapFolder(folder);
  double min_radius = 1e9, min_width = 1e9, max_width = 0;
  std::size_t tightest = 0;
  for (std::size_t i = 0; i < track.size(); ++i) {
    const double k = std::abs(track.curvature(i));
    if (k > 0 && 1 / k < min_radius) min_radius = 1 / k, tightest = i;
    const double w = track.point(i).width_left + track.point(i).width_right;
    min_width = std::min(min_width, w);
    max_width = std::max(max_width, w);
  }
  const auto deck = bridgeDeckPoints(track);
  const auto bridge_points = std::count(deck.begin(), deck.end(), true);
  std::cout << track.info().name << ": " << track.size() << " points, length " << track.length() << " m, width "
            << min_width << ".." << max_width << " m, tightest corner radius " << min_radius
            << " m at s = " << track.s(tightest) << " m; "
            << (track.closed() ? "closes"
                               : "a point-to-point course, " +
                                     std::to_string(static_cast<int>(std::lround(track.raceDistance()))) +
                                     " m from its start line to its finish line")
            << ", no crossing edges"
            << (bridge_points ? " but over bridges (" + std::to_string(bridge_points) + " points on a deck)" : "")
            << "\n";
  return 0;
}

std::vector<CentreLinePoint> importPoints(const std::string& source, double width) {
  if (!fs::exists(source)) throw MapError(source + ": no such file");
  const std::string ext = fs::path(source).extension().string();
  if (ext == ".npz") {
    TrackInfo info;
    return trackFromWaypoints(readRoarWaypoints(source), info).points();
  }
  // A TUMFTM file has four columns; a point list two.
  std::istringstream in(roar::config::readTextFile<MapError>(source, roar::config::kMaxTableBytes));
  std::string line;
  while (std::getline(in, line) && (line.empty() || line[0] == '#')) {
  }
  const auto commas = std::count(line.begin(), line.end(), ',');
  if (commas >= 3) return readCentreLineCsv(source).points;
  return readPointList(source, width);
}

// A circuit that crosses itself goes over itself on a bridge: the branch raised, said what was done.
std::vector<CentreLinePoint> withBridges(const std::vector<CentreLinePoint>& points, const std::string& source,
                                         const TrackInfo& info) {
  std::vector<RaisedBridge> raised;
  std::vector<CentreLinePoint> out;
  try {
    out = raiseBridges(points, info.barrier_offset, &raised, info.closed);
  } catch (const std::invalid_argument& e) {
    throw MapError(source + ": " + e.what());
  }
  for (const auto& b : raised) {
    std::cout << source << ": the course crosses itself at (" << b.x << ", " << b.y
              << "): raised the branch at s = " << b.s << " m by " << b.rise << " m onto a bridge (deck " << b.span
              << " m, ramps " << b.ramp << " m each side)\n";
  }
  return out;
}

// Road past a course's finish line where the cars stop, by default.
constexpr double kDefaultRunOff = 200.0;

// import --point-to-point: the line as it is, from its first point to its last, with its start and finish lines.
int importCourse(int argc, char** argv) {
  const std::string source = argv[2], folder = argv[3];
  TrackInfo info;
  info.name = option(argc, argv, "--name", fs::path(folder).filename().string());
  info.closed = false;
  auto points = importPoints(source, numberOption(argc, argv, "--width", "12"));
  // A recorded lap that drives on over its start: the retraced tail is cut here too.
  std::size_t cut = 0;
  points = trimRetracedTail(points, &cut);
  if (cut > 0)
    std::cout << source << ": cut the last " << cut << " points, which drive the start of the course again\n";
  const std::string spacing = option(argc, argv, "--spacing", "");
  if (!spacing.empty()) points = resampleLine(points, roar::config::numberArgument("--spacing", spacing), false);
  double length = 0.0;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    length += std::hypot(points[i + 1].x - points[i].x, points[i + 1].y - points[i].y);
  }
  points = withBridges(points, source, info);
  info.start_finish_s = numberOption(argc, argv, "--start", std::to_string(std::ceil(kGridLength)));
  info.finish_s = numberOption(argc, argv, "--finish", std::to_string(std::floor(length - kDefaultRunOff)));
  try {
    writeMapFolder(folder, points, info);
  } catch (const std::invalid_argument& e) {
    throw MapError(source + " as a point-to-point course: " + e.what() + " (--start and --finish place the lines)");
  }
  return check(folder);
}

}  // namespace

int main(int argc, char** argv) {
  if (roar::config::helpRequested(argc, argv)) return usage(std::cout);
  if (argc < 3) return usage();
  const std::string cmd = argv[1];
  try {
    if (cmd == "import" && argc >= 4 && flag(argc, argv, "--point-to-point")) return importCourse(argc, argv);
    if (cmd == "import" && argc >= 4) {
      const std::string folder = argv[3];
      TrackInfo info;
      info.name = option(argc, argv, "--name", fs::path(folder).filename().string());
      auto points = importPoints(argv[2], numberOption(argc, argv, "--width", "12"));
      // A recorded lap that drives on over its start: the retraced tail is cut.
      std::size_t cut = 0;
      points = trimRetracedTail(points, &cut);
      if (cut > 0) {
        std::cout << argv[2] << ": cut the last " << cut << " points, which drive the start of the course again\n";
      }
      // A loop that stops short of its start: bridged on request, refused naming the source otherwise.
      const LoopGap gap = loopGap(points);
      if (gap.open()) {
        if (!flag(argc, argv, "--close-gap")) {
          throw MapError(std::string(argv[2]) + ": the loop does not close: its last point is " +
                         std::to_string(gap.gap) + " m from its first (its points are " +
                         std::to_string(gap.median_step) +
                         " m apart); --close-gap bridges it with a straight stretch, if the course is a circuit; "
                         "--point-to-point imports it as an open course from its first point to its last");
        }
        if (!gap.bridgeable()) {
          throw MapError(std::string(argv[2]) + ": the loop cannot be closed: its first point lies " +
                         std::to_string(-gap.ahead) +
                         " m behind its last, not ahead of it (the course runs on past its "
                         "start, or is not a loop: --point-to-point imports it as an open course)");
        }
        points = closeLoopGap(points);
        std::cout << argv[2] << ": bridged the " << gap.gap
                  << " m from the last point back to the first with a straight stretch\n";
      }
      const std::string spacing = option(argc, argv, "--spacing", "");
      if (!spacing.empty()) points = resampleClosed(points, roar::config::numberArgument("--spacing", spacing));
      points = withBridges(points, argv[2], info);
      writeMapFolder(folder, points, info);
      return check(folder);
    }
    if (cmd == "export" && argc == 4) {
      const Track track = loadMapFolder(argv[2]);
      writeRoarWaypoints(argv[3], waypointsOf(track));
      std::cout << "wrote " << track.size() << " waypoints to " << argv[3] << "\n";
      return 0;
    }
    if (cmd == "resample" && argc == 5) {
      const Track track = loadMapFolder(argv[2]);
      const auto points = resampleLine(track.points(), numberOption(argc, argv, "--spacing", "2"), track.closed());
      writeMapFolder(argv[2], points, track.info());
      return check(argv[2]);
    }
    if (cmd == "spawn" && argc == 5) {
      const Track track = loadMapFolder(argv[2]);
      const int count = static_cast<int>(roar::config::wholeNumberArgument("spawn: N", argv[3], 1, 100000));
      std::vector<Waypoint> spawns;
      for (const auto& pose : track.evenSpawnPoints(count)) {
        Waypoint w;
        w.location = Eigen::Vector3d(pose.position.x(), pose.position.y(), 0.0);
        w.roll_pitch_yaw = Eigen::Vector3d(0, 0, pose.heading);
        spawns.push_back(w);
        std::cout << pose.position.x() << "," << pose.position.y() << "," << pose.heading << "\n";
      }
      writeRoarSpawnPoints(argv[4], spawns);
      return 0;
    }
    if (cmd == "build" && argc >= 4) {
      const std::string folder = argv[3];
      TrackInfo info;
      info.name = fs::path(folder).filename().string();
      if (fs::exists(fs::path(folder) / "track.yaml")) info = readTrackYaml(folder + "/track.yaml");
      const auto points = withBridges(
          buildCircuit(readControlPoints(argv[2]), numberOption(argc, argv, "--spacing", "2")), argv[2], info);
      writeMapFolder(folder, points, info);
      return check(folder);
    }
    if (cmd == "check") return check(argv[2]);
    if (cmd == "preview" && argc == 4) {
      renderTrackPreview(loadMapFolder(argv[2]), argv[3]);
      std::cout << "wrote " << argv[3] << "\n";
      return 0;
    }
  } catch (const std::exception& e) {
    std::cerr << "track_tool: " << e.what() << "\n";
    return 1;
  }
  return usage();
}

// track_tool: build, check and preview circuits from the command line.
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "roar/track/circuit_builder.h"
#include "roar/track/map_folder.h"
#include "roar/track/track_preview.h"

using namespace roar::track;

namespace {

int usage() {
  std::cerr << "usage:\n"
               "  track_tool build CONTROL_POINTS.csv MAP_FOLDER [--spacing M]\n"
               "      smooth closed circuit through control points (CSV: x_m,y_m,width_m) -> MAP_FOLDER/centerline.csv\n"
               "  track_tool check MAP_FOLDER\n"
               "      loads and validates a map; prints length, corner radii and widths\n"
               "  track_tool preview MAP_FOLDER OUT.png\n"
               "      top-down picture with start/finish and sector lines\n";
  return 2;
}

std::vector<ControlPoint> readControlPoints(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw MapError(path + ": cannot open");
  std::vector<ControlPoint> out;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    ControlPoint c;
    char comma1 = 0, comma2 = 0;
    if (!(ss >> c.x >> comma1 >> c.y >> comma2 >> c.width) || comma1 != ',' || comma2 != ',') {
      throw MapError(path + ":" + std::to_string(line_no) + ": expected x_m,y_m,width_m");
    }
    out.push_back(c);
  }
  return out;
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
  std::cout << track.info().name << ": " << track.size() << " points, length " << track.length() << " m, width "
            << min_width << ".." << max_width << " m, tightest corner radius " << min_radius << " m at s = "
            << track.s(tightest) << " m; closes, no crossing edges\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string cmd = argv[1];
  try {
    if (cmd == "build" && argc >= 4) {
      double spacing = 2.0;
      if (argc == 6 && std::string(argv[4]) == "--spacing") spacing = std::stod(argv[5]);
      const auto points = buildCircuit(readControlPoints(argv[2]), spacing);
      writeCentreLineCsv(std::string(argv[3]) + "/centerline.csv", points);
      return check(argv[3]);
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

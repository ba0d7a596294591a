#pragma once
// Reading a map folder: `track.yaml` plus a centre-line CSV in the TUMFTM racetrack-database format
// (`x_m,y_m,w_tr_right_m,w_tr_left_m`, optional `#` header). Every error names the file and, where there
// is one, the line.
#include <stdexcept>
#include <string>
#include <vector>

#include "roar/track/track.h"

namespace roar::track {

class MapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CentreLineFile {
  std::vector<CentreLinePoint> points;
  std::vector<int> lines;  // the file line each point came from, for error messages
};

CentreLineFile readCentreLineCsv(const std::string& path);
void writeCentreLineCsv(const std::string& path, const std::vector<CentreLinePoint>& points);

// Throws MapError when the road edges of the track cross themselves or each other.
// `lines` maps point indices to file lines for the message (may be empty).
void checkEdges(const Track& track, const std::string& path, const std::vector<int>& lines);

// track.yaml, strictly (an unknown key is refused naming the nearest known one; every number in its
// physical range); `centreline`, when given, receives the centre-line file it names, and `waypoints` the
// recorded waypoints' file (a ROAR_PY .npz, one waypoint per centre-line point), "" when it names none.
TrackInfo readTrackYaml(const std::string& path, std::string* centreline = nullptr, std::string* waypoints = nullptr);
void writeTrackYaml(const std::string& path, const TrackInfo& info, const std::string& centreline = "centerline.csv");

// Writes the centre line (to the file an existing track.yaml names; centerline.csv for a new map) and
// `<folder>/track.yaml` if missing, checked like loadMapFolder.
void writeMapFolder(const std::string& folder, const std::vector<CentreLinePoint>& points, const TrackInfo& info);

// A closed centre line from a file of points `x,y` (or `x y`), one per line, `#` comments; constant width.
std::vector<CentreLinePoint> readPointList(const std::string& path, double width);

// Loads `<folder>/track.yaml`, the centre line it names (default `centerline.csv`) and the recorded
// waypoints it names (Track::recordedWaypoints), validated.
Track loadMapFolder(const std::string& folder);

// `map` is a folder path, or a name looked up as `<maps_dir>/<map>`.
std::string resolveMapFolder(const std::string& map, const std::string& maps_dir);
std::vector<std::string> listMaps(const std::string& maps_dir);

}  // namespace roar::track

#pragma once
#include <string>
#include <vector>

#include "roar/track/track.h"

namespace roar::track {

// A path drawn over the track, coloured by a value per point (a car's speed) on a common scale.
struct ValuedPath {
  std::string label;
  std::vector<Eigen::Vector2d> points;
  std::vector<double> values;
};

// A labelled place on the map (where a pass happened: "ego > pace").
struct MapMark {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  std::string label;
};

// Writes a top-down PNG of the track: grass, barriers, road, centre line, start/finish line, sector lines,
// the direction of travel (a red arrow labelled "direction" beside the road after the line), the paths (one:
// coloured from blue, lowest value, to red, highest, with a scale labelled `value_name`; several: each its
// own colour, named in a legend, the first widest so paths on one line show as nested stripes), and the
// marks as white rings numbered on the map. The
// legend and the marks' list sit in a band below the map, where they cover no path.
// Throws std::runtime_error when the image cannot be written.
void renderTrackPreview(const Track& track, const std::string& png_path, int width_px = 1200,
                        const std::vector<ValuedPath>& paths = {}, const std::string& value_name = "",
                        const std::vector<MapMark>& marks = {});

}  // namespace roar::track

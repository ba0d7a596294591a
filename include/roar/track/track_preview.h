#pragma once
#include <string>

#include "roar/track/track.h"

namespace roar::track {

// Writes a top-down PNG of the track: grass, barriers, road, centre line, start/finish line, sector lines.
// Throws std::runtime_error when the image cannot be written.
void renderTrackPreview(const Track& track, const std::string& png_path, int width_px = 1200);

}  // namespace roar::track

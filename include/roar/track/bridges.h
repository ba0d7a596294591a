#pragma once
// Circuits that cross themselves (figure-eights): one branch runs over the other on a bridge. The importer
// and the circuit builder raise a branch at each crossing; the map reader accepts a crossing only with
// the clearance below; the barriers on a bridge stand at the road's edge (a parapet) and stop under the
// deck, so the road below runs through.
#include <string>
#include <vector>

#include "roar/track/track.h"

namespace roar::track {

// m between two road surfaces where they cross: a car with its roof sensors, and the deck.
inline constexpr double kBridgeClearance = 5.0;
// m a branch is raised by where the importer builds a bridge (above the clearance: rounding, banking).
inline constexpr double kBridgeRise = 6.0;
// Steepest grade of a bridge's ramps; cosine ramps, so the crest's vertical curvature stays gentle too.
inline constexpr double kBridgeMaxGrade = 0.05;
// m from the road's edge to a bridge's parapet (the barrier there), and of deck under its surface.
inline constexpr double kParapetOffset = 0.5;
inline constexpr double kDeckDepth = 1.0;

// A branch raised at a crossing.
struct RaisedBridge {
  double x = 0.0, y = 0.0;  // m, where the centre line crosses itself
  double s = 0.0;           // m along the raised branch (from the first point)
  double rise = 0.0;        // m it was raised by there
  double span = 0.0;        // m of the branch raised by all of it (the deck over the other road)
  double ramp = 0.0;        // m of each ramp up to it and down from it
};

// The centre line with a branch raised at every crossing that lacks the clearance (the branch already
// higher, or the later one), by a plateau over the other road and cosine ramps either side. Throws
// std::invalid_argument naming the crossing when there is not course enough between its branches for
// the ramps. `barrier_offset`: the run-off the other road keeps clear beside it (m). `closed` false: a
// point-to-point course's centre line, which does not lead from its last point back to its first.
std::vector<CentreLinePoint> raiseBridges(std::vector<CentreLinePoint> points, double barrier_offset,
                                          std::vector<RaisedBridge>* raised = nullptr, bool closed = true);

// For each centre-line point: whether its road runs over another part of the circuit there, at least
// the clearance above it (a bridge's deck).
std::vector<bool> bridgeDeckPoints(const Track& track);

}  // namespace roar::track

#pragma once
// Where on the racing line a pass was won (the passer drawing level with the car it passes): on a straight,
// in a braking zone or through a corner, and on which side of the corner. Issue 14 asks for passes in
// braking zones on the inside and on straights, on both sides: the traffic table counts each.
#include <string>

#include "roar/planning/trajectory.h"

namespace roar::harness {

enum class PassPlace { kStraight, kBrakingZone, kCorner };

struct PassPlaceOptions {
  double braking = 1.0;          // m/s^2 the racing line slows at, or more: a braking zone
  double corner_radius = 150.0;  // m: the line curving tighter is in a corner
  double corner_search = 400.0;  // m beyond a braking point within which the corner braked for is sought
};

struct PassWhere {
  PassPlace place = PassPlace::kStraight;
  // On the inside of the corner (the one braked for, in a braking zone); false on a straight.
  bool inside = false;
};

// `s`: line s (m) where the passer drew level; `side`: +1 passing on the left of the car passed, -1 on the
// right. The inside of a braking zone is that of the tightest turn from there to where the line stops
// slowing (the corner it brakes for). Throws std::invalid_argument for a side other than +1 or -1.
PassWhere passPlace(const planning::Trajectory& line, double s, int side, const PassPlaceOptions& options = {});

std::string describe(PassPlace place);  // "straight", "braking zone", "corner"

}  // namespace roar::harness

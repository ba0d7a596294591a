#include "roar/harness/pass_place.h"

#include <cmath>
#include <stdexcept>

namespace roar::harness {

PassWhere passPlace(const planning::Trajectory& line, double s, int side, const PassPlaceOptions& options) {
  if (side != 1 && side != -1) throw std::invalid_argument("passPlace: side must be +1 (left) or -1 (right)");
  const planning::TrajectoryPoint here = planning::sampleAt(line, s);
  PassWhere where;
  if (here.acceleration <= -options.braking) {
    where.place = PassPlace::kBrakingZone;
    // The corner braked for: the tightest turn from here to where the line stops slowing.
    double turn = here.curvature;
    const double step = 1.0;
    for (double ahead = step; ahead <= options.corner_search; ahead += step) {
      const planning::TrajectoryPoint p = planning::sampleAt(line, s + ahead);
      if (std::abs(p.curvature) > std::abs(turn)) turn = p.curvature;
      if (p.acceleration > -options.braking) break;
    }
    where.inside = turn * side > 0;
  } else if (std::abs(here.curvature) >= 1.0 / options.corner_radius) {
    where.place = PassPlace::kCorner;
    where.inside = here.curvature * side > 0;
  }
  return where;
}

std::string describe(PassPlace place) {
  switch (place) {
    case PassPlace::kStraight:
      return "straight";
    case PassPlace::kBrakingZone:
      return "braking zone";
    case PassPlace::kCorner:
      return "corner";
  }
  return "?";
}

}  // namespace roar::harness

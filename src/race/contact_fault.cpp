#include "roar/race/contact_fault.h"

#include <cmath>

#include "roar/track/heading.h"

namespace roar::race {

ContactFault attributeContact(const CarAtContact& a, const CarAtContact& b, double road_heading,
                              const ContactFaultOptions& options) {
  const Eigen::Vector2d along = track::forwardOf(road_heading);
  const Eigen::Vector2d across = track::leftOf(road_heading);
  const Eigen::Vector2d rel = b.position - a.position;
  const double gap = rel.dot(along);  // b ahead of a when positive
  const double overlap = options.car_length - std::abs(gap);
  if (overlap < options.alongside_overlap * options.car_length) {
    return {gap > 0 ? a.name : b.name, "from behind"};
  }
  // Sideways speed of each towards the other.
  const double side = rel.dot(across) >= 0 ? 1.0 : -1.0;  // where b is from a
  const double a_towards = side * a.velocity.dot(across);
  const double b_towards = -side * b.velocity.dot(across);
  if (a_towards > b_towards + options.sideways_margin) return {a.name, "alongside"};
  if (b_towards > a_towards + options.sideways_margin) return {b.name, "alongside"};
  return {"", "alongside"};
}

}  // namespace roar::race

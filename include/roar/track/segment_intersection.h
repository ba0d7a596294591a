#pragma once
#include <Eigen/Core>
#include <optional>
#include <utility>
#include <vector>

namespace roar::track {

// First pair of crossing segments between two closed polylines (or within one, when both are the same
// vector), as the indices of their first points. Neighbouring segments of one polyline share an end
// and are not counted. A uniform grid keeps this near-linear for real circuits.
std::optional<std::pair<std::size_t, std::size_t>> findClosedPolylineCrossing(const std::vector<Eigen::Vector2d>& a,
                                                                              const std::vector<Eigen::Vector2d>& b);

bool segmentsCross(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2, const Eigen::Vector2d& q1,
                   const Eigen::Vector2d& q2);

}  // namespace roar::track

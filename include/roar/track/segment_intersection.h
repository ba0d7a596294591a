#pragma once
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

namespace roar::track {

// First pair of crossing segments between two closed polylines (or within one, when both are the same
// vector), as the indices of their first points. Neighbouring segments of one polyline share an end
// and are not counted, nor are crossings `passes` lets by (given the two segments' first points: a bridge
// over the other). A uniform grid keeps this near-linear for real circuits.
using CrossingFilter = std::function<bool(std::size_t, std::size_t)>;
std::optional<std::pair<std::size_t, std::size_t>> findClosedPolylineCrossing(const std::vector<Eigen::Vector2d>& a,
                                                                              const std::vector<Eigen::Vector2d>& b,
                                                                              const CrossingFilter& passes = {});
// Every crossing within one closed polyline, as pairs (i < j) of its segments' first points.
std::vector<std::pair<std::size_t, std::size_t>> closedPolylineSelfCrossings(const std::vector<Eigen::Vector2d>& a);

bool segmentsCross(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2, const Eigen::Vector2d& q1,
                   const Eigen::Vector2d& q2);

}  // namespace roar::track

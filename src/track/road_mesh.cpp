#include "roar/track/road_mesh.h"

#include <algorithm>
#include <cmath>

#include "roar/track/bridges.h"
#include "roar/track/heading.h"

namespace roar::track {

TriangleMesh roadSurfaceMesh(const Track& track, double z) {
  TriangleMesh mesh;
  const int n = static_cast<int>(track.size());
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d l = track.leftEdge(i), r = track.rightEdge(i);
    const auto& p = track.point(i);
    mesh.vertices.emplace_back(l.x(), l.y(), z + track.surfaceHeight(i, p.width_left));
    mesh.vertices.emplace_back(r.x(), r.y(), z + track.surfaceHeight(i, -p.width_right));
  }
  for (int i = 0; i < static_cast<int>(track.segments()); ++i) {
    const int j = (i + 1) % n;
    const int li = 2 * i, ri = 2 * i + 1, lj = 2 * j, rj = 2 * j + 1;
    mesh.triangles.push_back({ri, rj, lj});
    mesh.triangles.push_back({ri, lj, li});
  }
  return mesh;
}

namespace {

// Adds a wall along a line of base points (a loop when `closed`), standing `height` above the road edge's
// height at each point and reaching below it, so that it meets the ground on an elevated or banked track
// too; on a bridge's deck it reaches only the deck's depth down, leaving the road below clear.
void addWall(TriangleMesh* mesh, const std::vector<Eigen::Vector2d>& inner, const std::vector<Eigen::Vector2d>& outer,
             const std::vector<double>& edge_z, const std::vector<bool>& deck, double height, bool closed) {
  const int n = static_cast<int>(inner.size());
  const int base = static_cast<int>(mesh->vertices.size());
  for (int i = 0; i < n; ++i) {
    const double bottom = deck[i] ? edge_z[i] - kDeckDepth : std::min(0.0, edge_z[i]) - 0.5;
    const double top = edge_z[i] + height;
    mesh->vertices.emplace_back(inner[i].x(), inner[i].y(), bottom);
    mesh->vertices.emplace_back(inner[i].x(), inner[i].y(), top);
    mesh->vertices.emplace_back(outer[i].x(), outer[i].y(), top);
    mesh->vertices.emplace_back(outer[i].x(), outer[i].y(), bottom);
  }
  for (int i = 0; i < (closed ? n : n - 1); ++i) {
    const int a = base + 4 * i, b = base + 4 * ((i + 1) % n);
    for (int f = 0; f < 3; ++f) {  // inner face, top, outer face
      mesh->triangles.push_back({a + f, b + f, b + f + 1});
      mesh->triangles.push_back({a + f, b + f + 1, a + f + 1});
    }
  }
}

// A point-to-point course's end closed by a wall across its run-off, `offset` beyond its end point
// (point i, looking the way `outwards` points), joining the side barriers' ends.
void addEndWall(TriangleMesh* mesh, const Track& track, std::size_t i, const Eigen::Vector2d& outwards, double offset,
                double thickness) {
  const auto& p = track.point(i);
  const std::vector<Eigen::Vector2d> inner = {track.leftEdge(i, offset), track.leftEdge(i, offset) + offset * outwards,
                                              track.rightEdge(i, offset) + offset * outwards,
                                              track.rightEdge(i, offset)};
  const double far = offset + thickness;
  const std::vector<Eigen::Vector2d> outer = {track.leftEdge(i, far), track.leftEdge(i, far) + far * outwards,
                                              track.rightEdge(i, far) + far * outwards, track.rightEdge(i, far)};
  const double left_z = track.surfaceHeight(i, p.width_left), right_z = track.surfaceHeight(i, -p.width_right);
  const std::vector<double> z = {left_z, left_z, right_z, right_z};
  addWall(mesh, inner, outer, z, std::vector<bool>(4, false), track.info().barrier_height, false);
}

}  // namespace

// An offset line around a corner tighter than the offset folds back on itself (a swallowtail) and would
// stand across the road. Points that would run backwards along the centre line collapse onto the last
// point that did not, leaving zero-length pieces: one wall piece per centre-line segment still.
void unfold(const Track& track, std::vector<Eigen::Vector2d>* line) {
  const std::size_t n = line->size();
  for (int pass = 0; pass < 2; ++pass) {  // the second pass settles the wrap-around
    for (std::size_t k = 1; k < (track.closed() ? n + 1 : n); ++k) {
      const std::size_t i = k % n, prev = k - 1;
      const Eigen::Vector2d along = track.position((prev + 1) % n) - track.position(prev);
      if (((*line)[i] - (*line)[prev]).dot(along) < 0) (*line)[i] = (*line)[prev];
    }
  }
}

TriangleMesh barrierMesh(const Track& track, double thickness) {
  TriangleMesh mesh;
  const std::size_t n = track.size();
  const std::vector<bool> deck = bridgeDeckPoints(track);
  std::vector<Eigen::Vector2d> left_in(n), left_out(n), right_in(n), right_out(n);
  for (std::size_t i = 0; i < n; ++i) {
    // A bridge has no run-off: its parapet stands at the road's edge.
    const double offset = deck[i] ? kParapetOffset : track.info().barrier_offset;
    left_in[i] = track.leftEdge(i, offset);
    left_out[i] = track.leftEdge(i, offset + thickness);
    right_in[i] = track.rightEdge(i, offset);
    right_out[i] = track.rightEdge(i, offset + thickness);
  }
  for (auto* line : {&left_in, &left_out, &right_in, &right_out}) unfold(track, line);
  std::vector<double> left_z(n), right_z(n);
  for (std::size_t i = 0; i < n; ++i) {
    left_z[i] = track.surfaceHeight(i, track.point(i).width_left);
    right_z[i] = track.surfaceHeight(i, -track.point(i).width_right);
  }
  addWall(&mesh, left_in, left_out, left_z, deck, track.info().barrier_height, track.closed());
  addWall(&mesh, right_in, right_out, right_z, deck, track.info().barrier_height, track.closed());
  if (!track.closed()) {
    auto heading = [&](std::size_t i) { return track::forwardOf(track.heading(i)); };
    addEndWall(&mesh, track, 0, -heading(0), track.info().barrier_offset, thickness);
    addEndWall(&mesh, track, n - 1, heading(n - 1), track.info().barrier_offset, thickness);
  }
  return mesh;
}

namespace {

// A flat strip between two lines at the heights z, one quad per centre-line segment.
void addStrip(TriangleMesh* mesh, const std::vector<Eigen::Vector2d>& inner, const std::vector<Eigen::Vector2d>& outer,
              const std::vector<double>& z, bool closed) {
  const int n = static_cast<int>(inner.size());
  const int base = static_cast<int>(mesh->vertices.size());
  for (int i = 0; i < n; ++i) {
    mesh->vertices.emplace_back(inner[i].x(), inner[i].y(), z[i]);
    mesh->vertices.emplace_back(outer[i].x(), outer[i].y(), z[i]);
  }
  for (int i = 0; i < (closed ? n : n - 1); ++i) {
    const int a = base + 2 * i, b = base + 2 * ((i + 1) % n);
    mesh->triangles.push_back({a, b, b + 1});
    mesh->triangles.push_back({a, b + 1, a + 1});
  }
}

// The run-off beyond a point-to-point course's end point i, out to its end wall, at the end's height.
void addEndApron(TriangleMesh* mesh, const Track& track, std::size_t i, const Eigen::Vector2d& outwards, double reach) {
  const auto& p = track.point(i);
  const Eigen::Vector2d left = track.leftEdge(i, reach), right = track.rightEdge(i, reach);
  const double left_z = track.surfaceHeight(i, p.width_left), right_z = track.surfaceHeight(i, -p.width_right);
  const std::vector<Eigen::Vector2d> at_end = {left, right},
                                     beyond = {left + reach * outwards, right + reach * outwards};
  // Counter-clockwise from above whichever way the end faces.
  const bool forwards = (right - left).x() * outwards.y() - (right - left).y() * outwards.x() > 0;
  addStrip(mesh, forwards ? at_end : beyond, forwards ? beyond : at_end, {left_z, right_z}, false);
}

}  // namespace

TriangleMesh runoffMesh(const Track& track, double thickness) {
  TriangleMesh mesh;
  const std::size_t n = track.size();
  const std::vector<bool> deck = bridgeDeckPoints(track);
  for (int side = 0; side < 2; ++side) {
    std::vector<Eigen::Vector2d> inner(n), outer(n);
    std::vector<double> z(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double reach = (deck[i] ? kParapetOffset : track.info().barrier_offset) + thickness;
      const auto& p = track.point(i);
      inner[i] = side == 0 ? track.leftEdge(i) : track.rightEdge(i);
      outer[i] = side == 0 ? track.leftEdge(i, reach) : track.rightEdge(i, reach);
      z[i] = track.surfaceHeight(i, side == 0 ? p.width_left : -p.width_right);
    }
    unfold(track, &outer);
    // Counter-clockwise from above: the right side's strip runs from its outer line in.
    if (side == 0)
      addStrip(&mesh, inner, outer, z, track.closed());
    else
      addStrip(&mesh, outer, inner, z, track.closed());
  }
  if (!track.closed()) {
    auto heading = [&](std::size_t i) { return track::forwardOf(track.heading(i)); };
    const double reach = track.info().barrier_offset + thickness;
    addEndApron(&mesh, track, 0, -heading(0), reach);
    addEndApron(&mesh, track, n - 1, heading(n - 1), reach);
  }
  return mesh;
}

KerbMesh kerbMesh(const Track& track, double width, double min_radius, double lift) {
  KerbMesh out;
  const std::size_t n = track.size();
  for (std::size_t i = 0; i < track.segments(); ++i) {
    const std::size_t j = (i + 1) % n;
    if (std::max(std::abs(track.curvature(i)), std::abs(track.curvature(j))) < 1.0 / min_radius) continue;
    for (int side = 0; side < 2; ++side) {
      auto edge = [&](std::size_t p, double extra) {
        return side == 0 ? track.leftEdge(p, extra) : track.rightEdge(p, extra);
      };
      const int base = static_cast<int>(out.mesh.vertices.size());
      const double zi = track.surfaceHeight(i, side == 0 ? track.point(i).width_left : -track.point(i).width_right);
      const double zj = track.surfaceHeight(j, side == 0 ? track.point(j).width_left : -track.point(j).width_right);
      const Eigen::Vector2d q[4] = {edge(i, 0), edge(i, width), edge(j, width), edge(j, 0)};
      const double qz[4] = {zi, zi, zj, zj};
      for (int c = 0; c < 4; ++c) out.mesh.vertices.emplace_back(q[c].x(), q[c].y(), qz[c] + lift);
      out.mesh.triangles.push_back({base, base + 1, base + 2});
      out.mesh.triangles.push_back({base, base + 2, base + 3});
      out.segment_of.push_back(static_cast<int>(i));
      out.segment_of.push_back(static_cast<int>(i));
    }
  }
  return out;
}

}  // namespace roar::track

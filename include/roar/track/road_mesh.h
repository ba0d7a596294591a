#pragma once
// Triangle meshes of a track, in the map frame: the road surface between the edges, a barrier wall along
// each side and the kerbs of the corners. Shared by the physics (Bullet), the ray-casting scene and rviz.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "roar/track/track.h"

namespace roar::track {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from outside
};

TriangleMesh roadSurfaceMesh(const Track& track, double z = 0.0);

// A wall `thickness` thick whose inner face stands barrier_offset outside each road edge.
TriangleMesh barrierMesh(const Track& track, double thickness = 0.5);

// The run-off: a strip outside each road edge at that edge's height, reaching under the barrier (and, on a
// point-to-point course, past each end to its end wall), so that a wheel over the edge rolls on as on the
// grass beside CARLA's roads.
TriangleMesh runoffMesh(const Track& track, double thickness = 0.5);

// Kerbs: strips `width` wide outside both road edges along every centre-line segment of a corner tighter
// than `min_radius`, `lift` above the road; segment_of[t] is the centre-line segment of triangle t.
struct KerbMesh {
  TriangleMesh mesh;
  std::vector<int> segment_of;
};
KerbMesh kerbMesh(const Track& track, double width = 1.2, double min_radius = 250.0, double lift = 0.01);

}  // namespace roar::track

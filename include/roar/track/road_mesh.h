#pragma once
// Triangle meshes of a track, in the map frame: the road surface between the edges and a barrier wall
// along each side. Shared by the physics (Bullet) and, later, the ray-casting scene.
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

}  // namespace roar::track

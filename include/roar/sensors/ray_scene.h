#pragma once
// The ray-casting scene shared by cameras and LiDAR: the track (road with markings, kerbs in the corners,
// barriers, ground) and every car, in Embree (Intel's CPU ray tracer). Cars are instances of their visual
// mesh, moved each tick, seen from outside only (a camera inside a car's body sees out of it). A cast can
// leave one car out (Embree ray masks): LiDAR, radar and the occupancy map never see their own car;
// cameras do, as CARLA's do.
#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "roar/sensors/semantic.h"
#include "roar/track/road_mesh.h"
#include "roar/track/track.h"

namespace roar::sensors {

// A car's looks: triangles in base_link with one colour each (linear RGB, 0..1).
struct VisualMesh {
  track::TriangleMesh mesh;
  std::vector<Eigen::Vector3f> colours;  // one per triangle
};

struct RayHit {
  bool hit = false;
  float distance = 0.0f;                              // m along the (unit) ray
  Eigen::Vector3f normal = Eigen::Vector3f::UnitZ();  // unit, facing the ray
  Eigen::Vector3f albedo = Eigen::Vector3f::Zero();   // surface colour, linear RGB 0..1
  float reflectivity = 0.0f;                          // LiDAR return strength of the material, 0..1
  SemanticClass semantic = SemanticClass::kSky;
  int vehicle = -1;  // the car hit (its id in the scene), -1: the track
};

class RayScene {
 public:
  explicit RayScene(const track::Track& track);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // Returns the id of the car in this scene. Its pose must be set before the next commit.
  int addVehicle(const VisualMesh& looks, const Eigen::Vector3f& paint);
  void removeVehicle(int id);
  void setVehiclePose(int id, const Eigen::Isometry3d& base_link_in_map);
  // base_link's velocities (m/s, rad/s, map frame), for what the radar measures; zero until set.
  void setVehicleVelocity(int id, const Eigen::Vector3d& linear, const Eigen::Vector3d& angular);
  // The velocity (m/s, map frame) of a point of car `id` (-1, the track: zero).
  Eigen::Vector3d velocityAt(int id, const Eigen::Vector3d& point) const;
  // Makes moved and added cars visible to the next casts.
  void commit();

  // Casts `count` rays from one origin. `own_vehicle` (-1: none) is invisible to them. Coherent rays
  // (camera pixels in order) go in packets of 16.
  void cast(const Eigen::Vector3d& origin, const Eigen::Vector3f* directions, std::size_t count, int own_vehicle,
            float max_distance, bool coherent, RayHit* hits) const;
  // Parallel rays from `count` origins along one unit direction (an orthographic view from above).
  void castParallel(const Eigen::Vector3d* origins, const Eigen::Vector3f& direction, std::size_t count,
                    int own_vehicle, float max_distance, RayHit* hits) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace roar::sensors

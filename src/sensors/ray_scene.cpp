#include "roar/sensors/ray_scene.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <map>
#include <stdexcept>

namespace roar::sensors {

namespace {

constexpr unsigned kStaticMask = 0x80000000u;
constexpr float kGroundZ = -0.02f;  // as in the physics: grass just below the road
constexpr float kKerbZ = 0.01f;
constexpr double kKerbWidth = 1.2;
constexpr double kKerbRadius = 250.0;  // m: corners tighter than this get kerbs

unsigned vehicleMask(int id) { return 1u << (static_cast<unsigned>(id) % 31u); }

// Cheap deterministic value noise in [0, 1) from integer cell coordinates, for surface texture.
float cellNoise(double x, double y, double cell) {
  const auto ix = static_cast<std::int64_t>(std::floor(x / cell)), iy = static_cast<std::int64_t>(std::floor(y / cell));
  std::uint64_t h =
      static_cast<std::uint64_t>(ix) * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(iy) * 0xC2B2AE3D27D4EB4Full;
  h ^= h >> 29;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 32;
  return static_cast<float>(h & 0xFFFFFF) / static_cast<float>(0x1000000);
}

// Cars' meshes are closed with outward faces: a hit on a face turned away from the ray is the inside of a
// body, which no one sees (ray_scene_test ACameraInsideACarSeesOutOfIt).
void frontFacesOnly(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const float facing = RTCRayN_dir_x(args->ray, args->N, i) * RTCHitN_Ng_x(args->hit, args->N, i) +
                         RTCRayN_dir_y(args->ray, args->N, i) * RTCHitN_Ng_y(args->hit, args->N, i) +
                         RTCRayN_dir_z(args->ray, args->N, i) * RTCHitN_Ng_z(args->hit, args->N, i);
    if (facing > 0.0f) args->valid[i] = 0;
  }
}

RTCGeometry triangleGeometry(RTCDevice device, const track::TriangleMesh& mesh, unsigned mask) {
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
  }
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), mesh.triangles.size()));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) idx[3 * i + k] = static_cast<unsigned>(mesh.triangles[i][k]);
  }
  rtcSetGeometryMask(geom, mask);
  rtcCommitGeometry(geom);
  return geom;
}

}  // namespace

struct RayScene::Impl {
  struct Vehicle {
    RTCScene scene = nullptr;
    unsigned instance = RTC_INVALID_GEOMETRY_ID;
    std::vector<Eigen::Vector3f> colours;
    Eigen::Matrix3f rotation = Eigen::Matrix3f::Identity();
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // base_link in the map
    Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  };
  struct KerbPrim {
    int segment;
  };

  // Two levels: the track is a scene of its own, built once; the top level holds only instances (the
  // track and the cars), so moving the cars each tick rebuilds a tree of a handful of boxes.
  explicit Impl(const track::Track& t) : track(t) {
    device = rtcNewDevice("threads=1");
    if (!device) throw std::runtime_error("Embree: cannot create a device");
    static_scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(static_scene, RTC_BUILD_QUALITY_HIGH);
    const std::size_t n = track.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d d = track.position((i + 1) % n) - track.position(i);
      seg_dir.push_back(d.normalized());
    }
    road_geom = attach(static_scene, triangleGeometry(device, track::roadSurfaceMesh(track), kStaticMask));
    barrier_geom = attach(static_scene, triangleGeometry(device, track::barrierMesh(track), kStaticMask));
    // Red and white kerbs outside both road edges wherever the corner is tight.
    track::KerbMesh kerbs = track::kerbMesh(track, kKerbWidth, kKerbRadius, kKerbZ);
    kerb_segments = std::move(kerbs.segment_of);
    kerb_geom = attach(static_scene, triangleGeometry(device, kerbs.mesh, kStaticMask));
    ground_geom = attach(static_scene, triangleGeometry(device, groundMesh(), kStaticMask));
    // The run-off at the road's height (grass, as the ground beyond the barriers): the physics' run-off.
    attach(static_scene, triangleGeometry(device, track::runoffMesh(track), kStaticMask));
    rtcCommitScene(static_scene);

    scene = rtcNewScene(device);
    static_instance = attach(scene, instanceOf(static_scene, kStaticMask));
    rtcCommitScene(scene);
  }

  RTCGeometry instanceOf(RTCScene child, unsigned mask) const {
    RTCGeometry inst = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(inst, child);
    rtcSetGeometryMask(inst, mask);
    const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
    rtcCommitGeometry(inst);
    return inst;
  }

  ~Impl() {
    for (auto& [id, v] : vehicles) rtcReleaseScene(v.scene);
    rtcReleaseScene(scene);
    rtcReleaseScene(static_scene);
    rtcReleaseDevice(device);
  }

  static unsigned attach(RTCScene target, RTCGeometry geom) {
    const unsigned id = rtcAttachGeometry(target, geom);
    rtcReleaseGeometry(geom);
    return id;
  }

  track::TriangleMesh groundMesh() const {
    Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
    for (std::size_t i = 0; i < track.size(); ++i) {
      lo = lo.cwiseMin(track.position(i));
      hi = hi.cwiseMax(track.position(i));
    }
    lo.array() -= 3000.0;
    hi.array() += 3000.0;
    const double z = track.lowestPoint() + kGroundZ;  // as in the physics: just below the lowest road
    track::TriangleMesh mesh;
    mesh.vertices = {{lo.x(), lo.y(), z}, {hi.x(), lo.y(), z}, {hi.x(), hi.y(), z}, {lo.x(), hi.y(), z}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    return mesh;
  }

  // Progress and lateral offset of a point on segment i.
  void frenet(std::size_t i, const Eigen::Vector3d& p, double* s, double* lateral) const {
    const Eigen::Vector2d rel = p.head<2>() - track.position(i);
    const Eigen::Vector2d d = seg_dir[i];
    *s = track.s(i) + rel.dot(d);
    *lateral = d.x() * rel.y() - d.y() * rel.x();
  }

  // What a ray from `origin` along the unit `dir` met at `tfar` (geom RTC_INVALID_GEOMETRY_ID: nothing).
  void finishHit(const Eigen::Vector3d& origin, const Eigen::Vector3f& dir, float tfar, unsigned geom, unsigned prim,
                 unsigned inst, const Eigen::Vector3f& geometric_normal, RayHit* out) const {
    *out = RayHit();
    if (geom == RTC_INVALID_GEOMETRY_ID) return;
    out->hit = true;
    out->distance = tfar;
    out->normal = geometric_normal.normalized();
    shade(geom, prim, inst, origin + static_cast<double>(tfar) * dir.cast<double>(), out);
    if (out->normal.dot(dir) > 0) out->normal = -out->normal;
  }

  void shade(unsigned geom, unsigned prim, unsigned inst, const Eigen::Vector3d& p, RayHit* out) const {
    if (inst != static_instance) {
      const Vehicle& v = vehicles.at(instance_to_vehicle.at(inst));
      out->albedo = v.colours[prim];
      out->reflectivity = 0.5f;
      out->semantic = SemanticClass::kVehicle;
      out->vehicle = instance_to_vehicle.at(inst);
      out->normal = v.rotation * out->normal;  // Embree reports instanced normals in the car's frame
      return;
    }
    if (geom == road_geom) {
      const std::size_t i = prim / 2;
      double s, lateral;
      frenet(i, p, &s, &lateral);
      const auto& pt = track.point(i);
      const bool edge_line = (lateral > pt.width_left - 0.5 && lateral < pt.width_left - 0.25) ||
                             (-lateral > pt.width_right - 0.5 && -lateral < pt.width_right - 0.25);
      // The start/finish line, and a point-to-point course's finish line, painted 0.6 m deep.
      auto painted = [&](double line_s) {
        const double from_line = track.closed() ? track.wrap(s - line_s) : s - line_s;
        return (from_line >= 0 && from_line < 0.6) || (track.closed() && from_line > track.length() - 0.01);
      };
      const bool start_line = painted(track.info().start_finish_s) || (!track.closed() && painted(track.finishLine()));
      if (edge_line || start_line) {
        out->albedo = Eigen::Vector3f::Constant(0.85f);
        out->reflectivity = 0.8f;
        out->semantic = SemanticClass::kLaneMarking;
      } else {
        out->albedo = Eigen::Vector3f::Constant(0.13f + 0.025f * cellNoise(p.x(), p.y(), 0.15));  // asphalt
        out->reflectivity = 0.3f;
        out->semantic = SemanticClass::kRoad;
      }
    } else if (geom == kerb_geom) {
      double s, lateral;
      frenet(static_cast<std::size_t>(kerb_segments[prim]), p, &s, &lateral);
      const bool red = static_cast<long>(std::floor(s / 2.0)) % 2 == 0;
      out->albedo = red ? Eigen::Vector3f(0.75f, 0.08f, 0.06f) : Eigen::Vector3f(0.9f, 0.9f, 0.9f);
      out->reflectivity = 0.6f;
      out->semantic = SemanticClass::kKerb;
    } else if (geom == barrier_geom) {
      const std::size_t n = track.size();
      const std::size_t i = (prim % (6 * n)) / 6;
      const bool top = (prim % 6) / 2 == 1;
      const bool band = static_cast<long>(std::floor(track.s(i) / 4.0)) % 2 == 0;
      out->albedo = top ? Eigen::Vector3f(0.55f, 0.55f, 0.55f)
                        : (band ? Eigen::Vector3f(0.85f, 0.85f, 0.85f) : Eigen::Vector3f(0.1f, 0.25f, 0.7f));
      out->reflectivity = 0.7f;
      out->semantic = SemanticClass::kBarrier;
    } else {
      const float stripe = static_cast<long>(std::floor(p.x() / 8.0)) % 2 == 0 ? 0.03f : -0.03f;
      const float noise = 0.05f * cellNoise(p.x(), p.y(), 0.5);
      out->albedo = Eigen::Vector3f(0.16f + stripe + noise, 0.40f + stripe + noise, 0.11f + noise);
      out->reflectivity = 0.2f;
      out->semantic = SemanticClass::kGround;
    }
  }

  const track::Track& track;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;         // top level: instances only
  RTCScene static_scene = nullptr;  // the track
  unsigned static_instance = 0;
  unsigned road_geom = 0, barrier_geom = 0, kerb_geom = 0, ground_geom = 0;
  std::vector<Eigen::Vector2d> seg_dir;
  std::vector<int> kerb_segments;
  std::map<int, Vehicle> vehicles;
  std::map<unsigned, int> instance_to_vehicle;
  int next_id = 0;
};

RayScene::RayScene(const track::Track& track) : impl_(std::make_unique<Impl>(track)) {}
RayScene::~RayScene() = default;

int RayScene::addVehicle(const VisualMesh& looks, const Eigen::Vector3f& paint) {
  auto& w = *impl_;
  const int id = w.next_id++;
  Impl::Vehicle v;
  v.scene = rtcNewScene(w.device);
  RTCGeometry body = triangleGeometry(w.device, looks.mesh, 0xFFFFFFFFu);
  rtcSetGeometryIntersectFilterFunction(body, frontFacesOnly);
  rtcCommitGeometry(body);
  rtcAttachGeometry(v.scene, body);
  rtcReleaseGeometry(body);
  rtcCommitScene(v.scene);
  v.colours = looks.colours;
  for (auto& c : v.colours) {
    if (c.x() < 0) c = paint;  // negative: "the car's paint"
  }
  v.instance = Impl::attach(w.scene, w.instanceOf(v.scene, vehicleMask(id)));
  w.instance_to_vehicle[v.instance] = id;
  w.vehicles.emplace(id, std::move(v));
  return id;
}

void RayScene::removeVehicle(int id) {
  auto& w = *impl_;
  auto it = w.vehicles.find(id);
  if (it == w.vehicles.end()) return;
  rtcDetachGeometry(w.scene, it->second.instance);
  w.instance_to_vehicle.erase(it->second.instance);
  rtcReleaseScene(it->second.scene);
  w.vehicles.erase(it);
}

void RayScene::setVehiclePose(int id, const Eigen::Isometry3d& pose) {
  auto& w = *impl_;
  Impl::Vehicle& v = w.vehicles.at(id);
  const Eigen::Matrix<float, 3, 4> m = pose.matrix().topRows<3>().cast<float>();
  float xfm[12];
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r) xfm[c * 3 + r] = m(r, c);
  v.rotation = m.leftCols<3>();
  v.origin = pose.translation();
  RTCGeometry inst = rtcGetGeometry(w.scene, v.instance);
  rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
  rtcCommitGeometry(inst);
}

void RayScene::setVehicleVelocity(int id, const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) {
  Impl::Vehicle& v = impl_->vehicles.at(id);
  v.linear_velocity = linear;
  v.angular_velocity = angular;
}

Eigen::Vector3d RayScene::velocityAt(int id, const Eigen::Vector3d& point) const {
  const auto it = impl_->vehicles.find(id);
  if (it == impl_->vehicles.end()) return Eigen::Vector3d::Zero();
  const Impl::Vehicle& v = it->second;
  return v.linear_velocity + v.angular_velocity.cross(point - v.origin);
}

void RayScene::commit() { rtcCommitScene(impl_->scene); }

namespace {

// Casts `count` rays, ray k from originOf(k) along dirOf(k) (unit), in packets of 16: even spread rays
// share the first levels of the tree. `coherent` tells Embree how alike they are.
template <class OriginOf, class DirOf, class Finish>
void castRays(RTCScene scene, std::size_t count, unsigned mask, float max_distance, bool coherent,
              const OriginOf& originOf, const DirOf& dirOf, const Finish& finish) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  std::size_t k = 0;
  for (; k + 16 <= count; k += 16) {
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[16];
    for (int j = 0; j < 16; ++j) {
      const Eigen::Vector3f org = originOf(k + j);
      const Eigen::Vector3f& dir = dirOf(k + j);
      valid[j] = -1;
      rh.ray.org_x[j] = org.x();
      rh.ray.org_y[j] = org.y();
      rh.ray.org_z[j] = org.z();
      rh.ray.dir_x[j] = dir.x();
      rh.ray.dir_y[j] = dir.y();
      rh.ray.dir_z[j] = dir.z();
      rh.ray.tnear[j] = 0.0f;
      rh.ray.tfar[j] = max_distance;
      rh.ray.mask[j] = mask;
      rh.ray.time[j] = 0.0f;
      rh.ray.flags[j] = 0;
      rh.ray.id[j] = static_cast<unsigned>(j);
      rh.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][j] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, scene, &context, &rh);
    for (int j = 0; j < 16; ++j) {
      finish(k + j, rh.ray.tfar[j], rh.hit.geomID[j], rh.hit.primID[j], rh.hit.instID[0][j], rh.hit.Ng_x[j],
             rh.hit.Ng_y[j], rh.hit.Ng_z[j]);
    }
  }
  for (; k < count; ++k) {
    const Eigen::Vector3f org = originOf(k);
    const Eigen::Vector3f& dir = dirOf(k);
    RTCRayHit rh;
    rh.ray.org_x = org.x();
    rh.ray.org_y = org.y();
    rh.ray.org_z = org.z();
    rh.ray.dir_x = dir.x();
    rh.ray.dir_y = dir.y();
    rh.ray.dir_z = dir.z();
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = max_distance;
    rh.ray.mask = mask;
    rh.ray.time = 0.0f;
    rh.ray.flags = 0;
    rh.ray.id = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rh);
    finish(k, rh.ray.tfar, rh.hit.geomID, rh.hit.primID, rh.hit.instID[0], rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  }
}

unsigned maskOf(int own_vehicle) { return own_vehicle >= 0 ? ~vehicleMask(own_vehicle) : 0xFFFFFFFFu; }

}  // namespace

void RayScene::cast(const Eigen::Vector3d& origin, const Eigen::Vector3f* dirs, std::size_t count, int own_vehicle,
                    float max_distance, bool coherent, RayHit* hits) const {
  const auto& w = *impl_;
  const Eigen::Vector3f org = origin.cast<float>();
  castRays(
      w.scene, count, maskOf(own_vehicle), max_distance, coherent, [&](std::size_t) { return org; },
      [&](std::size_t k) -> const Eigen::Vector3f& { return dirs[k]; },
      [&](std::size_t k, float tfar, unsigned geom, unsigned prim, unsigned inst, float nx, float ny, float nz) {
        w.finishHit(origin, dirs[k], tfar, geom, prim, inst, Eigen::Vector3f(nx, ny, nz), &hits[k]);
      });
}

void RayScene::castParallel(const Eigen::Vector3d* origins, const Eigen::Vector3f& direction, std::size_t count,
                            int own_vehicle, float max_distance, RayHit* hits) const {
  const auto& w = *impl_;
  castRays(
      w.scene, count, maskOf(own_vehicle), max_distance, true,
      [&](std::size_t k) -> Eigen::Vector3f { return origins[k].cast<float>(); },
      [&](std::size_t) -> const Eigen::Vector3f& { return direction; },
      [&](std::size_t k, float tfar, unsigned geom, unsigned prim, unsigned inst, float nx, float ny, float nz) {
        w.finishHit(origins[k], direction, tfar, geom, prim, inst, Eigen::Vector3f(nx, ny, nz), &hits[k]);
      });
}

}  // namespace roar::sensors

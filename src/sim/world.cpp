#include "roar/sim/world.h"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "roar/sim/safe_stop.h"
#include "roar/track/road_mesh.h"
#include "surface.h"
#include "vehicle_dynamics.h"

namespace roar::sim {

namespace {

// m/s: a barrier's hit that changes the car's velocity by more in one substep is a crash, which the car's
// body absorbs (VehicleDynamics::absorbCrash); a car sliding along the wall is not crashing.
constexpr double kCrashSpeedChange = 2.0;
constexpr double kBarrierFriction = 0.3;  // car body on barrier
constexpr double kGroundDrop = 0.02;      // m: the ground lies this far below the road so a ray's first hit is clear

std::unique_ptr<btTriangleMesh> toBullet(const track::TriangleMesh& mesh) {
  auto out = std::make_unique<btTriangleMesh>(true, false);
  for (const auto& t : mesh.triangles) {
    const auto &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    out->addTriangle(btVector3(a.x(), a.y(), a.z()), btVector3(b.x(), b.y(), b.z()), btVector3(c.x(), c.y(), c.z()));
  }
  return out;
}

// Footprint corners of a car, for the spawn overlap check.
std::array<Eigen::Vector2d, 4> footprint(const vehicle::VehicleParams& p, const Eigen::Vector2d& at, double yaw,
                                         double margin) {
  const Eigen::Vector2d c = p.chassis.box_centre.head<2>();
  const double hx = 0.5 * p.chassis.box_size.x() + margin, hy = 0.5 * p.chassis.box_size.y() + margin;
  const Eigen::Rotation2Dd rot(yaw);
  return {at + rot * (c + Eigen::Vector2d(hx, hy)), at + rot * (c + Eigen::Vector2d(-hx, hy)),
          at + rot * (c + Eigen::Vector2d(-hx, -hy)), at + rot * (c + Eigen::Vector2d(hx, -hy))};
}

bool footprintsOverlap(const std::array<Eigen::Vector2d, 4>& a, const std::array<Eigen::Vector2d, 4>& b) {
  // Separating axis theorem on the four edge normals of two rectangles.
  for (const auto* shape : {&a, &b}) {
    for (int e = 0; e < 2; ++e) {
      const Eigen::Vector2d edge = (*shape)[e + 1] - (*shape)[e];
      const Eigen::Vector2d axis(-edge.y(), edge.x());
      double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
      for (const auto& p : a) amin = std::min(amin, p.dot(axis)), amax = std::max(amax, p.dot(axis));
      for (const auto& p : b) bmin = std::min(bmin, p.dot(axis)), bmax = std::max(bmax, p.dot(axis));
      if (amax < bmin || bmax < amin) return false;
    }
  }
  return true;
}

}  // namespace

struct World::Impl {
  Impl(const track::Track& t, const WorldOptions& o) : track(t), options(o) {}

  struct StaticBody {
    std::unique_ptr<btTriangleMesh> mesh;
    std::unique_ptr<btCollisionShape> shape;
    std::vector<std::unique_ptr<btCollisionShape>> parts;  // a compound shape's children
    std::unique_ptr<btRigidBody> body;
  };

  struct Slot {
    std::unique_ptr<VehicleDynamics> dynamics;
    double last_control_time = 0.0;
    bool has_control = false;
    std::map<std::string, Contact> tick_contacts;
    std::vector<Contact> contacts;
    double barrier_impulse_before = 0.0;
    double barrierImpulse() const {
      auto it = tick_contacts.find("barrier");
      return it == tick_contacts.end() ? 0.0 : it->second.impulse.norm();
    }
  };

  void addStatic(StaticBody& sb, int surface, double friction) {
    btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, sb.shape.get());
    info.m_friction = friction;
    info.m_restitution = 0.1;
    sb.body = std::make_unique<btRigidBody>(info);
    sb.body->setUserIndex(surface);
    dynamics->addRigidBody(sb.body.get());
  }

  // The world's edge: four walls round the circuit, kWorldEdgeMargin beyond its barriers and
  // kWorldEdgeHeight high, so that a car thrown clear of the circuit stays in the world
  // (World.TheWorldsEdgeHoldsACarDrivingAway). Contacts with them count as the barrier's.
  void addWorldEdge() {
    constexpr double kWorldEdgeMargin = 50.0, kWorldEdgeHeight = 300.0, kThickness = 10.0;  // m
    Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
    for (std::size_t i = 0; i < track.size(); ++i) {
      const double reach = std::max(track.point(i).width_left, track.point(i).width_right) +
                           track.info().barrier_offset + kWorldEdgeMargin;
      lo = lo.cwiseMin(track.position(i) - Eigen::Vector2d::Constant(reach));
      hi = hi.cwiseMax(track.position(i) + Eigen::Vector2d::Constant(reach));
    }
    const Eigen::Vector2d centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
    const double bottom = track.lowestPoint() - 10.0, mid_z = bottom + 0.5 * kWorldEdgeHeight;
    auto compound = std::make_unique<btCompoundShape>();
    auto wall = [&](double x, double y, double half_x, double half_y) {
      world_edge.parts.push_back(std::make_unique<btBoxShape>(btVector3(half_x, half_y, 0.5 * kWorldEdgeHeight)));
      btTransform at;
      at.setIdentity();
      at.setOrigin(btVector3(x, y, mid_z));
      compound->addChildShape(at, world_edge.parts.back().get());
    };
    const double t = 0.5 * kThickness;
    wall(centre.x() - half.x() - t, centre.y(), t, half.y() + kThickness);
    wall(centre.x() + half.x() + t, centre.y(), t, half.y() + kThickness);
    wall(centre.x(), centre.y() - half.y() - t, half.x() + kThickness, t);
    wall(centre.x(), centre.y() + half.y() + t, half.x() + kThickness, t);
    world_edge.shape = std::move(compound);
    addStatic(world_edge, kBarrier, kBarrierFriction);
  }

  // Each car's drag share for this tick, from where the cars are and go at its start.
  void updateSlipstream() {
    if (vehicles.size() < 2) {  // a car alone is in free air (the RL environment's every tick)
      for (auto& [name, slot] : vehicles) slot.dynamics->setDragShare(1.0);
      return;
    }
    std::vector<vehicle::WakeCar> cars;
    cars.reserve(vehicles.size());
    for (auto& [name, slot] : vehicles) {
      const vehicle::VehicleState s = slot.dynamics->state();
      const auto& box = slot.dynamics->params().chassis.box_size;
      cars.push_back({s.pose.position.head<2>(), s.linear_velocity.head<2>(), box.x(), box.y()});
    }
    const std::vector<double> shares = vehicle::dragShares(cars, options.slipstream);
    std::size_t k = 0;
    for (auto& [name, slot] : vehicles) slot.dynamics->setDragShare(shares[k++]);
  }

  static bool isDrivenOn(const btCollisionObject* object) {
    return object->getUserIndex() == kRoad || object->getUserIndex() == kGround;
  }

  std::string nameOf(const btCollisionObject* object) const {
    const int id = object->getUserIndex();
    if (id == kBarrier) return "barrier";
    for (const auto& [name, slot] : vehicles) {
      if (slot.dynamics->body() == object) return name;
    }
    return "unknown";
  }

  Slot* findSlot(const btCollisionObject* object) {
    for (auto& [name, slot] : vehicles) {
      if (slot.dynamics->body() == object) return &slot;
    }
    return nullptr;
  }

  void gatherContacts() {
    btDispatcher* dispatcher = dynamics->getDispatcher();
    for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
      const btPersistentManifold* manifold = dispatcher->getManifoldByIndexInternal(m);
      const btCollisionObject* a = manifold->getBody0();
      const btCollisionObject* b = manifold->getBody1();
      Slot* slot_a = a->getUserIndex() >= kVehicleBase ? findSlot(a) : nullptr;
      Slot* slot_b = b->getUserIndex() >= kVehicleBase ? findSlot(b) : nullptr;
      if (!slot_a && !slot_b) continue;
      // The body on the road or the ground it drives on is no collision, as CARLA's collision sensor has it.
      if (isDrivenOn(a) || isDrivenOn(b)) continue;
      for (int c = 0; c < manifold->getNumContacts(); ++c) {
        const btManifoldPoint& pt = manifold->getContactPoint(c);
        if (pt.getAppliedImpulse() <= 0) continue;
        // normalWorldOnB points from B towards A: the impulse on A.
        const btVector3 on_a = pt.m_normalWorldOnB * pt.getAppliedImpulse();
        const btVector3 where = pt.getPositionWorldOnB();
        auto add = [&](Slot* slot, const btCollisionObject* other, const btVector3& impulse) {
          Contact& contact = slot->tick_contacts[nameOf(other)];
          contact.other = nameOf(other);
          const double weight = impulse.length();
          const double total = contact.impulse.norm() + weight;
          const Eigen::Vector3d p(where.x(), where.y(), where.z());
          contact.position = total > 0 ? (contact.position * contact.impulse.norm() + p * weight) / total : p;
          contact.impulse += Eigen::Vector3d(impulse.x(), impulse.y(), impulse.z());
        };
        if (slot_a) add(slot_a, b, on_a);
        if (slot_b) add(slot_b, a, -on_a);
      }
    }
  }

  const Slot& slot(const std::string& name) const {
    auto it = vehicles.find(name);
    if (it == vehicles.end()) throw SpawnError("no vehicle named '" + name + "'");
    return it->second;
  }
  Slot& slot(const std::string& name) { return const_cast<Slot&>(std::as_const(*this).slot(name)); }

  // Ground height under (x, y) from the static scene, or NaN when there is none: where roads run one over
  // another (a bridge), the road nearest the height `near_z`; elsewhere the highest surface there.
  double groundHeight(double x, double y, double near_z) const {
    const btVector3 from(x, y, 1000.0 + std::max(0.0, near_z)), to(x, y, -1000.0 + std::min(0.0, near_z));
    btCollisionWorld::AllHitsRayResultCallback ray(from, to);
    ray.m_collisionFilterMask = btBroadphaseProxy::StaticFilter;
    dynamics->rayTest(from, to, ray);
    double top = std::nan(""), road = std::nan("");
    for (int k = 0; k < ray.m_hitPointWorld.size(); ++k) {
      const double z = ray.m_hitPointWorld[k].z();
      if (!(z <= top)) top = z;
      if (ray.m_collisionObjects[k]->getUserIndex() == kRoad && !(std::abs(z - near_z) >= std::abs(road - near_z)))
        road = z;
    }
    return std::isfinite(road) ? road : top;
  }

  btTransform placement(const std::string& name, const vehicle::VehicleParams& params, const track::Pose& pose,
                        Placement how) const {
    const double yaw = track::yawOf(pose.orientation);
    const auto mine = footprint(params, pose.position.head<2>(), yaw, 0.3);
    for (const auto& [other, s] : vehicles) {
      if (other == name) continue;
      const btTransform t = s.dynamics->baseLinkPose();
      const btVector3 o = t.getOrigin();
      const double other_yaw = track::yawOf(
          Eigen::Quaterniond(t.getRotation().w(), t.getRotation().x(), t.getRotation().y(), t.getRotation().z()));
      if (footprintsOverlap(mine, footprint(s.dynamics->params(), Eigen::Vector2d(o.x(), o.y()), other_yaw, 0.3))) {
        throw SpawnError("cannot place '" + name + "' at (" + std::to_string(pose.position.x()) + ", " +
                         std::to_string(pose.position.y()) + "): it would overlap vehicle '" + other + "'");
      }
    }
    const double asked_z = std::isfinite(pose.position.z())
                               ? std::clamp(pose.position.z(), -track::kMaxElevation, track::kMaxElevation)
                               : 0.0;
    const double z = groundHeight(pose.position.x(), pose.position.y(), asked_z);
    if (!std::isfinite(z)) {
      throw SpawnError("cannot place '" + name + "' at (" + std::to_string(pose.position.x()) + ", " +
                       std::to_string(pose.position.y()) + "): no ground there");
    }
    btTransform t;
    t.setIdentity();
    if (how == Placement::kAsGiven) {
      const Eigen::Quaterniond q = pose.orientation.normalized();
      t.setOrigin(btVector3(pose.position.x(), pose.position.y(), std::max(z, asked_z)));
      t.setRotation(btQuaternion(q.x(), q.y(), q.z(), q.w()));
      return t;
    }
    t.setOrigin(btVector3(pose.position.x(), pose.position.y(), z));
    t.setRotation(btQuaternion(btVector3(0, 0, 1), yaw));
    return t;
  }

  track::Track track;
  WorldOptions options;
  int substeps = 1;
  std::uint64_t tick = 0;
  // The clock since the last change of control_dt: time = base_time + (tick - base_tick) * control_dt.
  std::uint64_t base_tick = 0;
  double base_time = 0.0;
  SurfaceFriction friction;
  std::unique_ptr<btDefaultCollisionConfiguration> config;
  std::unique_ptr<btCollisionDispatcher> dispatcher;
  std::unique_ptr<btBroadphaseInterface> broadphase;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver;
  std::unique_ptr<btDiscreteDynamicsWorld> dynamics;
  StaticBody road, barriers, runoff, ground, world_edge;
  std::map<std::string, Slot> vehicles;  // ordered: every loop over cars runs in the same order
  int next_vehicle_index = kVehicleBase;
};

namespace {

// Physics substeps per control tick; throws std::invalid_argument for steps that do not fit.
int substepsOf(double control_dt, double physics_dt) {
  if (!(physics_dt > 0) || !(control_dt >= physics_dt) || !std::isfinite(control_dt)) {
    throw std::invalid_argument("physics_dt must be positive and no larger than control_dt");
  }
  const double ratio = control_dt / physics_dt;
  const long substeps = std::lround(ratio);
  if (std::abs(ratio - static_cast<double>(substeps)) > 1e-9 * ratio || substeps > 100000) {
    throw std::invalid_argument("control_dt (" + std::to_string(control_dt) +
                                ") must be a whole multiple of physics_dt (" + std::to_string(physics_dt) + ")");
  }
  return static_cast<int>(substeps);
}

}  // namespace

World::World(const track::Track& track, const WorldOptions& options, const WorldClock& start)
    : impl_(std::make_unique<Impl>(track, options)) {
  auto& w = *impl_;
  w.substeps = substepsOf(options.control_dt, options.physics_dt);
  if (options.control_timeout < 0) throw std::invalid_argument("control_timeout must not be negative");
  validate(options.slipstream, "slipstream: ");
  if (!std::isfinite(start.time) || start.time < 0)
    throw std::invalid_argument("the start time must be finite and >= 0");
  w.tick = w.base_tick = start.tick;
  w.base_time = start.time;
  w.friction.road = track.info().friction;
  w.friction.ground = track.info().ground_friction;

  w.config = std::make_unique<btDefaultCollisionConfiguration>();
  w.dispatcher = std::make_unique<btCollisionDispatcher>(w.config.get());
  w.broadphase = std::make_unique<btDbvtBroadphase>();
  w.solver = std::make_unique<btSequentialImpulseConstraintSolver>();
  w.dynamics =
      std::make_unique<btDiscreteDynamicsWorld>(w.dispatcher.get(), w.broadphase.get(), w.solver.get(), w.config.get());
  w.dynamics->setGravity(btVector3(0, 0, -options.gravity));

  w.road.mesh = toBullet(track::roadSurfaceMesh(track));
  w.road.shape = std::make_unique<btBvhTriangleMeshShape>(w.road.mesh.get(), true);
  w.addStatic(w.road, kRoad, track.info().friction);
  w.barriers.mesh = toBullet(track::barrierMesh(track));
  w.barriers.shape = std::make_unique<btBvhTriangleMeshShape>(w.barriers.mesh.get(), true);
  w.addStatic(w.barriers, kBarrier, kBarrierFriction);
  w.runoff.mesh = toBullet(track::runoffMesh(track));
  w.runoff.shape = std::make_unique<btBvhTriangleMeshShape>(w.runoff.mesh.get(), true);
  w.addStatic(w.runoff, kGround, track.info().ground_friction);
  w.ground.shape = std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), track.lowestPoint() - kGroundDrop);
  w.addStatic(w.ground, kGround, track.info().ground_friction);
  w.addWorldEdge();
}

World::~World() {
  auto& w = *impl_;
  w.vehicles.clear();
  for (auto* sb : {&w.road, &w.barriers, &w.runoff, &w.ground, &w.world_edge})
    w.dynamics->removeRigidBody(sb->body.get());
}

const track::Track& World::track() const { return impl_->track; }
const WorldOptions& World::options() const { return impl_->options; }

void World::spawnVehicle(const std::string& name, const vehicle::VehicleParams& params, const track::Pose& pose,
                         Placement placement) {
  auto& w = *impl_;
  if (name.empty()) throw SpawnError("a vehicle needs a name");
  if (w.vehicles.count(name)) throw SpawnError("a vehicle named '" + name + "' already exists");
  const btTransform at = w.placement(name, params, pose, placement);
  Impl::Slot slot;
  slot.dynamics = std::make_unique<VehicleDynamics>(name, params, w.dynamics.get(), w.next_vehicle_index++, at);
  slot.last_control_time = time();
  w.vehicles.emplace(name, std::move(slot));
}

void World::destroyVehicle(const std::string& name) {
  impl_->slot(name);
  impl_->vehicles.erase(name);
}

void World::resetVehicle(const std::string& name, const track::Pose& pose, Placement placement) {
  auto& w = *impl_;
  Impl::Slot& slot = w.slot(name);
  slot.dynamics->reset(w.placement(name, slot.dynamics->params(), pose, placement));
  slot.has_control = false;
  slot.last_control_time = time();
  slot.contacts.clear();
}

void World::setVehicleVelocity(const std::string& name, const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) {
  Impl::Slot& slot = impl_->slot(name);
  if (!linear.allFinite() || linear.norm() > 150.0) {
    throw std::invalid_argument("linear velocity must be finite and at most 150 m/s");
  }
  if (!angular.allFinite() || angular.norm() > 20.0) {
    throw std::invalid_argument("angular velocity must be finite and at most 20 rad/s");
  }
  slot.dynamics->setVelocity(btVector3(linear.x(), linear.y(), linear.z()),
                             btVector3(angular.x(), angular.y(), angular.z()));
}

void World::moveVehicle(const std::string& name, const Eigen::Vector2d& position, double yaw, double speed) {
  Impl::Slot& slot = impl_->slot(name);
  if (!position.allFinite() || !std::isfinite(yaw) || !std::isfinite(speed) || speed < 0.0 || speed > 150.0) {
    throw std::invalid_argument("move: position and yaw must be finite and the speed 0 to 150 m/s");
  }
  btTransform pose = slot.dynamics->baseLinkPose();
  const btVector3 forward = pose.getBasis().getColumn(0);
  const btQuaternion turn(btVector3(0, 0, 1), std::remainder(yaw - std::atan2(forward.y(), forward.x()), 2.0 * M_PI));
  pose.setRotation(turn * pose.getRotation());
  pose.setOrigin(btVector3(position.x(), position.y(), pose.getOrigin().z()));
  slot.dynamics->moveTo(pose, speed);
}

bool World::hasVehicle(const std::string& name) const { return impl_->vehicles.count(name) > 0; }

std::vector<std::string> World::vehicleNames() const {
  std::vector<std::string> names;
  for (const auto& [name, slot] : impl_->vehicles) names.push_back(name);
  return names;
}

const vehicle::VehicleParams& World::vehicleParams(const std::string& name) const {
  return impl_->slot(name).dynamics->params();
}

void World::setControl(const std::string& name, const vehicle::VehicleControl& control) {
  Impl::Slot& slot = impl_->slot(name);
  slot.dynamics->setControl(control);
  slot.has_control = true;
  slot.last_control_time = time();
}

void World::step(const std::function<void(double)>& after_substep) {
  auto& w = *impl_;
  const double dt = w.options.physics_dt;
  for (auto& [name, slot] : w.vehicles) {
    const bool stale = w.options.control_timeout > 0 && time() - slot.last_control_time > w.options.control_timeout;
    // A car nobody has driven stays parked; one whose driver fell silent is brought to a stop on the road.
    if (!slot.has_control) {
      slot.dynamics->setControl(vehicle::parkedControl());
    } else if (stale) {
      slot.dynamics->setControl(safeStopControl(w.track, slot.dynamics->state(), slot.dynamics->params()));
    }
    slot.tick_contacts.clear();
  }
  w.updateSlipstream();
  for (int k = 0; k < w.substeps; ++k) {
    for (auto& [name, slot] : w.vehicles) {
      slot.dynamics->beginSubstep();
      slot.dynamics->applyForces(dt, w.friction);
    }
    w.dynamics->stepSimulation(dt, 0, dt);
    for (auto& [name, slot] : w.vehicles) slot.barrier_impulse_before = slot.barrierImpulse();
    w.gatherContacts();
    for (auto& [name, slot] : w.vehicles) {
      const double hit = slot.barrierImpulse() - slot.barrier_impulse_before;
      if (hit > kCrashSpeedChange * slot.dynamics->params().chassis.mass) slot.dynamics->absorbCrash();
      slot.dynamics->endSubstep(dt);
    }
    if (after_substep) after_substep(time() + (k + 1) * dt);
  }
  ++w.tick;
  for (auto& [name, slot] : w.vehicles) {
    slot.contacts.clear();
    for (auto& [other, contact] : slot.tick_contacts) slot.contacts.push_back(contact);
  }
}

std::uint64_t World::tick() const { return impl_->tick; }
double World::time() const {
  return impl_->base_time + static_cast<double>(impl_->tick - impl_->base_tick) * impl_->options.control_dt;
}

void World::setTiming(double control_dt, double physics_dt) {
  auto& w = *impl_;
  const int substeps = substepsOf(control_dt, physics_dt);
  w.base_time = time();
  w.base_tick = w.tick;
  w.substeps = substeps;
  w.options.control_dt = control_dt;
  w.options.physics_dt = physics_dt;
}

vehicle::VehicleState World::vehicleState(const std::string& name) const { return impl_->slot(name).dynamics->state(); }

const std::vector<Contact>& World::contacts(const std::string& name) const { return impl_->slot(name).contacts; }

}  // namespace roar::sim

#include "vehicle_dynamics.h"

#include <algorithm>
#include <cmath>

#include "surface.h"

namespace roar::sim {

namespace {

// Below this speed the slips use it as their denominator: keeps the tyre forces finite (they become a
// stiff damper) and the explicit chassis integration stable at the physics substep.
constexpr double kLowSpeed = 1.5;  // m/s

btVector3 toBt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
Eigen::Vector3d toEigen(const btVector3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }

// Nearest hit below a wheel, ignoring the car's own body; remembers which triangle of a mesh it was.
struct WheelRay : public btCollisionWorld::ClosestRayResultCallback {
  WheelRay(const btVector3& from, const btVector3& to, const btCollisionObject* self)
      : ClosestRayResultCallback(from, to), self_(self) {}
  bool needsCollision(btBroadphaseProxy* proxy) const override {
    return static_cast<const btCollisionObject*>(proxy->m_clientObject) != self_ &&
           ClosestRayResultCallback::needsCollision(proxy);
  }
  btScalar addSingleResult(btCollisionWorld::LocalRayResult& result, bool normal_in_world_space) override {
    // Bullet reports a hit only when it is nearer than the nearest so far: this one is the nearest now.
    triangle = result.m_localShapeInfo ? result.m_localShapeInfo->m_triangleIndex : -1;
    return ClosestRayResultCallback::addSingleResult(result, normal_in_world_space);
  }
  const btCollisionObject* self_;
  int triangle = -1;
};

// The corners of triangle `index` of a static triangle-mesh body, in the world frame.
std::array<btVector3, 3> meshTriangle(const btCollisionObject* object, int index) {
  const auto* shape = static_cast<const btTriangleMeshShape*>(object->getCollisionShape());
  const btStridingMeshInterface* mesh = shape->getMeshInterface();
  const unsigned char *vertices = nullptr, *indices = nullptr;
  int num_vertices = 0, vertex_stride = 0, index_stride = 0, num_faces = 0;
  PHY_ScalarType vertex_type, index_type;
  mesh->getLockedReadOnlyVertexIndexBase(&vertices, num_vertices, vertex_type, vertex_stride, &indices, index_stride,
                                         num_faces, index_type, 0);
  std::array<btVector3, 3> corners;
  for (int k = 0; k < 3; ++k) {
    const unsigned char* at_index = indices + index * index_stride;
    const int v = index_type == PHY_SHORT ? reinterpret_cast<const unsigned short*>(at_index)[k]
                                          : reinterpret_cast<const unsigned int*>(at_index)[k];
    const unsigned char* at = vertices + v * vertex_stride;
    corners[k] = vertex_type == PHY_DOUBLE
                     ? btVector3(reinterpret_cast<const double*>(at)[0], reinterpret_cast<const double*>(at)[1],
                                 reinterpret_cast<const double*>(at)[2])
                     : btVector3(reinterpret_cast<const float*>(at)[0], reinterpret_cast<const float*>(at)[1],
                                 reinterpret_cast<const float*>(at)[2]);
    corners[k] = object->getWorldTransform() * corners[k];
  }
  mesh->unLockReadOnlyVertexBase(0);
  return corners;
}

// Where the segment from -> to crosses the triangle: the fraction along it and the triangle's normal
// facing `from`, as Bullet's triangle ray test reports them.
bool crossTriangle(const std::array<btVector3, 3>& t, const btVector3& from, const btVector3& to, double* fraction,
                   btVector3* normal) {
  const btVector3 n = (t[1] - t[0]).cross(t[2] - t[0]);
  const double d_from = (from - t[0]).dot(n), d_to = (to - t[0]).dot(n);
  if (d_from * d_to >= 0.0) return false;
  const double f = d_from / (d_from - d_to);
  const btVector3 p = from.lerp(to, f);
  for (int k = 0; k < 3; ++k) {
    if ((t[(k + 1) % 3] - t[k]).cross(p - t[k]).dot(n) < 0.0) return false;
  }
  *fraction = f;
  *normal = (d_from > 0.0 ? n : -n).normalized();
  return true;
}

}  // namespace

VehicleDynamics::VehicleDynamics(std::string name, const vehicle::VehicleParams& params, btDiscreteDynamicsWorld* world,
                                 int user_index, const btTransform& base_link_pose)
    : name_(std::move(name)), params_(params), tyre_(params.tyre), powertrain_(params), world_(world) {
  const auto& ch = params_.chassis;
  // The rigid body's frame is the centre of mass with base_link's axes (the URDF inertia is principal).
  com_from_base_.setIdentity();
  com_from_base_.setOrigin(toBt(ch.centre_of_mass));
  box_ = std::make_unique<btBoxShape>(toBt(ch.box_size * 0.5));
  shape_ = std::make_unique<btCompoundShape>();
  btTransform box_in_com;
  box_in_com.setIdentity();
  box_in_com.setOrigin(toBt(ch.box_centre - ch.centre_of_mass));
  shape_->addChildShape(box_in_com, box_.get());

  btRigidBody::btRigidBodyConstructionInfo info(ch.mass, nullptr, shape_.get(), toBt(ch.inertia));
  info.m_startWorldTransform = base_link_pose * com_from_base_;
  info.m_friction = 0.4;
  info.m_restitution = 0.1;
  body_ = std::make_unique<btRigidBody>(info);
  body_->setActivationState(DISABLE_DEACTIVATION);
  body_->setUserIndex(user_index);
  world_->addRigidBody(body_.get());

  // Static loads from the centre of mass position, so the car rests at the URDF's ride height.
  const double wheelbase = params_.wheelbase();
  const double rear_x = params_.wheels[2].position.x();
  const double front_share = std::clamp((ch.centre_of_mass.x() - rear_x) / wheelbase, 0.05, 0.95);
  const double weight = ch.mass * 9.81;
  for (int i = 0; i < 4; ++i) {
    wheels_[i].centre = toBt(params_.wheels[i].position - ch.centre_of_mass);
    wheels_[i].static_load = 0.5 * weight * (i < 2 ? front_share : 1.0 - front_share);
  }
}

VehicleDynamics::~VehicleDynamics() { world_->removeRigidBody(body_.get()); }

btTransform VehicleDynamics::baseLinkPose() const {
  return body_->getCenterOfMassTransform() * com_from_base_.inverse();
}

void VehicleDynamics::place(const btTransform& base_link_pose) {
  const btTransform com = base_link_pose * com_from_base_;
  body_->setCenterOfMassTransform(com);
  body_->setInterpolationWorldTransform(com);
  world_->getBroadphase()->getOverlappingPairCache()->cleanProxyFromPairs(body_->getBroadphaseHandle(),
                                                                          world_->getDispatcher());
  world_->updateSingleAabb(body_.get());
}

void VehicleDynamics::reset(const btTransform& base_link_pose) {
  place(base_link_pose);
  body_->setLinearVelocity(btVector3(0, 0, 0));
  body_->setAngularVelocity(btVector3(0, 0, 0));
  body_->clearForces();
  for (auto& w : wheels_) {
    w.omega = 0.0;
    w.steer = 0.0;
    w.state = vehicle::WheelState();
    w.road_object = nullptr;
  }
  steering_ = 0.0;
  anti_roll_load_.fill(0.0);
  powertrain_.reset(false);  // moved, not spawned: CARLA keeps a teleported car in gear
  control_ = vehicle::parkedControl();
  brake_pedal_ = brake_level_ = 0.0;  // the pedals released: the parked car is held by its hand brake, at once
  substep_start_velocity_ = btVector3(0, 0, 0);
  last_acceleration_ = btVector3(0, 0, 0);
}

void VehicleDynamics::setVelocity(const btVector3& linear, const btVector3& angular) {
  const btTransform base = baseLinkPose();
  const btVector3 com_offset = body_->getCenterOfMassPosition() - base.getOrigin();
  body_->setLinearVelocity(linear + angular.cross(com_offset));
  body_->setAngularVelocity(angular);
  body_->activate(true);
  const btVector3 forward = base.getBasis().getColumn(0);
  for (std::size_t i = 0; i < wheels_.size(); ++i) wheels_[i].omega = linear.dot(forward) / params_.wheels[i].radius;
  // A car set moving is driving: in gear, its pedals' lags settled at its control (a car stopped is not:
  // ROAR_PY_RL's resets stop it and drive off at once, as over CARLA).
  if (linear.length() > 0.1) {
    powertrain_.settle(control_.throttle);
    brake_pedal_ = brake_level_ = control_.brake;
  }
  substep_start_velocity_ = body_->getLinearVelocity();
  last_acceleration_ = btVector3(0, 0, 0);
}

void VehicleDynamics::moveTo(const btTransform& base_link_pose, double speed) {
  const btTransform base = baseLinkPose();
  const btMatrix3x3 to_body = base.getBasis().transpose();
  const btVector3 com_offset = body_->getCenterOfMassPosition() - base.getOrigin();
  const btVector3 angular = body_->getAngularVelocity();
  // base_link's own velocity (not the centre of mass's), in the body frame, scaled to the speed.
  const btVector3 linear = body_->getLinearVelocity() - angular.cross(com_offset);
  const double scale = linear.length() > 1e-6 ? speed / linear.length() : 0.0;
  const btVector3 body_linear = to_body * linear * scale, body_angular = to_body * angular;
  place(base_link_pose);
  const btMatrix3x3& basis = base_link_pose.getBasis();
  const btVector3 new_angular = basis * body_angular;
  const btVector3 new_offset = body_->getCenterOfMassPosition() - base_link_pose.getOrigin();
  body_->setLinearVelocity(basis * body_linear + new_angular.cross(new_offset));
  body_->setAngularVelocity(new_angular);
  for (auto& w : wheels_) {
    w.omega *= scale;
    w.state.angular_velocity *= scale;
    w.road_object = nullptr;
  }
  substep_start_velocity_ = body_->getLinearVelocity();
}

std::array<double, 4> VehicleDynamics::wheelSteerAngles() const {
  // Ackermann: both front wheels point at one turning centre on the rear axle line.
  std::array<double, 4> angles{0.0, 0.0, 0.0, 0.0};
  if (std::abs(steering_) < 1e-6) return angles;
  const double wheelbase = params_.wheelbase(), half_track = 0.5 * params_.track_width();
  const double radius = wheelbase / std::tan(steering_);
  angles[0] = std::atan(wheelbase / (radius - half_track));
  angles[1] = std::atan(wheelbase / (radius + half_track));
  return angles;
}

void VehicleDynamics::applyForces(double dt, const SurfaceFriction& friction) {
  const btVector3 velocity = body_->getLinearVelocity();
  const double forward_speed = std::abs(velocity.dot(body_->getCenterOfMassTransform().getBasis().getColumn(0)));
  const double target = control_.steer * params_.steering.maxAngleAt(forward_speed);
  const double max_change = params_.steering.max_rate * dt;
  const double lag = params_.steering.response_time;
  const double wanted = lag > 0 ? (target - steering_) * -std::expm1(-dt / lag) : target - steering_;
  steering_ += std::clamp(wanted, -max_change, max_change);
  const auto angles = wheelSteerAngles();
  for (int i = 0; i < 4; ++i) wheels_[i].steer = angles[i];

  vehicle::DriveRequest request;
  request.throttle = control_.throttle;
  request.reverse = control_.reverse;
  request.manual = control_.manual_gear_shift;
  request.gear = control_.gear;
  const double front = params_.front_drive_share, rear = 1.0 - front;
  const double driven_omega =
      0.5 * front * (wheels_[0].omega + wheels_[1].omega) + 0.5 * rear * (wheels_[2].omega + wheels_[3].omega);
  const double drive = powertrain_.update(request, driven_omega, dt);
  const auto& brakes = params_.brakes;
  const double pedal_step = brakes.pedal_rate > 0 ? brakes.pedal_rate * dt : 1.0;
  brake_pedal_ += std::clamp(control_.brake - brake_pedal_, -pedal_step, pedal_step);
  const double brake_lag = brake_pedal_ > brake_level_ ? brakes.rise_time : brakes.release_time;
  brake_level_ =
      brake_lag > 0 ? brake_level_ + (brake_pedal_ - brake_level_) * -std::expm1(-dt / brake_lag) : brake_pedal_;
  // Anti-roll bars from the last substep's compressions (one substep of lag, far below the roll mode).
  const double bars[2] = {params_.suspension.anti_roll_front, params_.suspension.anti_roll_rear};
  for (int axle = 0; axle < 2; ++axle) {
    const vehicle::WheelState &l = wheels_[2 * axle].state, &r = wheels_[2 * axle + 1].state;
    const double twist = (l.in_contact && r.in_contact) ? l.compression - r.compression : 0.0;
    anti_roll_load_[2 * axle] = bars[axle] * twist;
    anti_roll_load_[2 * axle + 1] = -bars[axle] * twist;
  }
  const auto shares = vehicle::driveShares(params_.differential, front,
                                           {wheels_[0].omega, wheels_[1].omega, wheels_[2].omega, wheels_[3].omega});
  for (int i = 0; i < 4; ++i) updateWheel(i, drive * shares[i], dt, friction);

  // Aerodynamics: drag against the motion, downforce on each axle.
  const btMatrix3x3& basis = body_->getCenterOfMassTransform().getBasis();
  const btVector3 v = body_->getLinearVelocity();
  const auto& aero = params_.aero;
  body_->applyCentralForce(-0.5 * aero.air_density * aero.drag_area * drag_share_ * v.length() * v);
  const double forward = v.dot(basis.getColumn(0));
  const double downforce = 0.5 * aero.air_density * aero.downforce_area * forward * forward;
  const btVector3 down = -basis.getColumn(2);
  const btVector3 front_axle = basis * (0.5 * (wheels_[0].centre + wheels_[1].centre));
  const btVector3 rear_axle = basis * (0.5 * (wheels_[2].centre + wheels_[3].centre));
  body_->applyForce(down * (downforce * aero.front_downforce_share), front_axle);
  body_->applyForce(down * (downforce * (1.0 - aero.front_downforce_share)), rear_axle);
}

void VehicleDynamics::updateWheel(int index, double drive_torque, double dt, const SurfaceFriction& friction) {
  Wheel& wheel = wheels_[index];
  const vehicle::WheelParams& wp = params_.wheels[index];
  const auto& susp = params_.suspension;
  const btTransform& com = body_->getCenterOfMassTransform();
  const btMatrix3x3& basis = com.getBasis();
  const btVector3 up = basis.getColumn(2);

  // The ray starts at the wheel centre at full bump and reaches the tyre's bottom at full droop.
  const btVector3 from = com * (wheel.centre + btVector3(0, 0, susp.travel));
  const double reach = susp.travel + susp.droop + wp.radius;
  const btVector3 to = from - up * reach;
  const GroundHit ray = castWheelRay(wheel, from, to);
  vehicle::WheelState& st = wheel.state;
  st.steer_angle = wheel.steer;
  const double r = wp.radius;
  const double inertia = params_.tyre.wheel_inertia;
  const bool rear = index >= 2;
  double brake_torque = brake_level_ * (rear ? params_.brakes.max_torque_rear : params_.brakes.max_torque_front);
  const double hand_brake_torque = (rear && control_.hand_brake) ? params_.brakes.hand_brake_torque : 0.0;

  if (!ray.hit) {
    st = vehicle::WheelState();
    st.steer_angle = wheel.steer;
    // Airborne: the wheel spins up under drive and down under the brakes.
    double omega = wheel.omega + dt * drive_torque / inertia;
    const double stop = dt * (brake_torque + hand_brake_torque) / inertia;
    omega = std::abs(omega) <= stop ? 0.0 : omega - std::copysign(stop, omega);
    wheel.omega = omega;
    st.angular_velocity = omega;
    return;
  }

  const double distance = ray.fraction * reach;
  const double compression = susp.travel + r - distance;
  const btVector3 normal = ray.normal;
  const btVector3 contact = from.lerp(to, ray.fraction);
  const btVector3 rel = contact - com.getOrigin();
  const btVector3 v_contact = body_->getVelocityInLocalPoint(rel);
  const double compression_rate = -v_contact.dot(normal) / std::max(0.2, static_cast<double>(up.dot(normal)));

  double load =
      wheel.static_load + susp.stiffness * compression + susp.damping * compression_rate + anti_roll_load_[index];
  if (compression > susp.travel) load += 20.0 * susp.stiffness * (compression - susp.travel);  // bump stop
  load = std::max(0.0, load);

  const int surface = ray.object->getUserIndex();
  const double mu = surface == kRoad ? friction.road : friction.ground;

  // Wheel axes in the contact plane.
  const btVector3 heading = basis * btVector3(std::cos(wheel.steer), std::sin(wheel.steer), 0);
  btVector3 fwd = heading - normal * heading.dot(normal);
  fwd.normalize();
  const btVector3 left = normal.cross(fwd);
  const double vx = v_contact.dot(fwd), vy = v_contact.dot(left);
  const double denom = std::max(std::abs(vx), kLowSpeed);
  const double slip_angle = std::atan(vy / denom);
  auto longitudinal = [&](double omega) {
    return tyre_.longitudinalForce((omega * r - vx) / denom, slip_angle, load, mu);
  };

  // Wheel spin, integrated implicitly in the tyre force (linearised), which is stiff at low speed.
  const double f0 = longitudinal(wheel.omega);
  const double eps = 1e-3;
  const double stiffness = std::max(0.0, (longitudinal(wheel.omega + eps) - f0) / eps);
  // ABS and traction control act alike: below the tyre's peak slip they pass no more torque than the tyre
  // can put on the road at this slip angle; above it they ease off to a torque the road force overcomes, so
  // the wheel comes back without overshooting (a full release would, within one substep at low speed).
  const double slip_now = (wheel.omega * r - vx) / denom;
  const double share = std::clamp(std::abs(slip_angle) / tyre_.peakSlipAngle(), 0.0, 1.0);
  const double grip_torque = 0.95 * tyre_.peakForce(load, mu) * std::sqrt(1.0 - share * share) * r;
  const double release_slip = 1.2 * tyre_.peakSlipRatio();
  if (params_.brakes.abs && brake_torque > 0) {
    const double distribution = rear ? params_.brakes.rear_grip_share : 1.0;
    brake_torque = std::min(brake_torque, distribution * (std::abs(slip_now) > release_slip ? 0.6 : 1.0) * grip_torque);
  }
  if (params_.traction_control && drive_torque * slip_now > 0) {
    const double distribution = rear ? params_.rear_grip_share : 1.0;
    const double limit = distribution * (std::abs(slip_now) > release_slip ? 0.6 : 1.0) * grip_torque;
    drive_torque = std::clamp(drive_torque, -limit, limit);
  }
  const double resist = brake_torque + hand_brake_torque + params_.tyre.rolling_resistance * load * r;
  const double free_torque = drive_torque - r * f0;
  const double implicit = 1.0 + dt * r * stiffness / inertia;  // d(r Fx)/d(omega) = r * stiffness
  double omega;
  if (std::abs(wheel.omega) < 1e-9) {
    // At rest: the brakes hold the wheel unless the other torques overcome them.
    omega = std::abs(free_torque) <= resist
                ? 0.0
                : wheel.omega + dt * (free_torque - std::copysign(resist, free_torque)) / inertia / implicit;
  } else {
    omega = wheel.omega + dt * (free_torque - std::copysign(resist, wheel.omega)) / inertia / implicit;
    if (omega * wheel.omega < 0) omega = 0.0;  // the brakes stop the wheel, they do not turn it back
  }
  // Past the tyre's peak the linearisation gives no damping: the road's grip may bring the wheel to roll
  // with the road within a substep, never spin it past that (a spun-up wheel landing under a landing's load
  // went to negative slip and the tyre threw the car backwards: physics_test
  // ASpunUpWheelLandsWithoutThrowingTheCarBack).
  const double slip_after = (omega * r - vx) / denom;
  if (slip_now * slip_after < 0 && std::abs(slip_now) > tyre_.peakSlipRatio()) omega = vx / r;
  wheel.omega = omega;

  const double slip_ratio = (omega * r - vx) / denom;
  const TyreForce tyre = tyre_.force(slip_ratio, slip_angle, load, mu);
  body_->applyForce(up * load, rel);
  // Tyre forces act at the contact patch, or lifted towards the centre of mass's height (roll_influence).
  const btVector3 tyre_point = rel - up * (up.dot(rel) * (1.0 - susp.roll_influence));
  body_->applyForce(fwd * tyre.longitudinal + left * tyre.lateral, tyre_point);

  st.angular_velocity = omega;
  st.load = load;
  st.slip_ratio = slip_ratio;
  st.slip_angle = slip_angle;
  st.compression = compression;
  st.in_contact = true;
  st.on_road = surface == kRoad;
}

VehicleDynamics::GroundHit VehicleDynamics::castWheelRay(Wheel& wheel, const btVector3& from, const btVector3& to) {
  // A wheel on the road meets the road triangle it met last substep most of the time (they are metres
  // long): the ray is tried on it first, and the whole world is searched only when it misses, or when
  // another car is near enough to be nearer than the road (the ground and barriers are never above it).
  GroundHit hit;
  if (wheel.road_object && crossTriangle(wheel.road_triangle, from, to, &hit.fraction, &hit.normal) &&
      !otherCarNear(from, to)) {
    hit.hit = true;
    hit.object = wheel.road_object;
    return hit;
  }
  WheelRay ray(from, to, body_.get());
  world_->rayTest(from, to, ray);
  wheel.road_object = nullptr;
  if (!ray.hasHit()) return hit;
  hit.hit = true;
  hit.object = ray.m_collisionObject;
  hit.fraction = ray.m_closestHitFraction;
  hit.normal = ray.m_hitNormalWorld.normalized();
  if (hit.object->getUserIndex() == kRoad && ray.triangle >= 0) {
    wheel.road_object = hit.object;
    wheel.road_triangle = meshTriangle(hit.object, ray.triangle);
  }
  return hit;
}

bool VehicleDynamics::otherCarNear(const btVector3& from, const btVector3& to) const {
  const btVector3 lo(std::min(from.x(), to.x()), std::min(from.y(), to.y()), std::min(from.z(), to.z()));
  const btVector3 hi(std::max(from.x(), to.x()), std::max(from.y(), to.y()), std::max(from.z(), to.z()));
  const btCollisionObjectArray& objects = world_->getCollisionObjectArray();
  for (int i = 0; i < objects.size(); ++i) {
    const btCollisionObject* other = objects[i];
    if (other == body_.get() || other->getUserIndex() < kVehicleBase) continue;
    const btBroadphaseProxy* box = other->getBroadphaseHandle();
    if (TestAabbAgainstAabb2(lo, hi, box->m_aabbMin, box->m_aabbMax)) return true;
  }
  return false;
}

void VehicleDynamics::beginSubstep() {
  substep_start_velocity_ = body_->getLinearVelocity();
  substep_start_spin_ = body_->getAngularVelocity();
}

void VehicleDynamics::absorbCrash() {
  // The roll and pitch the hit gave are undone (the yaw it gave, a spin on the road, is kept), and the car
  // rises no faster than before it.
  const btVector3 w = body_->getAngularVelocity();
  body_->setAngularVelocity(btVector3(substep_start_spin_.x(), substep_start_spin_.y(), w.z()));
  btVector3 v = body_->getLinearVelocity();
  v.setZ(std::min(v.z(), std::max(substep_start_velocity_.z(), 0.0)));
  body_->setLinearVelocity(v);
}

void VehicleDynamics::endSubstep(double dt) {
  last_acceleration_ = (body_->getLinearVelocity() - substep_start_velocity_) / dt;
}

vehicle::VehicleState VehicleDynamics::state() const {
  vehicle::VehicleState s;
  const btTransform base = baseLinkPose();
  const btQuaternion q = base.getRotation();
  s.pose.position = toEigen(base.getOrigin());
  s.pose.orientation = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z());
  const btVector3 rel = base.getOrigin() - body_->getCenterOfMassPosition();
  const btVector3 v = body_->getVelocityInLocalPoint(rel);
  const btVector3 w = body_->getAngularVelocity();
  const btMatrix3x3 to_body = base.getBasis().transpose();
  s.linear_velocity = toEigen(v);
  s.angular_velocity = toEigen(w);
  s.body_linear_velocity = toEigen(to_body * v);
  s.body_angular_velocity = toEigen(to_body * w);
  s.body_acceleration = toEigen(to_body * last_acceleration_);
  s.speed = v.length();
  s.forward_speed = s.body_linear_velocity.x();
  s.gear = powertrain_.gear();
  s.engine_rpm = powertrain_.engineRpm();
  s.steering_angle = 0.5 * (wheels_[0].steer + wheels_[1].steer);
  s.on_track = true;
  for (int i = 0; i < 4; ++i) {
    s.wheels[i] = wheels_[i].state;
    s.on_track = s.on_track && wheels_[i].state.on_road;
  }
  s.applied_control = control_;
  s.drag_share = drag_share_;
  return s;
}

}  // namespace roar::sim

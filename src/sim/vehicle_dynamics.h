#pragma once
// One car in the Bullet world: a rigid chassis held up by four raycast suspensions, driven by tyre forces.
// Internal to the sim library (it includes Bullet).
#include <btBulletDynamicsCommon.h>

#include <array>
#include <memory>
#include <string>

#include "roar/sim/tyre.h"
#include "roar/sim/world.h"
#include "roar/vehicle/powertrain.h"

namespace roar::sim {

struct SurfaceFriction {
  double road = 1.0;
  double ground = 0.6;
};

class VehicleDynamics {
 public:
  VehicleDynamics(std::string name, const vehicle::VehicleParams& params, btDiscreteDynamicsWorld* world,
                  int user_index, const btTransform& base_link_pose);
  ~VehicleDynamics();
  VehicleDynamics(const VehicleDynamics&) = delete;
  VehicleDynamics& operator=(const VehicleDynamics&) = delete;

  const std::string& name() const { return name_; }
  const vehicle::VehicleParams& params() const { return params_; }
  btRigidBody* body() { return body_.get(); }

  void setControl(const vehicle::VehicleControl& control) { control_ = control; }
  void setDragShare(double share) { drag_share_ = share; }
  // Suspension, tyre, drivetrain and aero forces for one substep, to be integrated by Bullet next.
  void applyForces(double dt, const SurfaceFriction& friction);
  void beginSubstep();  // remembers the velocity for the substep's acceleration
  // A crash into a barrier is inelastic: the crumpling body takes the energy the rigid hit would turn into
  // roll, pitch and lift (World.BarriersHoldACarAtAnySpeed). Called after a substep with such a hit.
  void absorbCrash();
  void endSubstep(double dt);
  void reset(const btTransform& base_link_pose);
  // base_link's velocities (map frame) set as they are; the wheels roll with the road.
  void setVelocity(const btVector3& linear, const btVector3& angular);
  // base_link to the pose at the speed, its velocities kept in its own frame (slip angle and yaw rate) and
  // its wheels' spin scaled with the speed; steering, brakes and drivetrain keep their states.
  void moveTo(const btTransform& base_link_pose, double speed);
  btTransform baseLinkPose() const;
  vehicle::VehicleState state() const;

 private:
  struct Wheel {
    btVector3 centre;          // static wheel centre relative to the centre of mass, body frame
    double static_load = 0.0;  // N at rest, the spring preload
    double omega = 0.0;        // rad/s
    double steer = 0.0;        // rad
    vehicle::WheelState state;
    const btCollisionObject* road_object = nullptr;  // the road, when the last ray met one of its triangles
    std::array<btVector3, 3> road_triangle;          // that triangle's corners, world frame
  };

  struct GroundHit {
    bool hit = false;
    const btCollisionObject* object = nullptr;
    double fraction = 1.0;  // along the ray
    btVector3 normal{0, 0, 1};
  };

  std::array<double, 4> wheelSteerAngles() const;
  // The body at the pose, out of its old contacts' pairs (a teleport, not a motion).
  void place(const btTransform& base_link_pose);
  void updateWheel(int index, double drive_torque, double dt, const SurfaceFriction& friction);
  // The suspension ray's nearest hit, the car's own body aside.
  GroundHit castWheelRay(Wheel& wheel, const btVector3& from, const btVector3& to);
  bool otherCarNear(const btVector3& from, const btVector3& to) const;

  std::string name_;
  vehicle::VehicleParams params_;
  TyreModel tyre_;
  vehicle::Powertrain powertrain_;
  btDiscreteDynamicsWorld* world_;
  std::unique_ptr<btCompoundShape> shape_;
  std::unique_ptr<btBoxShape> box_;
  std::unique_ptr<btRigidBody> body_;
  btTransform com_from_base_;  // base_link -> centre of mass
  std::array<Wheel, 4> wheels_;
  std::array<double, 4> anti_roll_load_{0.0, 0.0, 0.0, 0.0};  // N added to each wheel's spring
  vehicle::VehicleControl control_ = vehicle::parkedControl();
  double drag_share_ = 1.0;   // of the free-air drag: below 1 in another car's slipstream
  double steering_ = 0.0;     // rad, commanded road-wheel angle after the rate limit
  double brake_pedal_ = 0.0;  // the brake pedal as its rate limit lets it follow the control (BrakeParams)
  double brake_level_ = 0.0;  // the brake pressure as it follows the pedal (BrakeParams::rise_time)
  btVector3 substep_start_velocity_{0, 0, 0};
  btVector3 substep_start_spin_{0, 0, 0};
  btVector3 last_acceleration_{0, 0, 0};
};

}  // namespace roar::sim

#pragma once
// Everything the simulator knows about a car model, in SI units. Geometry and mass come from the URDF,
// drivetrain, tyres and aerodynamics from config/vehicles/<model>.yaml (see vehicle_config.h).
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "roar/vehicle/car_size.h"
#include "roar/vehicle/steering_curve.h"

namespace roar::vehicle {

struct ChassisParams {
  double mass = 1850.0;                                                // kg
  Eigen::Vector3d inertia{600.0, 2800.0, 3100.0};                      // kg m^2, principal, about the centre of mass
  Eigen::Vector3d centre_of_mass{0.0, 0.0, 0.5};                       // m, in base_link
  Eigen::Vector3d box_size{kDefaultCarLength, kDefaultCarWidth, 1.0};  // m, collision box of the body
  Eigen::Vector3d box_centre{0.0, 0.0, 0.85};                          // m, in base_link
};

struct WheelParams {
  std::string name;          // URDF link name
  Eigen::Vector3d position;  // m, wheel centre in base_link at static ride height
  double radius = 0.34;      // m
  double width = 0.235;      // m
  bool front = false;
  bool left = false;
};

struct SuspensionParams {
  double stiffness = 45000.0;  // N/m at the wheel
  double damping = 3500.0;     // N s/m at the wheel
  double travel = 0.12;        // m of compression from static ride height before the bump stop
  double droop = 0.12;         // m of extension from static ride height before the wheel leaves the ground
  // Anti-roll bars: N/m of left-right compression difference. More front than rear makes the car
  // understeer at the limit, as road cars are set up.
  double anti_roll_front = 25000.0;
  double anti_roll_rear = 8000.0;
  // How much of the tyres' roll and pitch moment the body feels: 1, the tyre forces act at the contact
  // patches (a real car); below 1 they act that share of the way from the centre of mass's height down to
  // the road, as a game-physics vehicle lifts its tyre-force point (CARLA's PhysX cars corner at 3 g
  // without rolling over; physics_test CarlaModel3CornersAtCarlaGripWithoutRollingOver).
  double roll_influence = 1.0;
};

// Which curve gives a tyre's forces from its slips (roar/sim/tyre.h).
enum class TyreCurve {
  kMagicFormula,  // Pacejka's, each slip normalised by its peak slip
  kCarSimEd,      // CarSimEd's (the Michigan model), as PhysX's vehicles and so CARLA 0.9's cars have it
};

struct TyreParams {
  TyreCurve curve = TyreCurve::kMagicFormula;
  // Pacejka magic formula, pure slip, with normalised combined slip (see tyre.h).
  double long_b = 20.0, long_c = 1.55, long_e = 0.3;
  double lat_b = 18.0, lat_c = 1.45, lat_e = 0.3;
  // CarSimEd: the cornering stiffness is lateral_stiffness (per rad) times the nominal load, rising with the
  // load until lateral_stiffness_max_load times it; the longitudinal stiffness is longitudinal_stiffness
  // (per unit slip) times g, whatever the load. CARLA's names: lat_stiff_value, lat_stiff_max_load,
  // long_stiff_value.
  double lateral_stiffness = 17.0;
  double lateral_stiffness_max_load = 2.0;
  double longitudinal_stiffness = 1000.0;  // N per unit slip, per m/s^2 of gravity
  double nominal_load = 4500.0;            // N, Fz0
  double load_sensitivity = 0.08;          // friction drop per unit of (Fz - Fz0) / Fz0
  double rolling_resistance = 0.012;
  double wheel_inertia = 1.2;  // kg m^2, wheel and tyre about the axle
  // The tyre's friction relative to the road's rating: 1 for performance road tyres, below for economy
  // tyres, above for racing slicks. The friction a wheel has is road friction x grip (before load sensitivity).
  double grip = 1.0;
};

struct EngineParams {
  std::vector<std::pair<double, double>> torque_curve;  // (rpm, N m) at full throttle, rising rpm
  double idle_rpm = 900.0;
  double redline_rpm = 7000.0;
  double engine_brake_torque = 60.0;  // N m at redline with the throttle closed, proportional to rpm
  // s: the torque follows the pedal as a first-order lag of this time constant (0: at once). A drive-by-wire
  // motor's torque ramp (carla_model3: fitted to CARLA's telemetry, doc/cars.md).
  double response_time = 0.0;
  // The motor or engine's own rotation, felt only while the clutch slips (below): kg m^2.
  double inertia = 0.2;
};

struct GearboxParams {
  std::vector<double> ratios;  // forward gears, first to top
  double reverse_ratio = 3.2;
  double final_drive = 3.5;
  double efficiency = 0.9;
  double shift_up_rpm = 6500.0;
  double shift_down_rpm = 3000.0;
  double shift_time = 0.15;  // s without drive torque while shifting
  // Automatic mode shifts down to the strongest gear at (nearly) full throttle, not only below
  // shift_down_rpm.
  bool kickdown = true;
  // s: a car spawned stands in neutral until this long after its first throttle, its engine free to rev,
  // then engages first gear through a slipping clutch (0: in first from the start, the clutch never slips).
  // CARLA's cars stand still for their first 1.5 s at full throttle and then surge (carla_model3); a car
  // moved (reset, teleported) keeps its gear.
  double engage_time = 0.0;
  // N m per rad/s of slip between engine and gearbox while the clutch slips after engaging.
  double clutch_strength = 1.0;
};

struct BrakeParams {
  double max_torque_front = 3200.0;  // N m per wheel at brake = 1
  double max_torque_rear = 2000.0;
  double hand_brake_torque = 3000.0;  // N m per rear wheel
  bool abs = true;                    // keeps braking slip below the tyre's peak
  // Electronic brake-force distribution: the rear wheels brake with at most this share of their grip,
  // keeping lateral grip at the rear when braking into a corner.
  double rear_grip_share = 0.8;
  // The pedal moves at most pedal_rate a second (0: at once), as CARLA's vehicles rate-limit their inputs;
  // brake pressure follows it as a first-order lag, building with rise_time and releasing with release_time
  // (s; 0: at once).
  double pedal_rate = 0.0;
  double rise_time = 0.0;
  double release_time = 0.0;
};

struct SteeringParams {
  double max_angle = 0.61;             // rad, road wheel angle at steer = 1
  double max_rate = 2.5;               // rad/s
  double response_time = 0.0;          // s: the wheels follow the command as a first-order lag (0: at once)
  vehicle::SteeringCurve speed_curve;  // share of max_angle by speed (CARLA's steering curve); empty: all of it
  double maxAngleAt(double speed) const { return max_angle * vehicle::steeringShare(speed_curve, speed); }
};

struct AeroParams {
  double drag_area = 0.58;       // m^2, Cd * A
  double downforce_area = 0.25;  // m^2, Cl * A, positive pushes down
  double front_downforce_share = 0.45;
  double air_density = 1.2;  // kg/m^3
};

// How the drive torque is shared between the driven wheels. Open differentials give each wheel of an axle
// half the axle's share whatever their speeds; limited-slip ones are PhysX's (PxVehicleDifferential4WData's
// LS types, which CARLA's cars have by default): while the faster of two outputs (left and right of an axle,
// or the front axle and the rear) turns more than `bias` times the slower, torque moves to the slower by the
// excess's share of the faster's speed (powertrain_test LimitedSlipMovesTorqueToTheSlowerWheel).
enum class DifferentialType { kOpen, kLimitedSlip };
struct DifferentialParams {
  DifferentialType type = DifferentialType::kOpen;
  double centre_bias = 1.3;  // front axle against rear (four-wheel drive only)
  double front_bias = 1.3;   // left against right
  double rear_bias = 1.3;
};

struct VehicleParams {
  std::string model;
  std::string blueprint;  // the CARLA-style id ROAR_PY programs spawn it by, e.g. vehicle.tesla.model3
  std::string description;
  ChassisParams chassis;
  std::array<WheelParams, 4> wheels;  // front left, front right, rear left, rear right
  SuspensionParams suspension;
  TyreParams tyre;
  EngineParams engine;
  GearboxParams gearbox;
  BrakeParams brakes;
  SteeringParams steering;
  AeroParams aero;
  double front_drive_share = 0.4;  // share of drive torque to the front axle (0: rear-wheel drive)
  DifferentialParams differential;
  bool traction_control = true;  // keeps driving slip below the tyre's peak
  double rear_grip_share = 0.8;  // traction control lets the rear wheels drive with at most this share of their grip

  double wheelbase() const { return wheels[0].position.x() - wheels[2].position.x(); }
  // s the pedals take to act: the longer of the torque's response and the brakes' build, from half the pedal's
  // travel time on (0: at once).
  double pedalResponseTime() const {
    return std::max(engine.response_time, brakes.rise_time + (brakes.pedal_rate > 0 ? 0.5 / brakes.pedal_rate : 0.0));
  }
  double track_width() const { return wheels[0].position.y() - wheels[1].position.y(); }
};

}  // namespace roar::vehicle

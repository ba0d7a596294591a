#include "roar/sim/lap_bound.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "roar/sim/tyre.h"
#include "roar/vehicle/powertrain.h"

namespace roar::sim {

namespace {

constexpr double kG = 9.81;
constexpr int kFront = 0, kRear = 1;

// The car as steady state sees it: loads on its four wheels and what the tyre model gives at them.
class SteadyCar {
 public:
  SteadyCar(const vehicle::VehicleParams& car, double road_friction)
      : car_(car), tyre_(car.tyre), powertrain_(car), mu_(road_friction) {
    const double x_front = car.wheels[0].position.x(), x_rear = car.wheels[2].position.x();
    wheelbase_ = x_front - x_rear;
    const double x_com = car.chassis.centre_of_mass.x();
    front_share_ = std::clamp((x_com - x_rear) / wheelbase_, 0.05, 0.95);  // as VehicleDynamics' static loads
    radius_ = car.wheels[0].radius;
    // The tyre forces act roll_influence of the way down from the centre of mass (VehicleDynamics), so that
    // is the height the weight moves over.
    const double ground = car.wheels[0].position.z() - radius_;
    height_ = car.suspension.roll_influence * (car.chassis.centre_of_mass.z() - ground);
    track_ = car.track_width();
    // Roll stiffness per axle: the springs, and an anti-roll bar twice (it pushes one wheel and pulls the other).
    const double k = car.suspension.stiffness, front = k + 2 * car.suspension.anti_roll_front,
                 rear = k + 2 * car.suspension.anti_roll_rear;
    front_roll_share_ = front / (front + rear);
    mass_ = car.chassis.mass;
    effective_mass_ = mass_;
    for (const auto& wheel : car.wheels) effective_mass_ += car.tyre.wheel_inertia / (wheel.radius * wheel.radius);
    // The magic formula falls past its peak; CarSimEd's tyre saturates, at a slip angle that grows with the
    // load (tan alpha = 3 mu Fz / C_y), so the search may go to 80 degrees.
    max_slip_angle_ = car.tyre.curve == vehicle::TyreCurve::kMagicFormula ? tyre_.peakSlipAngle() : 1.4;
    for (double v = 0.0; v < 150.0; v += 0.25) {
      top_speed_ = v;
      if (fullThrottleForce(v) <= resistance(v)) break;
    }
  }

  double topSpeed() const { return top_speed_; }

  // Loads on the front axle's outer and inner wheel, then the rear's, at speed v, lateral acceleration ay
  // and longitudinal ax.
  std::array<double, 4> wheelLoads(double v, double ay, double ax) const {
    const double weight = mass_ * kG, downforce = downforceCoefficient() * v * v;
    const double along = mass_ * ax * height_ / wheelbase_;  // moved to the rear when accelerating
    const std::array<double, 2> axle_load = {
        weight * front_share_ + downforce * car_.aero.front_downforce_share - along,
        weight * (1.0 - front_share_) + downforce * (1.0 - car_.aero.front_downforce_share) + along};
    const double across = mass_ * std::abs(ay) * height_ / track_;
    const std::array<double, 2> moved = {front_roll_share_ * across, (1.0 - front_roll_share_) * across};
    std::array<double, 4> loads{};
    for (int a : {kFront, kRear}) {
      const double load = std::max(0.0, axle_load[a]);
      loads[2 * a] = std::min(load, 0.5 * load + moved[a]);
      loads[2 * a + 1] = load - loads[2 * a];
    }
    return loads;
  }

  // Friction force each axle's two wheels have.
  std::array<double, 2> axleGrip(const std::array<double, 4>& loads) const {
    return {tyre_.peakForce(loads[0], mu_) + tyre_.peakForce(loads[1], mu_),
            tyre_.peakForce(loads[2], mu_) + tyre_.peakForce(loads[3], mu_)};
  }

  // What the slip angles cost: a wheel carrying lateral force F at slip angle alpha has F sin(alpha) of it
  // against the motion. Each wheel carries its grip's share of its axle's force, at the smallest slip angle
  // the tyre model gives that force at.
  double slipDrag(const std::array<double, 4>& loads, double ay) const {
    const auto grip = axleGrip(loads);
    const auto demand = lateralDemand(ay);
    double drag = 0.0;
    for (int w = 0; w < 4; ++w) {
      const int a = w / 2;
      if (grip[a] <= 0 || demand[a] <= 0) continue;
      const double force = std::min(1.0, demand[a] / grip[a]) * tyre_.peakForce(loads[w], mu_);
      drag += force * std::sin(slipAngleFor(force, loads[w]));
    }
    return drag;
  }

  // The cornering force each axle carries: its share of m ay by the weight split.
  std::array<double, 2> lateralDemand(double ay) const {
    return {mass_ * std::abs(ay) * front_share_, mass_ * std::abs(ay) * (1.0 - front_share_)};
  }

  // Whether each axle's grip at these loads carries its share of the cornering force.
  bool axlesHold(const std::array<double, 4>& loads, double ay) const {
    const auto grip = axleGrip(loads);
    const auto demand = lateralDemand(ay);
    return demand[kFront] <= grip[kFront] && demand[kRear] <= grip[kRear];
  }

  // Steady on this curvature: each axle carries its cornering force, and the motor, through the grip the
  // driven axles have left, holds the speed against drag, rolling resistance and the slip angles' drag.
  bool corners(double v, double curvature) const {
    const double ay = v * v * curvature;
    const auto loads = wheelLoads(v, ay, 0.0);
    if (!axlesHold(loads, ay)) return false;
    const double drive = std::min(fullThrottleForce(v), tractionLimit(leftAfterCornering(loads, ay)));
    return drive >= resistance(v) + slipDrag(loads, ay);
  }

  double cornerSpeed(double curvature) const {
    if (corners(top_speed_, curvature)) return top_speed_;
    // The axles' grip alone bounds it first (cheap), then the drive against drag, slip drag included.
    double lo = 0.0, hi = top_speed_;
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (lo + hi), ay = mid * mid * curvature;
      (axlesHold(wheelLoads(mid, ay, 0.0), ay) ? lo : hi) = mid;
    }
    hi = lo;
    lo = 0.0;
    for (int i = 0; i < 30; ++i) {
      const double mid = 0.5 * (lo + hi);
      (corners(mid, curvature) ? lo : hi) = mid;
    }
    return lo;
  }

  // m/s^2 at full throttle, the driven axles inside their friction circles after the cornering force.
  double driveAcceleration(double v, double curvature) const {
    const double ay = v * v * curvature;
    double ax = 0.0;
    for (int pass = 0; pass < 4; ++pass) {  // the weight moved depends on ax
      const auto loads = wheelLoads(v, ay, ax);
      const double force = std::min(fullThrottleForce(v), tractionLimit(leftAfterCornering(loads, ay)));
      ax = (force - resistance(v) - slipDrag(loads, ay)) / effective_mass_;
    }
    return ax;
  }

  // m/s^2 (positive) with the brakes full on, each axle's braking inside its friction circle.
  double brakeDeceleration(double v, double curvature) const {
    const double ay = v * v * curvature;
    const double torque[2] = {2 * car_.brakes.max_torque_front, 2 * car_.brakes.max_torque_rear};
    const double rear_share = car_.brakes.abs ? car_.brakes.rear_grip_share : 1.0;  // brake-force distribution
    double deceleration = 0.0;
    for (int pass = 0; pass < 4; ++pass) {
      const auto loads = wheelLoads(v, ay, -deceleration);
      const auto left = leftAfterCornering(loads, ay);
      const double force = std::min(torque[kFront] / radius_, left[kFront]) +
                           std::min(torque[kRear] / radius_, rear_share * left[kRear]);
      deceleration = (force + resistance(v) + slipDrag(loads, ay)) / effective_mass_;
    }
    return deceleration;
  }

 private:
  double downforceCoefficient() const { return 0.5 * car_.aero.air_density * car_.aero.downforce_area; }

  double resistance(double v) const {
    const double drag = 0.5 * car_.aero.air_density * car_.aero.drag_area * v * v;
    return drag + car_.tyre.rolling_resistance * (mass_ * kG + downforceCoefficient() * v * v);
  }

  double fullThrottleForce(double v) const {
    const double wheel_rpm = v / radius_ * 60.0 / (2.0 * M_PI);
    const int gear = powertrain_.strongestGear(wheel_rpm);
    return gear > 0 ? powertrain_.fullThrottleWheelTorque(gear, wheel_rpm) / radius_ : 0.0;
  }

  // The most drive force the driven axles put down with `left` of their grip, split as the drivetrain splits it.
  double tractionLimit(const std::array<double, 2>& left) const {
    const double shares[2] = {car_.front_drive_share, 1.0 - car_.front_drive_share};
    // Traction control passes at most this share of a wheel's grip (VehicleDynamics).
    const double passed[2] = {car_.traction_control ? 0.95 : 1.0,
                              car_.traction_control ? 0.95 * car_.rear_grip_share : 1.0};
    double force = 1e300;
    for (int a : {kFront, kRear}) {
      if (shares[a] > 0) force = std::min(force, passed[a] * left[a] / shares[a]);
    }
    return force;
  }

  // rad: the smallest slip angle at which the tyre gives `force` sideways at this load (pure slip), no more
  // than the angle of its peak.
  double slipAngleFor(double force, double load) const {
    double lo = 0.0, hi = max_slip_angle_;
    for (int i = 0; i < 20; ++i) {
      const double mid = 0.5 * (lo + hi);
      (std::abs(tyre_.force(0.0, mid, load, mu_).lateral) < force ? lo : hi) = mid;
    }
    return hi;
  }

  std::array<double, 2> leftAfterCornering(const std::array<double, 4>& loads, double ay) const {
    const auto grip = axleGrip(loads);
    const auto demand = lateralDemand(ay);
    return {std::sqrt(std::max(0.0, grip[kFront] * grip[kFront] - demand[kFront] * demand[kFront])),
            std::sqrt(std::max(0.0, grip[kRear] * grip[kRear] - demand[kRear] * demand[kRear]))};
  }

  const vehicle::VehicleParams& car_;
  TyreModel tyre_;
  vehicle::Powertrain powertrain_;
  double mu_;
  double wheelbase_ = 0.0, front_share_ = 0.5, radius_ = 0.3, height_ = 0.0, track_ = 1.5;
  double front_roll_share_ = 0.5, mass_ = 0.0, effective_mass_ = 0.0, top_speed_ = 0.0, max_slip_angle_ = 0.2;
};

void checkLine(const std::vector<double>& curvature, const std::vector<double>& step, bool closed) {
  if (curvature.size() < 2) throw std::invalid_argument("lap bound: the line needs at least 2 points");
  if (step.size() != curvature.size()) {
    throw std::invalid_argument("lap bound: " + std::to_string(step.size()) + " steps for " +
                                std::to_string(curvature.size()) + " points");
  }
  const std::size_t steps = closed ? step.size() : step.size() - 1;
  for (std::size_t i = 0; i < steps; ++i) {
    if (!(step[i] > 0)) throw std::invalid_argument("lap bound: step " + std::to_string(i) + " is not positive");
  }
}

}  // namespace

LapBound quasiSteadyStateLap(const std::vector<double>& curvature, const std::vector<double>& step, bool closed,
                             const vehicle::VehicleParams& car, double road_friction) {
  checkLine(curvature, step, closed);
  if (!(road_friction > 0)) throw std::invalid_argument("lap bound: road friction must be positive");
  const SteadyCar model(car, road_friction);
  const std::size_t n = curvature.size();
  LapBound bound;
  bound.top_speed = model.topSpeed();
  bound.corner_speed.resize(n);
  for (std::size_t i = 0; i < n; ++i) bound.corner_speed[i] = model.cornerSpeed(std::abs(curvature[i]));
  auto& v = bound.speed;
  v = bound.corner_speed;
  // Round a circuit both passes start at the slowest corner, where the car is at its corner speed; a course
  // starts standing and ends free.
  const std::size_t first = closed ? static_cast<std::size_t>(std::min_element(v.begin(), v.end()) - v.begin()) : 0;
  const std::size_t segments = closed ? n : n - 1;
  if (!closed) v[0] = 0.0;
  for (std::size_t k = 0; k < segments; ++k) {
    const std::size_t i = (first + k) % n, j = (i + 1) % n;
    const double a = model.driveAcceleration(v[i], curvature[i]);
    v[j] = std::min(v[j], std::sqrt(std::max(0.0, v[i] * v[i] + 2.0 * a * step[i])));
  }
  const std::size_t last = closed ? first : n - 1;
  for (std::size_t k = 0; k < segments; ++k) {
    const std::size_t j = (last + n - k) % n, i = (j + n - 1) % n;
    const double d = model.brakeDeceleration(v[j], curvature[j]);
    v[i] = std::min(v[i], std::sqrt(v[j] * v[j] + 2.0 * d * step[i]));
  }
  for (std::size_t i = 0; i < segments; ++i) {
    const double mean = 0.5 * (v[i] + v[(i + 1) % n]);
    bound.lap_time += mean > 0 ? step[i] / mean : 0.0;
  }
  return bound;
}

}  // namespace roar::sim

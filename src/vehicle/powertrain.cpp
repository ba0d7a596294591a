#include "roar/vehicle/powertrain.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

namespace roar::vehicle {

namespace {

// PhysX's limited-slip split of a torque of 1 between two outputs turning at w1 and w2 (the same way):
// `split` to the first while neither turns more than `bias` times the other, the excess's share of the
// faster's speed moved to the slower past it.
std::array<double, 2> limitedSlipSplit(double w1, double w2, double bias, double split) {
  const double a1 = std::abs(w1), a2 = std::abs(w2);
  const double fastest = std::max(a1, a2), slowest = std::min(a1, a2);
  const double excess = fastest - bias * slowest;
  const double moved = excess >= 0 && fastest > 0 ? excess / fastest : 0.0;
  const bool first_faster = a1 >= a2;
  const double f1 = split * (first_faster ? 1.0 - moved : 1.0 + moved);
  const double f2 = (1.0 - split) * (first_faster ? 1.0 + moved : 1.0 - moved);
  return {f1 / (f1 + f2), f2 / (f1 + f2)};
}

bool sameWay(std::initializer_list<double> omegas) {
  const double first = *omegas.begin();
  if (first == 0.0) return false;
  for (const double w : omegas) {
    if (w == 0.0 || (w > 0) != (first > 0)) return false;
  }
  return true;
}

constexpr double kRadPerSecToRpm = 60.0 / (2.0 * M_PI);
// Kickdown needs the pedal nearly floored, like a road car's; a part-throttle cruise keeps its gear.
constexpr double kKickdownThrottle = 0.9;
// A kickdown gear must leave this much below the shift-up rpm, or the next tick would shift back up.
constexpr double kKickdownHeadroomRpm = 300.0;
// For this long after a shift up at full throttle, no kickdown back while the pedal has stayed floored and the
// car has lost less than kKickdownHoldLoss of the speed it shifted up at: on a climb the car loses a little speed in
// each shift's torque gap, and the gear just left, stronger at that speed but at its limit, would take it straight
// back, shift up again at once, and so on, never pulling the higher gear up the hill (the hatchback hunted 1-2 for 15 s
// up Roar Hillclimb). A car that lifted (behind another) or slowed by more kicks down as before.
constexpr double kKickdownHoldTime = 1.0;
constexpr double kKickdownHoldLoss = 0.1;
}  // namespace

std::array<double, 4> driveShares(const DifferentialParams& differential, double front_share,
                                  const std::array<double, 4>& w) {
  const double front = std::clamp(front_share, 0.0, 1.0), rear = 1.0 - front;
  std::array<double, 4> shares{0.5 * front, 0.5 * front, 0.5 * rear, 0.5 * rear};
  if (differential.type == DifferentialType::kOpen) return shares;
  // As PhysX: an axle's wheels, or all four, turning different ways share as open differentials do.
  const bool four_wheel = front > 0.0 && rear > 0.0;
  if (four_wheel) {
    if (!sameWay({w[0], w[1], w[2], w[3]})) return shares;
    const auto axles = limitedSlipSplit(w[0] + w[1], w[2] + w[3], differential.centre_bias, front);
    const auto fronts = limitedSlipSplit(w[0], w[1], differential.front_bias, 0.5);
    const auto rears = limitedSlipSplit(w[2], w[3], differential.rear_bias, 0.5);
    return {axles[0] * fronts[0], axles[0] * fronts[1], axles[1] * rears[0], axles[1] * rears[1]};
  }
  const int first = front > 0.0 ? 0 : 2;
  if (!sameWay({w[first], w[first + 1]})) return shares;
  const auto pair =
      limitedSlipSplit(w[first], w[first + 1], first == 0 ? differential.front_bias : differential.rear_bias, 0.5);
  shares[first] = pair[0];
  shares[first + 1] = pair[1];
  return shares;
}

Powertrain::Powertrain(const VehicleParams& params) : engine_(params.engine), gearbox_(params.gearbox) { reset(true); }

void Powertrain::reset(bool put_down) {
  standing_ = put_down && gearbox_.engage_time > 0;
  gear_ = standing_ ? 0 : 1;
  shift_timer_ = 0.0;
  since_upshift_ = kKickdownHoldTime;
  rpm_ = engine_.idle_rpm;
  throttle_level_ = 0.0;
  engage_timer_ = std::numeric_limits<double>::infinity();
  clutch_slipping_ = false;
  engine_omega_ = engine_.idle_rpm / kRadPerSecToRpm;
}

void Powertrain::settle(double throttle) {
  standing_ = false;
  clutch_slipping_ = false;
  if (gear_ == 0) gear_ = 1;
  throttle_level_ = std::clamp(throttle, 0.0, 1.0);
}

double Powertrain::ownTorque(double throttle) const {
  return rpm_ > engine_.redline_rpm ? 0.0 : throttle * engineTorqueAt(rpm_);
}

bool Powertrain::standInNeutral(double throttle, double dt) {
  if (std::isinf(engage_timer_) && throttle > 0) engage_timer_ = gearbox_.engage_time;
  engage_timer_ -= dt;
  // In neutral the engine revs against its own drag (its engine braking at the throttle's share).
  const double drag = (1.0 - throttle) * engine_.engine_brake_torque * (rpm_ / engine_.redline_rpm);
  const double idle = engine_.idle_rpm / kRadPerSecToRpm, redline = engine_.redline_rpm / kRadPerSecToRpm;
  engine_omega_ = std::clamp(engine_omega_ + dt * (ownTorque(throttle) - drag) / engine_.inertia, idle, redline);
  rpm_ = engine_omega_ * kRadPerSecToRpm;
  if (engage_timer_ > 0) return true;
  standing_ = false;
  gear_ = 1;
  clutch_slipping_ = true;
  return false;
}

bool Powertrain::slipClutch(double throttle, double wheel_rpm, double dt, double* wheel_torque) {
  const double r = ratio(gear_);
  const double coupled = wheel_rpm * r / kRadPerSecToRpm;
  const double clutch = gearbox_.clutch_strength * (engine_omega_ - coupled);
  const double own = ownTorque(throttle);
  // The clutch closes once the engine has come down to the wheels, or stops coming down (its own torque
  // now as much as the slipping clutch passes): from then on engine and wheels turn together.
  if (engine_omega_ <= coupled || clutch <= own) {
    clutch_slipping_ = false;
    return false;
  }
  engine_omega_ = std::max(coupled, engine_omega_ + dt * (own - clutch) / engine_.inertia);
  rpm_ = engine_omega_ * kRadPerSecToRpm;
  *wheel_torque = clutch * r * gearbox_.efficiency;
  return true;
}

double Powertrain::ratio(int gear) const {
  if (gear == 0) return 0.0;
  if (gear < 0) return -gearbox_.reverse_ratio * gearbox_.final_drive;
  return gearbox_.ratios[static_cast<std::size_t>(gear - 1)] * gearbox_.final_drive;
}

double Powertrain::engineTorqueAt(double rpm) const {
  const auto& curve = engine_.torque_curve;
  if (rpm <= curve.front().first) return curve.front().second;
  if (rpm >= curve.back().first) return curve.back().second;
  auto hi = std::upper_bound(curve.begin(), curve.end(), rpm, [](double r, const auto& p) { return r < p.first; });
  auto lo = hi - 1;
  const double t = (rpm - lo->first) / (hi->first - lo->first);
  return lo->second + t * (hi->second - lo->second);
}

double Powertrain::fullThrottleWheelTorque(int gear, double wheel_rpm) const {
  const double r = ratio(gear);
  return engineTorqueAt(std::max(wheel_rpm * r, engine_.idle_rpm)) * r * gearbox_.efficiency;
}

int Powertrain::strongestGear(double wheel_rpm, double headroom_rpm) const {
  const int top = static_cast<int>(gearbox_.ratios.size());
  int best_gear = 0;
  double best = 0.0;
  for (int g = 1; g <= top; ++g) {
    const double ceiling = g == top ? engine_.redline_rpm : gearbox_.shift_up_rpm - headroom_rpm;
    if (wheel_rpm * ratio(g) > ceiling) continue;
    const double torque = fullThrottleWheelTorque(g, wheel_rpm);
    if (torque > best) {
      best = torque;
      best_gear = g;
    }
  }
  return best_gear;
}

double Powertrain::update(const DriveRequest& request, double driven_wheel_omega, double dt) {
  const double pedal = std::clamp(request.throttle, 0.0, 1.0);
  throttle_level_ = engine_.response_time > 0
                        ? throttle_level_ + (pedal - throttle_level_) * -std::expm1(-dt / engine_.response_time)
                        : pedal;
  // A car standing in neutral waits for its first gear unless the driver picks one or reverse.
  if (standing_ && (request.manual || request.reverse)) standing_ = false;
  if (standing_ && standInNeutral(throttle_level_, dt)) return 0.0;
  double launch_torque = 0.0;
  if (clutch_slipping_ &&
      slipClutch(throttle_level_, std::abs(driven_wheel_omega) * kRadPerSecToRpm, dt, &launch_torque))
    return launch_torque;
  const int top = static_cast<int>(gearbox_.ratios.size());
  int wanted = gear_;
  if (request.manual) {
    wanted = std::clamp(request.gear, -1, top);
  } else if (request.reverse) {
    wanted = -1;
  } else if (gear_ <= 0) {
    wanted = 1;
  }
  if (wanted != gear_) {
    gear_ = wanted;
    shift_timer_ = gearbox_.shift_time;
  }

  const double wheel_rpm = std::abs(driven_wheel_omega) * kRadPerSecToRpm;
  const double throttle = throttle_level_;
  if (pedal < kKickdownThrottle) floored_since_upshift_ = false;
  if (!request.manual && gear_ > 0 && shift_timer_ <= 0) {
    const double rpm = wheel_rpm * ratio(gear_);
    int next = gear_;
    if (rpm > gearbox_.shift_up_rpm && gear_ < top) {
      next = gear_ + 1;
      since_upshift_ = 0.0;
      upshift_wheel_rpm_ = wheel_rpm;
      floored_since_upshift_ = true;
    } else {
      // Kickdown: floored, the gearbox drops straight to the gear that pulls hardest instead of lugging the
      // one it came into the corner with. Not when lifting as well: shifting down off the throttle
      // mid-corner makes engine braking jump and unsettles the car.
      const bool holding = since_upshift_ < kKickdownHoldTime && floored_since_upshift_ &&
                           wheel_rpm > (1.0 - kKickdownHoldLoss) * upshift_wheel_rpm_;
      if (gearbox_.kickdown && pedal >= kKickdownThrottle && !holding) {
        const int strongest = strongestGear(wheel_rpm, kKickdownHeadroomRpm);
        if (strongest > 0 && strongest < gear_) next = strongest;
      }
      if (next == gear_ && rpm < gearbox_.shift_down_rpm && gear_ > 1) next = gear_ - 1;
    }
    if (next != gear_) {
      gear_ = next;
      shift_timer_ = gearbox_.shift_time;
    }
  }
  shift_timer_ = std::max(0.0, shift_timer_ - dt);
  since_upshift_ += dt;

  const double r = ratio(gear_);
  if (r == 0.0) {
    rpm_ = engine_.idle_rpm + throttle * (engine_.redline_rpm - engine_.idle_rpm);
    return 0.0;
  }
  const double coupled_rpm = wheel_rpm * std::abs(r);
  rpm_ = std::max(engine_.idle_rpm, coupled_rpm);
  engine_omega_ = rpm_ / kRadPerSecToRpm;
  if (shift_timer_ > 0) return 0.0;

  double engine_torque = ownTorque(throttle);
  // Engine braking only once the clutch is closed (the wheels turn the engine above idle).
  if (coupled_rpm > engine_.idle_rpm) {
    engine_torque -= (1.0 - throttle) * engine_.engine_brake_torque * (rpm_ / engine_.redline_rpm);
  }
  if (engine_torque >= 0) return engine_torque * r * gearbox_.efficiency;
  // Engine braking opposes the wheels' rotation, whichever way the gear turns them.
  const double rolling_direction = driven_wheel_omega >= 0 ? 1.0 : -1.0;
  return engine_torque * std::abs(r) * gearbox_.efficiency * rolling_direction;
}

}  // namespace roar::vehicle

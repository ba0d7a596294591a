#include "roar/planning/speed_profile.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace roar::planning {

double accelerationAt(const VehicleLimits& limits, double v, double kappa, bool shifting) {
  const double drive =
      shifting ? 0.0 : std::min(limits.driveForce(v), limits.traction_share * limits.longitudinalGrip(v, kappa));
  return (drive - limits.resistance(v)) / limits.effectiveMass();
}

double decelerationAt(const VehicleLimits& limits, double v, double kappa) {
  const double brake = std::min(limits.max_brake_force, limits.longitudinalGrip(v, kappa));
  return (brake + limits.resistance(v)) / limits.effectiveMass();
}

double decelerationAt(const VehicleLimits& limits, double v, double kappa, double grade) {
  return std::max(0.0, decelerationAt(limits, v, kappa) + limits.gravity * grade);
}

SpeedProfile computeSpeedProfile(const std::vector<double>& step, const std::vector<double>& curvature,
                                 const VehicleLimits& limits, bool closed, const SpeedProfileOptions& options) {
  const std::size_t n = curvature.size();
  if (n < 2 || step.size() != n) {
    throw std::invalid_argument("speed profile: need at least 2 points and one step per point (got " +
                                std::to_string(n) + " curvatures, " + std::to_string(step.size()) + " steps)");
  }
  const std::size_t segments = closed ? n : n - 1;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(curvature[i]))
      throw std::invalid_argument("speed profile: curvature " + std::to_string(i) + " is not finite");
    if (i < segments && !(step[i] > 0 && std::isfinite(step[i]))) {
      throw std::invalid_argument("speed profile: step " + std::to_string(i) + " is not a positive distance");
    }
  }
  if (!options.grade.empty() && options.grade.size() != n) {
    throw std::invalid_argument("speed profile: " + std::to_string(options.grade.size()) + " grades for " +
                                std::to_string(n) + " points");
  }
  for (std::size_t i = 0; i < options.grade.size(); ++i) {
    if (!(std::abs(options.grade[i]) <= 1.0))
      throw std::invalid_argument("speed profile: grade " + std::to_string(i) + " is not the sine of a slope");
  }
  if (!options.vertical_curvature.empty() && options.vertical_curvature.size() != n) {
    throw std::invalid_argument("speed profile: " + std::to_string(options.vertical_curvature.size()) +
                                " vertical curvatures for " + std::to_string(n) + " points");
  }
  for (std::size_t i = 0; i < options.vertical_curvature.size(); ++i) {
    if (!std::isfinite(options.vertical_curvature[i]))
      throw std::invalid_argument("speed profile: vertical curvature " + std::to_string(i) + " is not finite");
  }
  auto along = [&](std::size_t i) { return options.grade.empty() ? 0.0 : limits.gravity * options.grade[i]; };
  auto vertical = [&](std::size_t i) {
    return options.vertical_curvature.empty() ? 0.0 : options.vertical_curvature[i];
  };
  const double top = options.max_speed > 0 ? std::min(options.max_speed, limits.max_speed) : limits.max_speed;

  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = std::min(top, limits.corneringSpeed(curvature[i], vertical(i)));
  if (!closed) {
    if (options.start_speed >= 0) v.front() = std::min(v.front(), options.start_speed);
    if (options.end_speed >= 0) v.back() = std::min(v.back(), options.end_speed);
  }

  // Passes start where nothing before matters: the slowest point of a loop, or the path's ends.
  const std::size_t start = closed ? static_cast<std::size_t>(std::min_element(v.begin(), v.end()) - v.begin()) : 0;
  // Each upshift costs the gearbox's shift time without drive: the distance covered meanwhile coasts.
  // The gear only goes up while the car accelerates (a gearbox has hysteresis: losing a little speed
  // while shifting does not shift it back down); it follows the speed down where a corner caps it.
  double coast = 0.0;
  int gear = limits.gearAt(v[start]);
  for (std::size_t k = 0; k < segments; ++k) {
    const std::size_t i = (start + k) % n, j = (i + 1) % n;
    const double a = accelerationAt(limits, v[i], curvature[i], coast > 0) - along(i);
    coast = std::max(0.0, coast - step[i]);
    const double reachable = std::sqrt(std::max(0.0, v[i] * v[i] + 2.0 * a * step[i]));
    if (reachable < v[j]) {
      if (limits.gearAt(reachable) > gear) {
        gear = limits.gearAt(reachable);
        coast = limits.shift_time * reachable;
      }
      v[j] = reachable;
    } else {
      gear = limits.gearAt(v[j]);
    }
  }
  const std::size_t end = closed ? start : n - 1;
  for (std::size_t k = 0; k < segments; ++k) {
    const std::size_t j = (end + n - k) % n, i = (j + n - 1) % n;
    const double d = decelerationAt(limits, v[j], curvature[j], options.grade.empty() ? 0.0 : options.grade[i]);
    v[i] = std::min(v[i], std::sqrt(v[j] * v[j] + 2.0 * d * step[i]));
  }

  SpeedProfile profile;
  profile.speed = v;
  profile.acceleration.assign(n, 0.0);
  profile.time.assign(n, 0.0);
  double t = 0.0;
  for (std::size_t i = 0; i < segments; ++i) {
    const std::size_t j = (i + 1) % n;
    profile.acceleration[i] = (v[j] * v[j] - v[i] * v[i]) / (2.0 * step[i]);
    const double mean = 0.5 * (v[i] + v[j]);
    t += mean > 1e-6 ? step[i] / mean : 0.0;
    if (j != 0) profile.time[j] = t;
  }
  profile.total_time = t;
  return profile;
}

std::vector<double> towedSpeeds(const std::vector<double>& step, const std::vector<double>& curvature,
                                const std::vector<double>& speed, const VehicleLimits& limits, double drag_share) {
  std::vector<double> out = speed;
  if (!(drag_share < 1.0) || speed.size() < 2) return out;
  VehicleLimits tow = limits;
  tow.drag_coefficient *= std::max(0.0, drag_share);
  SpeedProfileOptions start;
  start.start_speed = speed.front();
  const SpeedProfile free_air = computeSpeedProfile(step, curvature, limits, false, start);
  const SpeedProfile in_tow = computeSpeedProfile(step, curvature, tow, false, start);
  for (std::size_t k = 0; k < out.size(); ++k) {
    if (free_air.speed[k] > 1.0) out[k] *= std::max(1.0, in_tow.speed[k] / free_air.speed[k]);
  }
  return out;
}

}  // namespace roar::planning

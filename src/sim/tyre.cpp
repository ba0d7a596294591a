#include "roar/sim/tyre.h"

#include <algorithm>
#include <cmath>

namespace roar::sim {

namespace {

double magicFormula(double b, double c, double e, double slip) {
  const double bs = b * slip;
  return std::sin(c * std::atan(bs - e * (bs - std::atan(bs))));
}

// Slip at which the curve peaks: where the sine's argument reaches pi/2 (found by bisection; the
// argument rises monotonically for E < 1).
double peakSlip(double b, double c, double e) {
  const double target = std::tan(M_PI / (2.0 * c));
  double lo = 0.0, hi = 10.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double bs = b * mid;
    (bs - e * (bs - std::atan(bs)) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

constexpr double kG = 9.81;

// CarSimEd's saturating curve (its equation 20): rises like K at first and reaches 1 at K = 3.
double carSimEdCurve(double k) { return std::min(1.0, k - k * k / 3.0 + k * k * k / 27.0); }

double carSimEdCorneringStiffness(const vehicle::TyreParams& p, double load) {
  return p.nominal_load * p.lateral_stiffness *
         carSimEdCurve(3.0 * (load / p.nominal_load) / p.lateral_stiffness_max_load);
}

}  // namespace

TyreModel::TyreModel(const vehicle::TyreParams& params) : params_(params) {
  if (params.curve == vehicle::TyreCurve::kCarSimEd) {
    // K = 3 in pure slip at the nominal load: kappa C_x = 3 mu Fz, tan(alpha) C_y = 3 mu Fz.
    const double friction = 3.0 * params.grip * params.nominal_load;
    peak_slip_ratio_ = friction / (params.longitudinal_stiffness * kG);
    peak_slip_angle_ = std::atan(friction / carSimEdCorneringStiffness(params, params.nominal_load));
  } else {
    peak_slip_ratio_ = peakSlip(params.long_b, params.long_c, params.long_e);
    peak_slip_angle_ = peakSlip(params.lat_b, params.lat_c, params.lat_e);
  }
}

TyreForce TyreModel::carSimEd(double slip_ratio, double slip_angle, double load, double mu) const {
  const double friction = peakForce(load, mu);
  if (friction <= 0) return {};
  const double cx = params_.longitudinal_stiffness * kG, cy = carSimEdCorneringStiffness(params_, load);
  const double t = std::tan(slip_angle);
  const double k = std::hypot(cx * slip_ratio, cy * t) / friction;
  if (k < 1e-12) return {};
  // The share between the slips: nu blends the stiffnesses' ratio (small K) towards 1 (K = 2 pi and beyond).
  const double ratio = cy / cx;
  const double nu = k <= 2.0 * M_PI ? 0.5 * (1.0 + ratio - (1.0 - ratio) * std::cos(0.5 * k)) : 1.0;
  const double scale = friction * carSimEdCurve(k) / std::hypot(slip_ratio, nu * t);
  return {slip_ratio * scale, -nu * t * scale};
}

double TyreModel::peakForce(double load, double mu) const {
  if (load <= 0) return 0.0;
  const double dfz = (load - params_.nominal_load) / params_.nominal_load;
  const double scale = std::max(0.5, 1.0 - params_.load_sensitivity * dfz);
  return mu * params_.grip * scale * load;
}

TyreForce TyreModel::force(double slip_ratio, double slip_angle, double load, double mu) const {
  if (params_.curve == vehicle::TyreCurve::kCarSimEd) return carSimEd(slip_ratio, slip_angle, load, mu);
  const double d = peakForce(load, mu);
  if (d <= 0) return {};
  const double sx = slip_ratio / peak_slip_ratio_;
  const double sy = slip_angle / peak_slip_angle_;
  const double rho = std::hypot(sx, sy);
  if (rho < 1e-12) return {};
  const double fx = d * magicFormula(params_.long_b, params_.long_c, params_.long_e, rho * peak_slip_ratio_);
  const double fy = d * magicFormula(params_.lat_b, params_.lat_c, params_.lat_e, rho * peak_slip_angle_);
  return {fx * sx / rho, -fy * sy / rho};
}

double TyreModel::longitudinalForce(double slip_ratio, double slip_angle, double load, double mu) const {
  // force()'s longitudinal half, without the lateral curve: the wheel-spin integration asks for it twice.
  if (params_.curve == vehicle::TyreCurve::kCarSimEd) return carSimEd(slip_ratio, slip_angle, load, mu).longitudinal;
  const double d = peakForce(load, mu);
  if (d <= 0) return 0.0;
  const double sx = slip_ratio / peak_slip_ratio_;
  const double rho = std::hypot(sx, slip_angle / peak_slip_angle_);
  if (rho < 1e-12) return 0.0;
  return d * magicFormula(params_.long_b, params_.long_c, params_.long_e, rho * peak_slip_ratio_) * sx / rho;
}

}  // namespace roar::sim

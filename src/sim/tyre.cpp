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

}  // namespace

TyreModel::TyreModel(const vehicle::TyreParams& params)
    : params_(params),
      peak_slip_ratio_(peakSlip(params.long_b, params.long_c, params.long_e)),
      peak_slip_angle_(peakSlip(params.lat_b, params.lat_c, params.lat_e)) {}

double TyreModel::peakForce(double load, double mu) const {
  if (load <= 0) return 0.0;
  const double dfz = (load - params_.nominal_load) / params_.nominal_load;
  const double scale = std::max(0.5, 1.0 - params_.load_sensitivity * dfz);
  return mu * params_.grip * scale * load;
}

TyreForce TyreModel::force(double slip_ratio, double slip_angle, double load, double mu) const {
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
  const double d = peakForce(load, mu);
  if (d <= 0) return 0.0;
  const double sx = slip_ratio / peak_slip_ratio_;
  const double rho = std::hypot(sx, slip_angle / peak_slip_angle_);
  if (rho < 1e-12) return 0.0;
  return d * magicFormula(params_.long_b, params_.long_c, params_.long_e, rho * peak_slip_ratio_) * sx / rho;
}

}  // namespace roar::sim

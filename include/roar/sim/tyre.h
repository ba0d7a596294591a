#pragma once
// Tyre forces from one of two curves (vehicle::TyreCurve):
// - the Pacejka magic formula F = D sin(C atan(B s - E (B s - atan(B s)))), with load sensitivity (the
//   friction coefficient falls as the load rises above the nominal load) and combined slip by normalised
//   slip: each slip is divided by the slip of its pure-slip peak, the resultant
//   rho = |(kappa/kappa_peak, alpha/alpha_peak)| is fed to each curve and the force shared out in
//   proportion, so that pure slip gives the pure curves and combined slip stays inside the friction ellipse;
// - CarSimEd's tyre (the Michigan model; CarSimEd manual, appendix F, equations 20 and 21), the one PhysX's
//   vehicle SDK and so CARLA 0.9's cars use: with stiffnesses C_x (per unit slip) and C_y (per rad),
//   K = |(C_x kappa, C_y tan(alpha))| / (mu Fz), the force's size mu Fz min(1, K - K^2/3 + K^3/27) (linear
//   at first, saturating at K = 3 and never falling off) shared between the slips with a blend nu of the
//   two stiffnesses. Soft for its friction: CARLA's cars corner at slip angles of 10 degrees and more.
#include "roar/vehicle/vehicle_params.h"

namespace roar::sim {

struct TyreForce {
  double longitudinal = 0.0;  // N, along the wheel heading
  double lateral = 0.0;       // N, to the wheel's left
};

class TyreModel {
 public:
  explicit TyreModel(const vehicle::TyreParams& params);

  // slip_ratio = (omega r - vx) / |vx|; slip_angle = atan(vy / |vx|) in radians (vy: contact patch velocity to
  // the left); load in N; mu: road friction. The lateral force opposes the slip angle.
  TyreForce force(double slip_ratio, double slip_angle, double load, double mu) const;
  // force(...).longitudinal, bit for bit, at half the cost.
  double longitudinalForce(double slip_ratio, double slip_angle, double load, double mu) const;
  // Friction force available at this load and road (with the tyre's own grip): the magic formula's D.
  double peakForce(double load, double mu) const;
  // The slips of the pure-slip peaks (CarSimEd's: at the nominal load on a road of friction 1).
  double peakSlipRatio() const { return peak_slip_ratio_; }
  double peakSlipAngle() const { return peak_slip_angle_; }

 private:
  TyreForce carSimEd(double slip_ratio, double slip_angle, double load, double mu) const;

  vehicle::TyreParams params_;
  double peak_slip_ratio_;
  double peak_slip_angle_;
};

}  // namespace roar::sim

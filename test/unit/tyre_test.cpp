#include <gtest/gtest.h>

#include "roar/sim/tyre.h"

using roar::sim::TyreModel;
using roar::vehicle::TyreParams;

TEST(Tyre, PurePeaksAtTheComputedSlipAndReachD) {
  TyreModel tyre{TyreParams{}};
  const double load = 4500, mu = 1.0, d = tyre.peakForce(load, mu);
  EXPECT_NEAR(d, 4500.0, 1e-9) << "no load sensitivity at the nominal load";
  double best = 0, best_slip = 0;
  for (double k = 0.0; k < 0.5; k += 0.0005) {
    const double f = tyre.force(k, 0, load, mu).longitudinal;
    if (f > best) best = f, best_slip = k;
  }
  EXPECT_NEAR(best, d, 1e-3 * d);
  EXPECT_NEAR(best_slip, tyre.peakSlipRatio(), 0.002);
  EXPECT_GT(tyre.peakSlipRatio(), 0.05);
  EXPECT_LT(tyre.peakSlipRatio(), 0.15);
  EXPECT_GT(tyre.peakSlipAngle(), 3 * M_PI / 180);
  EXPECT_LT(tyre.peakSlipAngle(), 10 * M_PI / 180);
  // Sliding keeps most of the grip.
  EXPECT_GT(tyre.force(1.0, 0, load, mu).longitudinal, 0.7 * d);
}

TEST(Tyre, LateralForceOpposesSlipAngle) {
  TyreModel tyre{TyreParams{}};
  EXPECT_LT(tyre.force(0, 0.05, 4000, 1.0).lateral, 0);
  EXPECT_GT(tyre.force(0, -0.05, 4000, 1.0).lateral, 0);
  EXPECT_LT(tyre.force(-0.05, 0, 4000, 1.0).longitudinal, 0) << "braking slip gives a braking force";
}

TEST(Tyre, CombinedSlipStaysInsideTheFrictionCircle) {
  TyreModel tyre{TyreParams{}};
  const double load = 5000, mu = 1.1, d = tyre.peakForce(load, mu);
  for (double k = -1; k <= 1; k += 0.05) {
    for (double a = -0.5; a <= 0.5; a += 0.02) {
      const auto f = tyre.force(k, a, load, mu);
      EXPECT_LE(std::hypot(f.longitudinal, f.lateral), d * (1 + 1e-9));
    }
  }
  // Adding brake slip at the lateral peak costs lateral force.
  const double pure = std::abs(tyre.force(0, tyre.peakSlipAngle(), load, mu).lateral);
  const double combined = std::abs(tyre.force(-tyre.peakSlipRatio(), tyre.peakSlipAngle(), load, mu).lateral);
  EXPECT_LT(combined, 0.8 * pure);
}

TEST(Tyre, LoadSensitivityLowersTheFrictionCoefficient) {
  TyreModel tyre{TyreParams{}};
  EXPECT_LT(tyre.peakForce(9000, 1.0) / 9000, tyre.peakForce(4500, 1.0) / 4500);
  EXPECT_GT(tyre.peakForce(2000, 1.0) / 2000, 1.0);
  EXPECT_EQ(tyre.peakForce(0, 1.0), 0.0);
  EXPECT_EQ(tyre.force(0.1, 0.1, 0, 1.0).longitudinal, 0.0);
}

TEST(Tyre, LongitudinalForceIsForcesLongitudinalHalfExactly) {
  TyreModel tyre{TyreParams{}};
  for (double load : {0.0, 2500.0, 6000.0}) {
    for (double k = -1; k <= 1; k += 0.1) {
      for (double a = -0.4; a <= 0.4; a += 0.05) {
        EXPECT_EQ(tyre.longitudinalForce(k, a, load, 1.05), tyre.force(k, a, load, 1.05).longitudinal)
            << "slip " << k << ", angle " << a << ", load " << load;
      }
    }
  }
}

// CarSimEd's tyre (CARLA 0.9's, through PhysX): linear at small slip with the stiffnesses CARLA names,
// saturating at mu Fz where K reaches 3 and never falling past it, and combined slip inside the circle.
TEST(Tyre, CarSimEdIsLinearThenSaturatesAtFrictionWithoutFallingOff) {
  roar::vehicle::TyreParams p;
  p.curve = roar::vehicle::TyreCurve::kCarSimEd;
  p.nominal_load = 4500;
  p.grip = 3.0;
  p.load_sensitivity = 0.0;
  p.lateral_stiffness = 17.0;  // CARLA's WheelPhysicsControl defaults
  p.lateral_stiffness_max_load = 2.0;
  p.longitudinal_stiffness = 1000.0;
  const roar::sim::TyreModel tyre(p);
  const double load = 4500, cy = 4500 * 17.0 * (1.5 - 0.75 + 0.125);  // CarSimEd's curve at 3 * 1 / 2
  EXPECT_NEAR(-tyre.force(0.0, 0.001, load, 1.0).lateral / 0.001, cy, 0.01 * cy) << "cornering stiffness";
  EXPECT_NEAR(tyre.force(1e-4, 0.0, load, 1.0).longitudinal / 1e-4, 1000 * 9.81, 10.0) << "slip stiffness";
  const double friction = 3.0 * load;
  EXPECT_NEAR(-tyre.force(0.0, tyre.peakSlipAngle(), load, 1.0).lateral, friction, 1e-6 * friction);
  EXPECT_NEAR(-tyre.force(0.0, 1.2, load, 1.0).lateral, friction, 1e-6 * friction) << "no fall-off past the peak";
  EXPECT_NEAR(tyre.force(tyre.peakSlipRatio(), 0.0, load, 1.0).longitudinal, friction, 1e-6 * friction);
  for (double kappa : {-0.5, -0.1, 0.05, 0.3, 2.0}) {
    for (double alpha : {-0.6, -0.1, 0.0, 0.2, 0.9}) {
      const auto f = tyre.force(kappa, alpha, load, 0.8);
      EXPECT_LE(std::hypot(f.longitudinal, f.lateral), 0.8 * friction * (1 + 1e-9)) << kappa << " " << alpha;
      EXPECT_DOUBLE_EQ(f.longitudinal, tyre.longitudinalForce(kappa, alpha, load, 0.8));
      if (alpha != 0) EXPECT_LT(f.lateral * alpha, 0) << "opposes the slip angle";
    }
  }
}

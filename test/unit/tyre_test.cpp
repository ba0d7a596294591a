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

#include "roar/vehicle/slipstream.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.h"

using namespace roar;
using vehicle::SlipstreamOptions;
using vehicle::slipstreamReduction;
using vehicle::WakeCar;

TEST(Slipstream, TheTowFallsOffWithGapAndOffset) {
  const SlipstreamOptions o;
  const double nose_to_tail = slipstreamReduction(0.0, 0.0, 40.0, 1.85, o);
  EXPECT_NEAR(nose_to_tail, o.max_reduction, 1e-12);
  double last = nose_to_tail;
  for (double gap : {2.0, 5.0, 10.0, 20.0, 35.0}) {
    const double r = slipstreamReduction(gap, 0.0, 40.0, 1.85, o);
    EXPECT_LT(r, last) << "gap " << gap;
    EXPECT_GT(r, 0.0) << "gap " << gap;
    last = r;
  }
  EXPECT_NEAR(slipstreamReduction(o.decay_length, 0.0, 40.0, 1.85, o), o.max_reduction / std::exp(1.0), 1e-12);
  EXPECT_EQ(slipstreamReduction(o.max_gap + 1.0, 0.0, 40.0, 1.85, o), 0.0) << "too far back";
  EXPECT_EQ(slipstreamReduction(-1.0, 0.0, 40.0, 1.85, o), 0.0) << "beside or ahead: no tow";
  EXPECT_EQ(slipstreamReduction(5.0, 0.0, o.min_speed - 1.0, 1.85, o), 0.0) << "a slow car leaves no wake";
  // Pulled out by a car's width and air, a pass leaves most of the tow behind.
  const double behind = slipstreamReduction(7.0, 0.0, 40.0, 1.85, o);
  EXPECT_LT(slipstreamReduction(7.0, 1.0, 40.0, 1.85, o), behind);
  EXPECT_LT(slipstreamReduction(7.0, 3.0, 40.0, 1.85, o), 0.1 * behind);
  EXPECT_EQ(slipstreamReduction(7.0, 3.0, 40.0, 1.85, o), slipstreamReduction(7.0, -3.0, 40.0, 1.85, o));
  EXPECT_EQ(slipstreamReduction(5.0, NAN, 40.0, 1.85, o), 0.0);
  EXPECT_EQ(slipstreamReduction(NAN, 0.0, 40.0, 1.85, o), 0.0);
  SlipstreamOptions off = o;
  off.enabled = false;
  EXPECT_EQ(slipstreamReduction(0.0, 0.0, 40.0, 1.85, off), 0.0);
}

TEST(Slipstream, OnlyTheCarBehindIsTowedAndTheStrongestWakeCounts) {
  const SlipstreamOptions o;
  // Three cars heading east in a line, 10 m apart centre to centre, and one far to the side.
  std::vector<WakeCar> cars = {
      {{100.0, 0.0}, {40.0, 0.0}}, {{90.0, 0.0}, {40.0, 0.0}}, {{80.0, 0.0}, {40.0, 0.0}}, {{90.0, 20.0}, {40.0, 0.0}}};
  const auto share = vehicle::dragShares(cars, o);
  ASSERT_EQ(share.size(), 4u);
  EXPECT_EQ(share[0], 1.0) << "the leader is in free air";
  const double gap = 10.0 - 4.7;
  EXPECT_NEAR(share[1], 1.0 - slipstreamReduction(gap, 0.0, 40.0, 1.85, o), 1e-12);
  EXPECT_NEAR(share[2], share[1], 1e-12) << "the nearest wake, not the sum of both";
  EXPECT_EQ(share[3], 1.0) << "20 m to the side";
  // Heading west, the same line is towed the other way round.
  for (auto& c : cars) c.velocity = -c.velocity;
  const auto west = vehicle::dragShares(cars, o);
  EXPECT_LT(west[0], 1.0);
  EXPECT_EQ(west[2], 1.0);
}

TEST(Slipstream, OptionsOutOfRangeAreRefusedByName) {
  SlipstreamOptions o;
  EXPECT_NO_THROW(vehicle::validate(o, "slipstream: "));
  o.max_reduction = 1.0;
  EXPECT_NE(test::errorOf([&] { vehicle::validate(o, "slipstream: "); }).find("slipstream: max_reduction"),
            std::string::npos);
  o = {};
  o.decay_length = NAN;
  EXPECT_NE(test::errorOf([&] { vehicle::validate(o, "x: "); }).find("x: decay_length"), std::string::npos);
}

// Telling a car held to a speed (a pace car, a scripted car) from one driven at a share of the line's.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "roar/planning/held_speed.h"

using roar::planning::HeldSpeed;

namespace {
// A line out of a corner: 15 m/s rising to 40 over 5 s, 40 for 5 s, back down to 15 over 3 s, at 20 Hz.
double lineSpeed(double t) {
  if (t < 5.0) return 15.0 + 5.0 * t;
  if (t < 10.0) return 40.0;
  return std::max(15.0, 40.0 - (t - 10.0) * 25.0 / 3.0);
}
}  // namespace

TEST(HeldSpeed, ACarKeptAtOneSpeedWhileTheLineSpeedsUpIsHeld) {
  HeldSpeed held;
  for (double t = 0.0; t < 13.0; t += 0.05) held.observe(std::min(14.0, lineSpeed(t)), lineSpeed(t), t);
  EXPECT_DOUBLE_EQ(held.speed(), 14.0);
}

TEST(HeldSpeed, ACarAtAShareOfTheLineIsNotHeldEvenAtItsTopSpeed) {
  // At 75% of the line: it gains speed with the line, then holds 30 m/s on the straight and into the
  // braking zone, where the line's speed falls (not rises) under it.
  HeldSpeed held;
  for (double t = 0.0; t < 13.0; t += 0.05) held.observe(0.75 * lineSpeed(t), lineSpeed(t), t);
  EXPECT_EQ(held.speed(), 0.0);
}

TEST(HeldSpeed, ACarSeenFasterThanItWasHeldIsHeldNoLonger) {
  // Held up behind a slower car, then free: it was not its driver that held it.
  HeldSpeed held;
  double t = 0.0;
  for (; t < 5.0; t += 0.05) held.observe(std::min(16.0, lineSpeed(t)), lineSpeed(t), t);
  ASSERT_DOUBLE_EQ(held.speed(), 16.0);
  held.observe(17.5, lineSpeed(t), t);
  EXPECT_EQ(held.speed(), 0.0);
}

TEST(HeldSpeed, AShortOrNonFiniteObservationHoldsNothing) {
  HeldSpeed held;
  for (double t = 0.0; t < 1.5; t += 0.05) held.observe(14.0, lineSpeed(t), t);  // 1.5 s: not long enough
  held.observe(std::numeric_limits<double>::quiet_NaN(), 30.0, 1.6);
  EXPECT_EQ(held.speed(), 0.0);
}

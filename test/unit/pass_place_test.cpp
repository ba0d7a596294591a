// Where a pass was won: on a straight, in a braking zone (on the inside of the corner braked for or the
// outside) or through a corner (harness::passPlace), on a made-up line whose every stretch is known.
#include <gtest/gtest.h>

#include <stdexcept>

#include "roar/harness/pass_place.h"

using namespace roar;
using harness::PassPlace;

namespace {

// 600 m: a straight to 200 m, braking at 6 m/s^2 to 300 m, into a left turn of 50 m radius to 400 m, where
// the line holds its speed, then a straight.
planning::Trajectory straightBrakingLeftTurnStraight() {
  planning::Trajectory line;
  line.closed = false;
  for (int k = 0; k <= 600; ++k) {
    planning::TrajectoryPoint p;
    p.s = k;
    p.speed = 30.0;
    p.acceleration = (k >= 200 && k < 300) ? -6.0 : 0.0;
    p.curvature = (k >= 300 && k < 400) ? 0.02 : 0.0;
    line.points.push_back(p);
  }
  line.length = 600.0;
  return line;
}

}  // namespace

TEST(PassPlace, EachStretchOfTheLineIsToldApartAndTheInsideIsTheCornersInside) {
  const auto line = straightBrakingLeftTurnStraight();
  EXPECT_EQ(harness::passPlace(line, 100.0, +1).place, PassPlace::kStraight);
  EXPECT_FALSE(harness::passPlace(line, 100.0, +1).inside);
  EXPECT_EQ(harness::passPlace(line, 500.0, -1).place, PassPlace::kStraight);

  // Braking for a left turn: the left is the inside, though the line does not turn yet where it brakes.
  const auto braking_left = harness::passPlace(line, 250.0, +1);
  EXPECT_EQ(braking_left.place, PassPlace::kBrakingZone);
  EXPECT_TRUE(braking_left.inside);
  const auto braking_right = harness::passPlace(line, 250.0, -1);
  EXPECT_EQ(braking_right.place, PassPlace::kBrakingZone);
  EXPECT_FALSE(braking_right.inside);

  const auto corner_right = harness::passPlace(line, 350.0, -1);
  EXPECT_EQ(corner_right.place, PassPlace::kCorner);
  EXPECT_FALSE(corner_right.inside);
  EXPECT_TRUE(harness::passPlace(line, 350.0, +1).inside);
}

TEST(PassPlace, ACornerIsATurnTighterThanTheCornerRadius) {
  auto line = straightBrakingLeftTurnStraight();
  for (auto& p : line.points) p.curvature = p.curvature != 0.0 ? -1.0 / 200.0 : 0.0;  // a gentle right
  EXPECT_EQ(harness::passPlace(line, 350.0, -1).place, PassPlace::kStraight);
  harness::PassPlaceOptions wide;
  wide.corner_radius = 250.0;
  const auto where = harness::passPlace(line, 350.0, -1, wide);
  EXPECT_EQ(where.place, PassPlace::kCorner);
  EXPECT_TRUE(where.inside);
}

TEST(PassPlace, RefusesASideThatIsNeitherLeftNorRight) {
  const auto line = straightBrakingLeftTurnStraight();
  EXPECT_THROW(harness::passPlace(line, 100.0, 0), std::invalid_argument);
  EXPECT_THROW(harness::passPlace(line, 100.0, 2), std::invalid_argument);
}

TEST(PassPlace, DescribesEachPlace) {
  EXPECT_EQ(harness::describe(PassPlace::kStraight), "straight");
  EXPECT_EQ(harness::describe(PassPlace::kBrakingZone), "braking zone");
  EXPECT_EQ(harness::describe(PassPlace::kCorner), "corner");
}

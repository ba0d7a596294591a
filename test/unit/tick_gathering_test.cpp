// Which cars' odometry the planner node plans a tick from (lockstep::TickGathering): every car's window
// of a tick from every car's place at that tick, and no car missing from the world ever stalls the rest.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "roar/lockstep/tick_gathering.h"

using roar::lockstep::TickGathering;

namespace {

std::vector<std::string> carsOf(const std::vector<TickGathering::Tick>& ticks, std::size_t k = 0) {
  return ticks.size() > k ? ticks[k].cars : std::vector<std::string>{};
}

}  // namespace

TEST(TickGathering, ATickIsPlannedOnceEveryCarHasComeInTheRacesOrder) {
  TickGathering ticks({"a", "b", "c"}, 0.25);
  EXPECT_TRUE(ticks.arrive("c", 0.05, 10.0).empty());
  EXPECT_TRUE(ticks.arrive("a", 0.05, 10.001).empty());
  const auto planned = ticks.arrive("b", 0.05, 10.002);
  ASSERT_EQ(planned.size(), 1u);
  EXPECT_DOUBLE_EQ(planned[0].stamp, 0.05);
  EXPECT_EQ(planned[0].cars, (std::vector<std::string>{"a", "b", "c"})) << "the race's order, not the messages'";
  EXPECT_LT(ticks.expiresAt(), 0.0) << "nothing left gathering";
}

TEST(TickGathering, ACarThatMissedATickIsNotWaitedForUntilItComesBack) {
  TickGathering ticks({"a", "b"}, 0.25);
  ticks.arrive("a", 0.05, 10.0);
  ticks.arrive("b", 0.05, 10.0);
  // b's odometry of 0.10 never comes: a's of 0.15 begins a later tick, and 0.10 is planned without b.
  EXPECT_TRUE(ticks.arrive("a", 0.10, 10.01).empty());
  auto planned = ticks.arrive("a", 0.15, 10.02);
  ASSERT_EQ(planned.size(), 2u) << "0.10 as it was, and 0.15: b is not waited for now";
  EXPECT_DOUBLE_EQ(planned[0].stamp, 0.10);
  EXPECT_EQ(planned[0].cars, std::vector<std::string>{"a"});
  EXPECT_DOUBLE_EQ(planned[1].stamp, 0.15);
  EXPECT_EQ(carsOf(planned, 1), std::vector<std::string>{"a"});
  // b back: its tick is planned with it, and the next waits for it again.
  EXPECT_TRUE(ticks.arrive("b", 0.20, 10.03).empty()) << "a is expected too";
  EXPECT_EQ(carsOf(ticks.arrive("a", 0.20, 10.03)), (std::vector<std::string>{"a", "b"}));
  EXPECT_TRUE(ticks.arrive("a", 0.25, 10.04).empty()) << "b is waited for again";
}

TEST(TickGathering, ATickWaitsAtMostItsWaitOfWallTime) {
  TickGathering ticks({"a", "b"}, 0.25);
  EXPECT_TRUE(ticks.arrive("a", 0.05, 10.0).empty());  // b, never seen yet, is waited for
  EXPECT_DOUBLE_EQ(ticks.expiresAt(), 10.25);
  EXPECT_TRUE(ticks.expire(10.2).empty());
  EXPECT_EQ(carsOf(ticks.expire(10.25)), std::vector<std::string>{"a"});
  EXPECT_TRUE(ticks.expire(20.0).empty()) << "planned once";
  EXPECT_EQ(carsOf(ticks.arrive("a", 0.10, 10.3)), std::vector<std::string>{"a"}) << "b, missing, not waited for";
}

TEST(TickGathering, LateRepeatedAndStrangeOdometryStallsNothing) {
  TickGathering ticks({"a", "b"}, 0.25);
  ticks.arrive("a", 0.10, 10.0);
  // Older than the tick gathered: planned at once, alone; the tick goes on gathering.
  const auto late = ticks.arrive("b", 0.05, 10.0);
  ASSERT_EQ(late.size(), 1u);
  EXPECT_DOUBLE_EQ(late[0].stamp, 0.05);
  EXPECT_EQ(late[0].cars, std::vector<std::string>{"b"});
  EXPECT_TRUE(ticks.arrive("nobody", 0.10, 10.0).empty()) << "not a car of the race";
  // a's odometry of 0.10 again (the planner answering it afresh with a new racing line): 0.10 as it was,
  // b missing from it, then the repeat, b not waited for.
  const auto again = ticks.arrive("a", 0.10, 10.01);
  ASSERT_EQ(again.size(), 2u);
  EXPECT_EQ(again[0].cars, std::vector<std::string>{"a"});
  EXPECT_EQ(again[1].cars, std::vector<std::string>{"a"});
  EXPECT_LT(ticks.expiresAt(), 0.0);
}

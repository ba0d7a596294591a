// The drivers a lockstep tick waits for (lockstep::DriverRoll): connected, not lost, not yet answered.
#include "roar/lockstep/driver_roll.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

using roar::lockstep::DriverRoll;

namespace {

struct Roll {
  std::set<std::string> connected;
  DriverRoll roll{[this](const std::string& car) { return connected.count(car) > 0; }};
};

}  // namespace

TEST(DriverRoll, ATickWaitsForEveryConnectedDriverToAnswerIt) {
  Roll r;
  r.roll.add("a");
  r.roll.add("b");
  r.roll.add("parked");  // nobody drives it: never waited for
  r.connected = {"a", "b"};
  EXPECT_FALSE(r.roll.answered(0.0)) << "no control yet";
  r.roll.control("a", 0.0);
  EXPECT_FALSE(r.roll.answered(0.0));
  EXPECT_EQ(r.roll.silent(0.0), std::vector<std::string>{"b"});
  r.roll.control("b", 0.0);
  EXPECT_TRUE(r.roll.answered(0.0));
  EXPECT_FALSE(r.roll.answered(0.05)) << "the next tick waits again";
  r.roll.control("a", 0.05);
  r.roll.control("b", 0.1);  // a control ahead of the tick answers it too
  EXPECT_TRUE(r.roll.answered(0.05));
}

TEST(DriverRoll, ALostDriverIsNotWaitedForUntilItAnswersAgain) {
  Roll r;
  r.roll.add("a");
  r.roll.add("b");
  r.connected = {"a", "b"};
  r.roll.control("a", 0.0);
  for (const auto& car : r.roll.silent(0.0)) r.roll.lose(car);
  EXPECT_TRUE(r.roll.lost("b"));
  EXPECT_TRUE(r.roll.answered(0.0));
  EXPECT_FALSE(r.roll.everyDriverLost()) << "a still drives";
  EXPECT_TRUE(r.roll.control("b", 0.05)) << "back";
  EXPECT_FALSE(r.roll.lost("b"));
  EXPECT_FALSE(r.roll.control("b", 0.1)) << "back once";
  EXPECT_FALSE(r.roll.answered(0.15));
}

TEST(DriverRoll, ADriverWhosePublisherIsGoneIsLostAtOnceAndOnlyOnce) {
  Roll r;
  r.roll.add("a");
  r.roll.add("never");
  r.connected = {"a"};
  r.roll.control("a", 0.0);
  EXPECT_TRUE(r.roll.disconnected().empty());
  r.connected.clear();
  EXPECT_EQ(r.roll.disconnected(), std::vector<std::string>{"a"}) << "a drove and its publisher went";
  r.roll.lose("a");
  EXPECT_TRUE(r.roll.disconnected().empty());
  EXPECT_TRUE(r.roll.everyDriverLost());
  r.roll.remove("a");
  EXPECT_FALSE(r.roll.everyDriverLost()) << "nobody is lost: nobody drove";
  EXPECT_TRUE(r.roll.answered(1.0));
}

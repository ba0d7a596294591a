// The controller's pairing of odometry ticks with trajectory windows: tick t is answered with the window
// of tick t while the planner answers odometry, never held for a planner that does not, held until the
// first window, and never longer than window_wait.
#include <gtest/gtest.h>

#include "roar/lockstep/window_pairing.h"

using roar::lockstep::WindowPairing;

namespace {

// A pairing whose planner answered tick `t0`, then missed its wait for the next tick: given up on.
WindowPairing givenUpAfter(double t0) {
  WindowPairing p(1.0);
  p.onOdometry(t0, 0.0);
  p.onWindow(t0);
  p.answered();
  EXPECT_FALSE(p.onOdometry(t0 + 0.05, 10.0));
  EXPECT_TRUE(p.waitedTooLong(11.0));
  p.answeredLate();
  return p;
}

}  // namespace

TEST(WindowPairing, OdometryIsHeldUntilTheFirstWindow) {
  WindowPairing p(1.0);
  EXPECT_FALSE(p.onOdometry(0.0, 10.0)) << "no window yet";
  EXPECT_FALSE(p.onOdometry(0.05, 10.1)) << "still none: the newer tick is held instead";
  EXPECT_DOUBLE_EQ(p.heldStamp(), 0.05);
  EXPECT_FALSE(p.waitedTooLong(20.0)) << "without a window there is nothing to answer with";
  EXPECT_TRUE(p.onWindow(0.0)) << "the first window answers the held tick";
  p.answered();
  EXPECT_FALSE(p.holding());
}

TEST(WindowPairing, WhileThePlannerAnswersOdometryATickWaitsForItsOwnWindow) {
  WindowPairing p(1.0);
  p.onOdometry(0.0, 0.0);
  p.onWindow(0.0);  // stamped with the odometry's time: the planner answers odometry
  p.answered();
  EXPECT_TRUE(p.plannerAnswersOdometry());
  EXPECT_FALSE(p.onOdometry(0.05, 0.01)) << "the window of t = 0.05 is not here yet";
  EXPECT_FALSE(p.onWindow(0.0)) << "a late window of the tick before does not answer it";
  EXPECT_TRUE(p.onWindow(0.05)) << "its own window does";
  p.answered();
  EXPECT_TRUE(p.onOdometry(0.05, 0.02)) << "odometry again for a tick whose window is here: answered at once";
}

TEST(WindowPairing, AWindowThatComesBeforeItsOdometryShowsAPlannerThatAnswersOdometry) {
  // The planner's answer can be quicker than the odometry's way to the controller (a loaded machine).
  WindowPairing p(1.0);
  EXPECT_FALSE(p.onWindow(0.05)) << "nothing held to answer";
  EXPECT_TRUE(p.onOdometry(0.05, 0.0)) << "its window is here";
  p.answered();
  EXPECT_TRUE(p.plannerAnswersOdometry());
  EXPECT_FALSE(p.onOdometry(0.10, 0.01)) << "the next tick waits for its own window, not the one here";
  EXPECT_TRUE(p.onWindow(0.10));
}

TEST(WindowPairing, ATickWaitsNoLongerThanWindowWait) {
  WindowPairing p(0.5);
  p.onOdometry(0.0, 0.0);
  p.onWindow(0.0);
  p.answered();
  EXPECT_FALSE(p.onOdometry(0.05, 100.0));
  EXPECT_FALSE(p.waitedTooLong(100.4));
  EXPECT_TRUE(p.waitedTooLong(100.5)) << "answered with the latest window after 0.5 s";
}

TEST(WindowPairing, APlannerWithUnstampedWindowsIsNotWaitedFor) {
  WindowPairing p(1.0);
  p.onOdometry(1.0, 0.0);
  p.onWindow(0.0);  // unstamped, on a running clock
  p.answered();
  EXPECT_FALSE(p.plannerAnswersOdometry());
  EXPECT_TRUE(p.onOdometry(1.05, 0.1));
  EXPECT_TRUE(p.onOdometry(1.10, 0.2));
  // And with window_wait 0 nothing is ever held once there is a window.
  WindowPairing never(0.0);
  never.onOdometry(0.0, 0.0);
  never.onWindow(0.0);
  never.answered();
  EXPECT_TRUE(never.onOdometry(0.05, 0.0));
}

TEST(WindowPairing, AWindowLaggingBehindTheNewestOdometrySaysNothingNew) {
  WindowPairing p(1.0);
  p.onOdometry(0.0, 0.0);
  p.onWindow(0.0);
  p.answered();
  EXPECT_TRUE(p.plannerAnswersOdometry());
  EXPECT_FALSE(p.onOdometry(0.10, 0.0));
  p.onWindow(0.05);  // older than the newest odometry: still a planner that answers odometry
  EXPECT_TRUE(p.plannerAnswersOdometry());
  EXPECT_TRUE(p.holding()) << "t = 0.10 still waits for its window";
}

TEST(WindowPairing, APlannerThatMissedItsWaitIsNotWaitedForUntilItAnswersAgain) {
  WindowPairing p = givenUpAfter(0.0);
  EXPECT_FALSE(p.plannerAnswersOdometry());
  EXPECT_TRUE(p.onOdometry(0.10, 11.0)) << "the next tick is answered at once: a dead planner costs one wait";
  EXPECT_TRUE(p.onOdometry(0.15, 11.1));
  p.onWindow(0.15);  // the planner (restarted) answers a tick again
  EXPECT_TRUE(p.plannerAnswersOdometry());
  EXPECT_FALSE(p.onOdometry(0.20, 11.2)) << "and is waited for again";
}

TEST(WindowPairing, ARestartedPlannerLaggingBehindIsWaitedForAgain) {
  WindowPairing p = givenUpAfter(0.0);
  for (int k = 2; k <= 40; ++k) EXPECT_TRUE(p.onOdometry(0.05 * k, 11.0 + 0.01 * k));
  p.onWindow(1.5);  // the restarted planner's first window, planned from odometry 0.5 s old
  EXPECT_TRUE(p.plannerAnswersOdometry());
  EXPECT_FALSE(p.onOdometry(2.05, 11.5)) << "the next tick waits: the simulator stops while the planner catches up";
  EXPECT_FALSE(p.onWindow(1.6)) << "a window of an older tick does not answer it";
  EXPECT_TRUE(p.onWindow(2.05));
  p.answered();
  // A window arriving late from the planner before it was given up is no news: it is not waited for.
  WindowPairing dying = givenUpAfter(10.0);
  dying.onWindow(10.0);
  EXPECT_FALSE(dying.plannerAnswersOdometry());
  EXPECT_TRUE(dying.onOdometry(10.1, 11.0));
}

TEST(WindowPairing, AWindowOlderThanTheOdometryByMoreThanItsLimitIsStale) {
  WindowPairing p(1.0);
  EXPECT_FALSE(p.windowStale(100.0, 2.0)) << "no window: nothing to be stale";
  p.onOdometry(10.0, 0.0);
  p.onWindow(10.0);
  EXPECT_FALSE(p.windowStale(12.0, 2.0));
  EXPECT_TRUE(p.windowStale(12.05, 2.0));
  p.onWindow(0.0);
  EXPECT_FALSE(p.windowStale(100.0, 2.0)) << "an unstamped window says nothing of its age";
}

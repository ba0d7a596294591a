// roar_sim runs no more than kRecorderMaxLag ticks ahead of a recorder, gives up on one that is silent
// for the timeout (and only it), and waits for it again once it reports.
#include <gtest/gtest.h>

#include "roar/lockstep/recorder_pacing.h"

using roar::lockstep::kRecorderMaxLag;
using roar::lockstep::RecorderPacing;

TEST(RecorderPacing, TicksGoOutOnlyWhileEveryRecorderIsWithinTheLag) {
  const double dt = 0.05;
  RecorderPacing pacing({"/recorder", "/other"}, dt, 5.0);
  std::vector<std::string> given_up;
  // Nothing recorded yet: the first kRecorderMaxLag ticks may go out, the next may not.
  for (int tick = 1; tick <= kRecorderMaxLag; ++tick)
    EXPECT_EQ(pacing.waitingFor(tick * dt, 0.0, &given_up), "") << tick;
  EXPECT_EQ(pacing.waitingFor((kRecorderMaxLag + 1) * dt, 0.0, &given_up), "/recorder");
  pacing.recorded("/recorder", 0.0, 0.1);
  EXPECT_EQ(pacing.waitingFor((kRecorderMaxLag + 1) * dt, 0.1, &given_up), "/recorder") << "tick 1 not yet written";
  pacing.recorded("/recorder", 1 * dt, 0.1);
  EXPECT_EQ(pacing.waitingFor((kRecorderMaxLag + 1) * dt, 0.1, &given_up), "/other") << "every recorder";
  pacing.recorded("/other", 1 * dt, 0.1);
  EXPECT_EQ(pacing.waitingFor((kRecorderMaxLag + 1) * dt, 0.1, &given_up), "");
  EXPECT_EQ(pacing.waitingFor((kRecorderMaxLag + 2) * dt, 0.1, &given_up), "/recorder");
  // Reports of an older clock do not move it back.
  pacing.recorded("/recorder", 3 * dt, 0.2);
  pacing.recorded("/recorder", 2 * dt, 0.2);
  EXPECT_DOUBLE_EQ(pacing.lastRecorded("/recorder"), 3 * dt);
  EXPECT_TRUE(given_up.empty());
}

TEST(RecorderPacing, ASilentRecorderIsGivenUpAfterTheTimeoutAndWaitedForOnceBack) {
  const double dt = 0.05;
  RecorderPacing pacing({"/recorder", "/live"}, dt, 5.0);
  pacing.recorded("/recorder", 1.0, 10.0);
  pacing.recorded("/live", 1.0, 10.0);
  const double next = 1.0 + (kRecorderMaxLag + 1) * dt;
  std::vector<std::string> given_up;
  EXPECT_EQ(pacing.waitingFor(next, 14.0, &given_up), "/recorder") << "4 s silent: still waited for";
  EXPECT_TRUE(given_up.empty());
  pacing.recorded("/live", 2.0, 15.0);
  EXPECT_EQ(pacing.waitingFor(next, 15.5, &given_up), "") << "5.5 s silent: given up";
  ASSERT_EQ(given_up, std::vector<std::string>{"/recorder"});
  EXPECT_TRUE(pacing.givenUp("/recorder"));
  EXPECT_FALSE(pacing.givenUp("/live"));
  EXPECT_EQ(pacing.waitingFor(next + 0.5, 16.0, &given_up), "") << "not waited for while given up";
  EXPECT_EQ(given_up.size(), 1u) << "given up once";
  EXPECT_TRUE(pacing.recorded("/recorder", 1.5, 20.0)) << "back";
  EXPECT_EQ(pacing.waitingFor(2.5, 20.0, &given_up), "/recorder") << "waited for again";
  // A recorder whose node went is given up at once.
  pacing.gone("/live");
  EXPECT_TRUE(pacing.givenUp("/live"));
  EXPECT_FALSE(pacing.recorded("/unknown", 1.0, 20.0)) << "a report from a recorder not waited for is ignored";
}

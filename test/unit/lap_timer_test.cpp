#include <gtest/gtest.h>

#include "roar/race/lap_timer.h"
#include "test_support.h"

using namespace roar;

TEST(LapTimer, TimesLapsFromTheFirstCrossing) {
  const auto track = test::circleTrack(100.0);  // start/finish at s = 0, 3 sectors
  race::LapTimer timer(track);
  const double speed = 20.0, dt = 0.05, length = track.length();
  std::vector<race::LapRecord> laps;
  // Start 30 m behind the line, drive 3.2 laps.
  for (double t = 0; t < (3.2 * length + 30) / speed; t += dt) {
    if (auto lap = timer.update(t, test::onCircleTrack(-30 + speed * t))) laps.push_back(*lap);
  }
  ASSERT_EQ(laps.size(), 3u);
  for (const auto& lap : laps) {
    EXPECT_NEAR(lap.lap_time, length / speed, 0.05);
    ASSERT_EQ(lap.sector_times.size(), 3u);
    EXPECT_NEAR(lap.sector_times[0] + lap.sector_times[1] + lap.sector_times[2], lap.lap_time, 1e-9);
    for (double s : lap.sector_times) EXPECT_NEAR(s, length / 3 / speed, 0.05);
  }
  EXPECT_NEAR(laps[0].finish_time, (30 + length) / speed, 0.05) << "crossing time interpolated between samples";
  EXPECT_EQ(timer.lapsCompleted(), 3);
  EXPECT_NEAR(*timer.bestLap(), length / speed, 0.05);
}

TEST(LapTimer, WobblingOverTheLineCountsNoLap) {
  const auto track = test::circleTrack(100.0);
  race::LapTimer timer(track);
  int laps = 0;
  double t = 0;
  for (int k = 0; k < 200; ++k, t += 0.05) {
    const double s = 5.0 * std::sin(k * 0.3);  // back and forth across the start/finish line
    if (timer.update(t, test::onCircleTrack(s))) ++laps;
  }
  EXPECT_EQ(laps, 0);
  EXPECT_TRUE(timer.started());
}

TEST(LapTimer, ReversingRoundTheLoopCountsNoLap) {
  const auto track = test::circleTrack(100.0);
  race::LapTimer timer(track);
  int laps = 0;
  for (double t = 0; t < 100; t += 0.05) {
    if (timer.update(t, test::onCircleTrack(30 - 20 * t))) ++laps;  // driving the wrong way
  }
  EXPECT_EQ(laps, 0);
}

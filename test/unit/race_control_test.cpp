#include "roar/race/race_control.h"
#include "roar/report/race_report.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "test_support.h"

using namespace roar;
namespace fs = std::filesystem;

namespace {

// On the 100 m circle track (centre line radius 100, 12 m wide), at arc length s and `lateral` to the left.
Eigen::Vector3d atCircle(double s, double lateral = 0.0) { return test::onCircleTrack(s, 100.0, lateral); }
Eigen::Vector2d onCircle(double s, double lateral = 0.0) { return atCircle(s, lateral).head<2>(); }

int lines(const std::string& path) {
  std::ifstream in(path);
  int n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

}  // namespace

TEST(RaceControl, ContactsArePenalisedOncePerIncident) {
  const auto track = test::circleTrack(100.0);
  race::RaceControl race(track, {}, {"ego"});
  race.updatePosition("ego", 0.0, atCircle(-20));
  auto first = race.updateContact("ego", 1.0, "barrier");
  ASSERT_TRUE(first);
  EXPECT_EQ(first->kind, "barrier");
  EXPECT_EQ(first->penalty, 5.0);
  EXPECT_FALSE(race.updateContact("ego", 1.05, "barrier")) << "the same scrape, a tick later";
  EXPECT_FALSE(race.updateContact("ego", 1.4, "ground"));
  auto second = race.updateContact("ego", 3.0, "rival");
  ASSERT_TRUE(second);
  EXPECT_EQ(second->kind, "car rival");
  EXPECT_EQ(race.car("ego").barrier_contacts, 1);
  EXPECT_EQ(race.car("ego").car_contacts, 1);
  EXPECT_EQ(race.car("ego").penalties, 10.0);
}

TEST(RaceControl, BetweenCarsOnlyTheCarAtFaultIsPenalised) {
  // Counter-clockwise on a circle of 100 m: at (100, 0) the road heads +y.
  const auto track = test::circleTrack(100.0);
  race::RaceControl race(track, {}, {"front", "rear", "a", "b"});
  const double up = M_PI / 2;
  race.updateMotion("front", {100.0, 5.0}, up, {0.0, 20.0});
  race.updateMotion("rear", {100.2, 0.5}, up, {0.0, 25.0});
  const auto rear = race.updateContact("rear", 2.0, "front");
  const auto front = race.updateContact("front", 2.0, "rear");
  ASSERT_TRUE(rear && front);
  EXPECT_EQ(rear->at_fault, "rear");
  EXPECT_EQ(rear->contact, "from behind");
  EXPECT_EQ(rear->penalty, 5.0);
  EXPECT_EQ(front->at_fault, "rear");
  EXPECT_EQ(front->penalty, 0.0) << "run into from behind: no penalty";
  // Alongside, both holding their lines: a racing incident, nobody pays.
  race.updateMotion("a", {98.0, 0.0}, up, {0.0, 20.0});
  race.updateMotion("b", {100.0, 0.5}, up, {0.0, 20.0});
  const auto a = race.updateContact("a", 4.0, "b");
  ASSERT_TRUE(a);
  EXPECT_EQ(a->contact, "alongside");
  EXPECT_EQ(a->at_fault, "");
  EXPECT_EQ(a->penalty, 0.0);
  const std::string dir = (std::filesystem::temp_directory_path() / "roar_fault_results").string();
  race::writeResults(dir, race, race::RaceOutcome::kTimedOut);
  std::ifstream in(dir + "/results.yaml");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("contact: \"from behind\", at_fault: \"rear\""), std::string::npos) << text;
}

TEST(RaceControl, ARetiredCarIsNotWaitedForAndClassifiedLast) {
  const auto track = test::circleTrack(100.0);
  race::RaceRules rules;
  rules.laps = 1;
  race::RaceControl race(track, rules, {"runner", "dead"});
  double t = 0.0;
  for (; t < 10.0; t += 0.05) {
    race.updatePosition("runner", t, atCircle(-5 + 20.0 * t));
    race.updatePosition("dead", t, atCircle(-10 + 30.0 * t));  // ahead when its driver dies
  }
  race.retire("dead", t, "driver lost");
  EXPECT_FALSE(race.finished()) << "the runner is still racing";
  for (; !race.finished() && t < 60.0; t += 0.05) race.updatePosition("runner", t, atCircle(-5 + 20.0 * t));
  ASSERT_TRUE(race.finished()) << "every car finished or retired";
  EXPECT_EQ(race.standings().front().name, "runner");
  EXPECT_EQ(race.car("dead").retired, "driver lost");
  race.retire("runner", t, "too late");
  EXPECT_EQ(race.car("runner").retired, "") << "a finished car cannot retire";
  const std::string dir = (std::filesystem::temp_directory_path() / "roar_retired_results").string();
  race::writeResults(dir, race, race::RaceOutcome::kFinished);
  std::ifstream in(dir + "/results.yaml");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("retired: \"driver lost\""), std::string::npos) << text;
  EXPECT_EQ(race::outcomeName(race::RaceOutcome::kAborted), std::string("aborted"));
}

TEST(RaceControl, TimeInTrafficAndTheLapTimeItCost) {
  // The 628 m circle: `runner` laps at 20 m/s; on its second lap it catches `blocker` (15 m/s, started
  // 200 m ahead), is held 10 m behind it for 10 s, then goes by.
  const auto track = test::circleTrack(100.0);
  race::RaceRules rules;
  rules.laps = 4;
  race::RaceControl race(track, rules, {"runner", "blocker"});
  const double dt = 0.05;
  double runner = -5.0, blocker = 195.0, held = 0.0;
  for (double t = 0.0; t < 200.0 && !race.finished(); t += dt) {
    const double gap = blocker - runner;
    const bool behind = gap > 0.0 && gap <= 10.0 && held < 10.0;
    held += behind ? dt : 0.0;
    runner += (behind ? 15.0 : 20.0) * dt;
    blocker += 15.0 * dt;
    race.updatePosition("runner", t, atCircle(runner));
    race.updatePosition("blocker", t, atCircle(blocker));
  }
  ASSERT_TRUE(race.finished());
  const auto& r = race.car("runner");
  ASSERT_EQ(r.lap_traffic.size(), 4u);
  EXPECT_EQ(r.lap_traffic[0], 0.0);
  EXPECT_GT(r.lap_traffic[1], 10.0) << "held 10 s, and closing in before";
  EXPECT_EQ(r.lap_traffic[2], 0.0);
  EXPECT_EQ(r.lap_traffic[3], 0.0);
  // Closing from a car and a second (24.7 m) to 10 m at 5 m/s, 10 s held, then 10 m to alongside at
  // 5 m/s: about 15 s.
  EXPECT_NEAR(r.time_in_traffic, 14.9, 0.3);
  // 10 s at 15 instead of 20 m/s: 50 m, 2.5 s at 20 m/s.
  EXPECT_NEAR(race.timeLostInTraffic("runner"), 2.5, 0.1);
  EXPECT_GT(race.car("blocker").time_in_traffic, 0.0) << "the runner just ahead of it once by";
  EXPECT_NEAR(race.timeLostInTraffic("blocker"), 0.0, 0.06) << "a car ahead that pulls away costs nothing";
  race::RaceControl fresh(track, rules, {"a"});
  EXPECT_TRUE(std::isnan(fresh.timeLostInTraffic("a"))) << "no clean lap to compare with yet";
  const std::string dir = (std::filesystem::temp_directory_path() / "roar_traffic_results").string();
  race::writeResults(dir, race, race::RaceOutcome::kFinished);
  const YAML::Node results = YAML::LoadFile(dir + "/results.yaml");
  for (const auto& car : results["cars"]) {
    const auto name = car["name"].as<std::string>();
    EXPECT_NEAR(car["time_in_traffic_s"].as<double>(), race.car(name).time_in_traffic, 1e-6);
    EXPECT_NEAR(car["time_lost_in_traffic_s"].as<double>(), race.timeLostInTraffic(name), 1e-6);
  }
}

TEST(RaceControl, LeavingTheTrackIsOneViolationPerExcursion) {
  const auto track = test::circleTrack(100.0);  // 6 m either side
  race::RaceRules rules;
  rules.track_limits_penalty = 3.0;
  race::RaceControl race(track, rules, {"ego"});
  int violations = 0;
  double t = 0.0;
  // Drive along; from s = 100 m to 140 m run 8 m left of the centre line (2 m beyond the edge: all wheels
  // off), then come back; again from 300 m to 310 m.
  for (double s = 0; s < 400; s += 1.0, t += 0.05) {
    const bool off = (s >= 100 && s < 140) || (s >= 300 && s < 310);
    std::optional<race::Incident> incident;
    race.updatePosition("ego", t, atCircle(s, off ? 8.0 : 0.0), &incident);
    if (incident) {
      ++violations;
      EXPECT_EQ(incident->kind, "track limits");
    }
  }
  EXPECT_EQ(violations, 2);
  EXPECT_EQ(race.car("ego").track_limit_violations, 2);
  EXPECT_EQ(race.car("ego").penalties, 6.0);
  // Running wide with two wheels over the edge is not leaving the track.
  race::RaceControl lenient(track, rules, {"ego"});
  for (double s = 0; s < 200; s += 1.0) lenient.updatePosition("ego", s * 0.05, atCircle(s, 6.5));
  EXPECT_EQ(lenient.car("ego").track_limit_violations, 0);
}

TEST(RaceControl, RespawnRulePutsTheCarBackAtTheLastWaypoint) {
  const auto track = test::circleTrack(100.0);
  race::RaceRules rules;
  rules.collision = race::IncidentRule::kRespawn;
  race::RaceControl race(track, rules, {"ego"});
  for (double s = -20; s <= 150; s += 1.0) race.updatePosition("ego", (s + 20) * 0.05, atCircle(s, 3.0));
  const auto incident = race.updateContact("ego", 10.0, "barrier");
  ASSERT_TRUE(incident);
  EXPECT_TRUE(incident->respawn);
  EXPECT_EQ(incident->penalty, 0.0) << "the clock running is the penalty";
  EXPECT_NEAR((incident->respawn_pose.position - onCircle(150)).norm(), 0.0, 1.5)
      << "on the centre line, where the car was";
  EXPECT_NEAR(track::wrapAngle(incident->respawn_pose.heading - (1.5 + M_PI / 2)), 0.0, 0.02);
}

TEST(RaceControl, StandingsGapsFinishAndResults) {
  const auto track = test::circleTrack(100.0);
  race::RaceRules rules;
  rules.laps = 2;
  race::RaceControl race(track, rules, {"fast", "slow"});
  EXPECT_THROW(race::RaceControl(track, rules, {"a", "a"}), std::invalid_argument);
  const double length = track.length();
  // Both at 20 m/s; slow starts 2 s (40 m) behind fast.
  for (double t = 0; t < (2 * length + 100) / 20.0; t += 0.05) {
    race.updatePosition("fast", t, atCircle(-20 + 20 * t));
    race.updatePosition("slow", t, atCircle(-60 + 20 * t));
    if (t > 5 && t < 60) {
      const auto standings = race.standings();
      ASSERT_EQ(standings[0].name, "fast");
      EXPECT_NEAR(standings[1].gap_to_leader, 2.0, 0.6);
    }
  }
  ASSERT_TRUE(race.finished());
  auto standings = race.standings();
  EXPECT_EQ(standings[0].name, "fast");
  EXPECT_NEAR(standings[1].gap_to_leader, 2.0, 0.06);
  // A 5 s penalty for the leader after the flag changes the order.
  race::RaceControl penalised(track, rules, {"fast", "slow"});
  for (double t = 0; t < (2 * length + 100) / 20.0; t += 0.05) {
    if (t > 3 && t < 3.1) penalised.updateContact("fast", t, "barrier");
    penalised.updatePosition("fast", t, atCircle(-20 + 20 * t));
    penalised.updatePosition("slow", t, atCircle(-60 + 20 * t));
  }
  standings = penalised.standings();
  EXPECT_EQ(standings[0].name, "slow");
  EXPECT_NEAR(standings[1].gap_to_leader, 3.0, 0.06);

  const fs::path dir = fs::temp_directory_path() / ("roar_race_" + std::to_string(::getpid()));
  race::writeResults(dir.string(), penalised, race::RaceOutcome::kFinished);
  EXPECT_FALSE(YAML::LoadFile((dir / "results.yaml").string())["run_id"]) << "no run named";
  race::writeResults(dir.string(), penalised, race::RaceOutcome::kInterrupted, "0f3c-run");
  const YAML::Node results = YAML::LoadFile((dir / "results.yaml").string());
  EXPECT_EQ(results["run_id"].as<std::string>(), "0f3c-run");
  EXPECT_EQ(results["status"].as<std::string>(), "interrupted");
  ASSERT_EQ(results["cars"].size(), 2u);
  EXPECT_EQ(results["cars"][0]["name"].as<std::string>(), "slow") << "the cars in finishing order";
  EXPECT_EQ(results["cars"][0]["position"].as<int>(), 1);
  // From the start signal (t = 0): slow crossed the line at 3 s and ran two laps.
  EXPECT_NEAR(results["cars"][0]["race_time_s"].as<double>(), 3.0 + 2 * length / 20.0, 0.05);
  const YAML::Node fast = results["cars"][1];
  EXPECT_EQ(fast["name"].as<std::string>(), "fast");
  EXPECT_EQ(fast["position"].as<int>(), 2);
  EXPECT_EQ(fast["penalties_s"].as<double>(), 5.0);
  EXPECT_EQ(fast["laps"].size(), 2u);
  EXPECT_EQ(fast["incidents"][0]["kind"].as<std::string>(), "barrier");
  EXPECT_NEAR(fast["race_time_s"].as<double>(), 1.0 + 2 * length / 20.0 + 5.0, 0.05);
  EXPECT_LT(results["cars"][0]["race_time_s"].as<double>(), fast["race_time_s"].as<double>())
      << "the winner's race time is the shortest";
  EXPECT_EQ(lines((dir / "laps.csv").string()), 1 + 2 * 2);
  EXPECT_EQ(lines((dir / "sectors.csv").string()), 1 + 2 * 2 * 3);
  fs::remove_all(dir);
}

// A faster car gets by a slower one: one pass, named, on the right lap and place; cars running side by side
// (within the hysteresis) swap nothing; lapping a car is not a pass.
TEST(RaceControl, OvertakesAreRecordedOnceWithWhoWhereAndWhen) {
  const auto track = test::circleTrack(100.0);
  race::RaceRules rules;
  rules.laps = 5;
  race::RaceControl race(track, rules, {"fast", "slow", "twin"});
  // 200 s: fast is a lap ahead of slow (628 m) from t = 131 s on, which is lapping, not another pass.
  for (double t = 0.0; t < 200.0; t += 0.05) {
    race.updatePosition("slow", t, atCircle(-5 + 15.0 * t));                           // 15 m/s, starts ahead
    race.updatePosition("fast", t, atCircle(-30 + 20.0 * t));                          // 20 m/s
    race.updatePosition("twin", t, atCircle(-5 + 15.0 * t + 1.5 * std::sin(t), 3.0));  // beside slow, wobbling
  }
  ASSERT_EQ(race.overtakes().size(), 2u) << "fast passes slow and twin once each; twin and slow swap nothing";
  for (const auto& o : race.overtakes()) {
    EXPECT_EQ(o.passer, "fast");
    EXPECT_EQ(o.lap, 1);
    // fast catches 25 m at 5 m/s: 5 s in, 70 m after the line.
    EXPECT_NEAR(o.time, 5.0, 0.8);
    EXPECT_NEAR(o.s, 70.0, 15.0);
  }
  EXPECT_NE(race.overtakes()[0].passed, race.overtakes()[1].passed);
}

// Odometry of different cars arrives in any order: a second of one car's positions, then a second of the
// other's. Two cars side by side 1 m apart at 30 m/s swapped places every batch (a batch apart is 30 m);
// judged at the same moment they never do, and a real pass is still seen once.
TEST(RaceControl, OvertakesAreJudgedAtTheSameMomentWhateverOrderPositionsArriveIn) {
  const auto track = test::circleTrack(100.0);
  race::RaceRules rules;
  rules.laps = 5;
  race::RaceControl race(track, rules, {"a", "b", "c"});
  const double dt = 0.05;
  for (double t0 = 0.0; t0 < 12.0; t0 += 1.0) {
    for (const char* car : {"a", "b", "c"}) {
      for (double t = t0; t < t0 + 1.0 - 1e-9; t += dt) {
        const std::string name = car;
        const double s = name == "a" ? -5 + 30.0 * t : name == "b" ? -6 + 30.0 * t : -40 + 35.0 * t;
        race.updatePosition(name, t, atCircle(s, name == "b" ? 3.0 : 0.0));
      }
    }
  }
  ASSERT_EQ(race.overtakes().size(), 2u) << "c passes a and b; a and b, side by side, swap nothing";
  for (const auto& o : race.overtakes()) EXPECT_EQ(o.passer, "c");
}

TEST(RaceReport, EachCarHasItsOwnColourAndTheLegendCoversNoPath) {
  const auto track = test::circleTrack(100.0);
  race::RaceRules rules;
  rules.laps = 1;
  race::RaceControl race(track, rules, {"a", "b"});
  report::Telemetry telemetry;
  for (double t = 0.0; t < 40.0; t += 0.05) {
    race.updatePosition("a", t, atCircle(-5 + 20.0 * t, 2.0));
    race.updatePosition("b", t, atCircle(-15 + 20.0 * t, -2.0));
    telemetry["a"].push_back({t, onCircle(-5 + 20.0 * t, 2.0), 20.0});
    telemetry["b"].push_back({t, onCircle(-15 + 20.0 * t, -2.0), 20.0});
  }
  const std::string dir = (std::filesystem::temp_directory_path() / "roar_report_colours").string();
  report::writeRaceReport(dir, race, telemetry, {});
  const cv::Mat image = cv::imread(dir + "/trajectories.png");
  ASSERT_FALSE(image.empty());
  // A circle's map is as high as it is wide, under a 60 px title; the legend's band lies below it.
  const int map_bottom = image.cols + 60;
  ASSERT_GT(image.rows, map_bottom + 20);
  auto count = [&](const cv::Vec3b& bgr, int from_row, int to_row) {
    int n = 0;
    for (int r = from_row; r < to_row; ++r)
      for (int c = 0; c < image.cols; ++c) n += image.at<cv::Vec3b>(r, c) == bgr;
    return n;
  };
  const cv::Vec3b first(255, 140, 30), second(14, 127, 255);  // the palette's first two colours
  EXPECT_GT(count(first, 0, map_bottom), 500) << "car a's path in its colour";
  EXPECT_GT(count(second, 0, map_bottom), 500) << "car b's path in its colour";
  EXPECT_GT(count(first, map_bottom, image.rows), 20) << "car a in the legend, below the map";
  EXPECT_GT(count(second, map_bottom, image.rows), 20) << "car b in the legend, below the map";
}

// Three cars driving the very same line: the last one drawn must not hide the others.
TEST(RaceReport, CarsOnTheSameLineEachShowTheirColour) {
  const auto track = test::circleTrack(100.0);
  race::RaceRules rules;
  rules.laps = 1;
  race::RaceControl race(track, rules, {"a", "b", "c"});
  report::Telemetry telemetry;
  for (double t = 0.0; t < 40.0; t += 0.05) {
    for (const char* car : {"a", "b", "c"}) {
      race.updatePosition(car, t, atCircle(-5 + 20.0 * t));
      telemetry[car].push_back({t, onCircle(-5 + 20.0 * t), 20.0});
    }
  }
  const std::string dir = (std::filesystem::temp_directory_path() / "roar_report_same_line").string();
  report::writeRaceReport(dir, race, telemetry, {});
  const cv::Mat image = cv::imread(dir + "/trajectories.png");
  ASSERT_FALSE(image.empty());
  const int map_bottom = image.cols + 60;
  auto count = [&](const cv::Vec3b& bgr) {
    int n = 0;
    for (int r = 0; r < map_bottom; ++r)
      for (int c = 0; c < image.cols; ++c) n += image.at<cv::Vec3b>(r, c) == bgr;
    return n;
  };
  for (const cv::Vec3b& colour : {cv::Vec3b(255, 140, 30), cv::Vec3b(14, 127, 255), cv::Vec3b(40, 39, 214)}) {
    EXPECT_GT(count(colour), 1000) << "colour " << colour << " shows along the shared line";
  }
}

TEST(RaceControl, ResultsAreReplacedWholeAsTheRaceGoes) {
  const auto track = test::circleTrack(100.0);
  race::RaceRules rules;
  rules.laps = 2;
  race::RaceControl race(track, rules, {"runner"});
  double t = 0.0;
  for (; race.car("runner").timer.lapsCompleted() < 1 && t < 60.0; t += 0.05)
    race.updatePosition("runner", t, atCircle(-5 + 20.0 * t));
  const std::string dir = (std::filesystem::temp_directory_path() / "roar_running_results").string();
  std::filesystem::remove_all(dir);
  race::writeResults(dir, race, race::RaceOutcome::kRunning);
  auto read = [&](const std::string& name) {
    std::ifstream in(dir + "/" + name);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  EXPECT_NE(read("results.yaml").find("status: running"), std::string::npos) << read("results.yaml");
  EXPECT_NE(read("results.yaml").find("laps_completed: 1"), std::string::npos);
  const std::string laps = read("laps.csv");
  EXPECT_EQ(std::count(laps.begin(), laps.end(), '\n'), 2) << laps;
  race::writeResults(dir, race, race::RaceOutcome::kAborted);
  EXPECT_NE(read("results.yaml").find("status: aborted"), std::string::npos);
  EXPECT_EQ(read("results.yaml").find("recording:"), std::string::npos) << "no recorder, nothing said";
  race::writeResults(dir, race, race::RaceOutcome::kFinished, "", race::RecordingState{17.65, false});
  EXPECT_NE(read("results.yaml").find("recording:\n  complete: false\n  recorded_until_s: 17.65\n"), std::string::npos)
      << read("results.yaml");
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir)) files.push_back(e.path().filename().string());
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"laps.csv", "results.yaml", "sectors.csv"}))
      << "nothing half-written left";
}

TEST(RaceControl, ALostDriverBackWithinTheGraceRacesOnAndOneThatIsNotRetires) {
  const auto track = test::circleTrack(100.0);
  race::RaceRules rules;
  rules.laps = 1;
  rules.driver_grace = 30.0;
  race::RaceControl race(track, rules, {"paused", "dead"});
  race.updatePosition("paused", 0.0, atCircle(-5));
  race.updatePosition("dead", 0.0, atCircle(-10));
  race.driverLost("paused", 10.0);
  race.driverLost("dead", 10.0);
  EXPECT_TRUE(race.retireLostDrivers(39.9).empty()) << "within the grace both wait";
  EXPECT_FALSE(race.finished()) << "a car waiting for its driver keeps the race open";
  race.driverBack("paused");
  EXPECT_EQ(race.retireLostDrivers(40.0), std::vector<std::string>{"dead"});
  EXPECT_EQ(race.car("dead").retired, "driver lost");
  EXPECT_DOUBLE_EQ(race.car("dead").retire_time, 10.0) << "retired as of when its driver was lost";
  EXPECT_EQ(race.car("paused").retired, "") << "back in time: it races on, the time it stood lost";
  EXPECT_FALSE(race.anyFinisher());
  double t = 40.0;
  for (; !race.finished() && t < 120.0; t += 0.05) race.updatePosition("paused", t, atCircle(-5 + 20.0 * (t - 40.0)));
  ASSERT_TRUE(race.finished());
  EXPECT_TRUE(race.anyFinisher());
}

TEST(RaceControl, RaceEndsAreJudgedAsRaceControlReportsThem) {
  auto judge = [](bool complete, bool any_finisher, bool out_of_time, bool simulator_lost) {
    race::RaceEnd end;
    end.complete = complete;
    end.any_finisher = any_finisher;
    end.out_of_time = out_of_time;
    end.simulator_lost = simulator_lost;
    return race::judgeRaceEnd(end);
  };
  EXPECT_EQ(judge(true, true, false, false).outcome, race::RaceOutcome::kFinished);
  EXPECT_EQ(judge(true, true, true, true).outcome, race::RaceOutcome::kFinished) << "done before anything failed";
  const race::RaceVerdict nobody = judge(true, false, false, false);
  EXPECT_EQ(nobody.outcome, race::RaceOutcome::kAborted) << "every car retired: no result";
  EXPECT_EQ(nobody.reason, "every car retired, none finished");
  EXPECT_EQ(judge(false, false, true, false).outcome, race::RaceOutcome::kTimedOut);
  EXPECT_EQ(judge(false, true, true, false).outcome, race::RaceOutcome::kTimedOut) << "some finished, not all";
  EXPECT_EQ(judge(false, false, true, true).outcome, race::RaceOutcome::kAborted) << "the simulator died first";
  EXPECT_EQ(judge(false, false, false, false).outcome, race::RaceOutcome::kAborted)
      << "shut down before the end and its time limit";
  EXPECT_TRUE(judge(false, false, false, true).reason.empty());
  EXPECT_STREQ(race::outcomeWords(race::RaceOutcome::kTimedOut), "timed out");
  EXPECT_STREQ(race::outcomeWords(race::RaceOutcome::kFinished), "finished");
}

TEST(RaceControl, StandingLineSaysTheCarsRace) {
  const auto track = test::circleTrack(100.0);
  race::RaceRules rules;
  rules.laps = 2;
  const std::string long_name(600, 'x');  // longer than any fixed buffer a line might be printed into
  race::RaceControl race(track, rules, {"runner", long_name});
  double t = 0.0;
  for (; t < 40.0; t += 0.05) {
    race.updatePosition("runner", t, atCircle(-5 + 20.0 * t));
    race.updatePosition(long_name, t, atCircle(-10 + 10.0 * t));
  }
  race.retire(long_name, t, "driver lost");
  const auto standings = race.standings();
  ASSERT_EQ(standings.front().name, "runner");
  const std::string runner = race::standingLine(race, standings.front());
  const double best = *race.car("runner").timer.bestLap();
  EXPECT_EQ(runner.rfind("P1 runner: 1/2 laps, best lap " + std::to_string(best) + " s, gap 0.000 s", 0), 0u) << runner;
  EXPECT_NE(runner.find("barrier contacts 0, car contacts 0, track limits 0"), std::string::npos) << runner;
  const std::string retired = race::standingLine(race, standings.back());
  EXPECT_EQ(retired.rfind("P2 " + long_name + ": 0/2 laps (retired: driver lost), best lap - s", 0), 0u)
      << retired.substr(590);
  EXPECT_NE(retired.find("(no clean lap to compare)"), std::string::npos) << "the line is whole, not cut";
}

// Racing in a field: who is at fault in a contact, the planner's choice of the car to follow, and whole
// races of the stack's cars in one process (harness::runRace), with and without overtaking.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "roar/harness/race.h"
#include "roar/planning/field_planner.h"
#include "roar/planning/speed_profile.h"
#include "roar/race/contact_fault.h"
#include "roar/sim/world.h"
#include "roar/track/map_folder.h"
#include "test_support.h"

using namespace roar;
using planning::RaceMode;

namespace {

race::CarAtContact car(const std::string& name, double x, double y, double vx, double vy) {
  return {name, {x, y}, std::atan2(vy, vx), {vx, vy}};
}

struct Sprint {
  track::Track track = track::loadMapFolder(test::sourceDir() + "/maps/roar_sprint");
  vehicle::VehicleParams vehicle = test::sedan();
  planning::VehicleLimits limits = planning::vehicleLimits(vehicle, track.info().friction, 0.85);
  planning::Trajectory line = planning::planRacingTrajectory(track, limits, {});
};

Sprint& sprint() {
  static Sprint s;
  return s;
}

Eigen::Vector3d onLineAt(double s, double lateral = 0.0) {
  const auto p = planning::sampleAt(sprint().line, s);
  const Eigen::Vector2d xy = p.position + lateral * Eigen::Vector2d(-std::sin(p.yaw), std::cos(p.yaw));
  return {xy.x(), xy.y(), p.z};
}

}  // namespace

TEST(ContactFault, TheCarBehindIsAtFaultForRunningIntoTheBack) {
  const auto fault = race::attributeContact(car("front", 10, 0, 20, 0), car("rear", 5.5, 0.3, 25, 0), 0.0);
  EXPECT_EQ(fault.at_fault, "rear");
  EXPECT_EQ(fault.kind, "from behind");
  EXPECT_EQ(race::attributeContact(car("rear", 5.5, 0.3, 25, 0), car("front", 10, 0, 20, 0), 0.0).at_fault, "rear");
}

TEST(ContactFault, AlongsideTheCarThatMovedSidewaysIsAtFault) {
  // b alongside a, on its left; a steers left into it.
  const auto fault = race::attributeContact(car("a", 0, 0, 30, 2.0), car("b", 1.0, 1.9, 30, 0), 0.0);
  EXPECT_EQ(fault.at_fault, "a");
  EXPECT_EQ(fault.kind, "alongside");
  EXPECT_EQ(race::attributeContact(car("a", 0, 0, 30, 0), car("b", 1.0, 1.9, 30, -2.0), 0.0).at_fault, "b");
}

TEST(ContactFault, SidewaysIsAcrossTheRoadNotAcrossTheCars) {
  // Both cars follow a road heading 0.3 rad left; b alongside on the left holds its place, a moves over.
  const double road = 0.3;
  const Eigen::Vector2d along(std::cos(road), std::sin(road)), left(-std::sin(road), std::cos(road));
  auto at = [&](const std::string& n, const Eigen::Vector2d& p, const Eigen::Vector2d& v) {
    return race::CarAtContact{n, p, std::atan2(v.y(), v.x()), v};
  };
  const auto fault = race::attributeContact(at("a", {0, 0}, 30 * along + 2.0 * left),
                                            at("b", 1.0 * along + 1.9 * left, 30 * along), road);
  EXPECT_EQ(fault.at_fault, "a");
}

TEST(ContactFault, TwoCarsSqueezingAlikeIsARacingIncident) {
  const auto fault = race::attributeContact(car("a", 0, 0, 30, 0.5), car("b", 0.5, 1.9, 30, -0.5), 0.0);
  EXPECT_EQ(fault.at_fault, "");
  EXPECT_EQ(fault.kind, "alongside");
}

TEST(FieldPlanner, WithoutOvertakingACarFollowsTheCarAheadOnTheLine) {
  planning::FieldOptions options;
  options.overtaking = false;
  planning::FieldPlanner field(sprint().track, sprint().line, sprint().limits, options);
  const double s = 100.0;
  field.locate("ego", onLineAt(s), 20.0, 0.0);
  field.locate("slow", onLineAt(s + 30.0), 10.0, 0.0);
  field.locate("aside", onLineAt(s + 15.0, 6.0), 5.0, 0.0);  // off the line: not in the way
  const auto window = field.window("ego");
  EXPECT_EQ(field.decision("ego").mode, RaceMode::kFollow);
  EXPECT_EQ(field.decision("ego").other, "slow");
  // No faster than the car followed once at the gap behind it.
  EXPECT_LE(planning::sampleAt(window, s + 30.0 - field.options().overtake.margins.follow_gap + 3.5).speed,
            10.0 + 1e-6);
  // The car in front has nobody ahead within the window: the racing line.
  field.window("slow");
  EXPECT_EQ(field.decision("slow").mode, RaceMode::kRacingLine);
}

TEST(FieldPlanner, ACarALapUpIsToldFromOneJustBehind) {
  // `fast` goes once round the lap (in steps the planner can follow) and comes up behind `slow` again:
  // slow lets it by (blue flag). Behind it on the same lap, it would be racing for position.
  planning::FieldOptions options;
  options.overtake.blue_flags.enabled = true;
  planning::FieldPlanner field(sprint().track, sprint().line, sprint().limits, options);
  const double L = sprint().line.length, s = 300.0;
  field.locate("slow", onLineAt(s), 20.0, 0.0);
  field.locate("fast", onLineAt(s - 40.0), 40.0, 0.0);
  field.window("slow");
  EXPECT_NE(field.decision("slow").mode, RaceMode::kYield) << "the same lap: racing";
  double t = 0.0;
  for (double covered = 10.0; covered <= L; covered += 10.0)
    field.locate("fast", onLineAt(s - 40.0 + covered), 40.0, t += 0.25);
  field.locate("fast", onLineAt(s - 40.0), 40.0, t += 0.25);
  field.locate("slow", onLineAt(s), 20.0, t);
  field.window("slow");
  EXPECT_EQ(field.decision("slow").mode, RaceMode::kYield);
  EXPECT_EQ(field.decision("slow").other, "fast");
}

TEST(FieldPlanner, APaceBelowOneScalesTheWindowsSpeeds) {
  planning::FieldPlanner field(sprint().track, sprint().line, sprint().limits, {});
  field.locate("ego", onLineAt(300.0), 20.0, 0.0);
  const auto full = field.window("ego");
  field.setPace("ego", 0.9);
  const auto slow = field.window("ego");
  ASSERT_EQ(full.points.size(), slow.points.size());
  for (std::size_t k = 0; k < full.points.size(); k += 10) {
    EXPECT_NEAR(slow.points[k].speed, 0.9 * full.points[k].speed, 1e-9);
  }
  for (double bad : {0.0, -0.5, 1.5, std::nan("")}) {
    EXPECT_NE(test::errorOf([&] { field.setPace("ego", bad); }).find("pace of 'ego'"), std::string::npos) << bad;
  }
  EXPECT_THROW(field.window("nobody"), std::out_of_range);
}

namespace {

// Metres along Roar Sprint's line a car's view of `other` has it cover in its first `seconds`.
double predictedTravel(const planning::FieldPlanner& field, const std::string& car, const std::string& other,
                       double seconds) {
  for (const auto& path : field.predictions(car)) {
    if (path.name != other) continue;
    const auto k = static_cast<std::size_t>(std::lround(seconds / path.step));
    const double from = planning::project(sprint().line, path.positions.at(0)).s;
    return planning::project(sprint().line, path.positions.at(k)).s - from;
  }
  ADD_FAILURE() << car << " predicted nothing of " << other;
  return 0.0;
}

}  // namespace

// A slow car where the line's speeds rise (out of a corner, down a straight) gains speed too, gently: it
// is driving its pace, and is predicted at it. Only a car gaining as hard as it can (off the grid) shows
// its engine rather than its pace. Until then any car gaining speed kept the estimate it had: the pace car
// on its opening lap at Roar Speedway was predicted at 79% of the line's speed while it drove 63%.
TEST(FieldPlanner, ACarGainingSpeedGentlyIsPredictedAtThePaceItDrives) {
  planning::FieldOptions options;
  options.overtake.prediction.keep = true;
  const auto& line = sprint().line;
  auto drive = [&](planning::FieldPlanner* field, const std::string& name, double share, double from, double to) {
    // From rest (taken for a full-pace car), then 20 odometry messages a second along the line from `from`
    // (75-153 m: the line's speeds rise from 35.7 to 42.2 m/s) at `share` of its speed.
    field->locate(name, onLineAt(from - 15.0), 0.0, 0.0);
    double t = 0.0, s = from;
    while (s < to) {
      const double v = share * planning::sampleAt(line, s).speed;
      field->locate(name, onLineAt(s), v, t += 0.05);
      s += 0.05 * v;
    }
    return std::pair{s, t};
  };
  planning::FieldPlanner field(sprint().track, line, sprint().limits, options);
  const auto [slow_s, slow_t] = drive(&field, "slow", 0.6, 75.0, 150.0);
  field.locate("ego", onLineAt(slow_s - 40.0), 25.0, slow_t);
  field.window("ego");
  double at_line_speed = 0.0;
  for (double t = 0.0; t < 2.0; t += 0.01)
    at_line_speed += 0.01 * planning::sampleAt(line, slow_s + at_line_speed).speed;
  EXPECT_LT(predictedTravel(field, "ego", "slow", 2.0), 0.7 * at_line_speed)
      << "its 60% of the line's speed, not the full pace it was taken for at rest";

  // Gaining as hard as the engine lets it from 10 m/s: taken for a full-pace car still, and predicted to
  // go on gaining (not held at the share of the line's speed it has while it is still slow).
  planning::FieldPlanner launch(sprint().track, line, sprint().limits, options);
  launch.locate("launching", onLineAt(60.0), 0.0, 0.0);
  double t = 0.0, s = 75.0, v = 10.0;
  const auto& limits = sprint().limits;
  while (s < 150.0) {
    launch.locate("launching", onLineAt(s), v, t += 0.05);
    s += 0.05 * v;
    v += 0.05 * planning::accelerationAt(limits, v, 0.0);
  }
  launch.locate("ego", onLineAt(s - 40.0), v, t);
  launch.window("ego");
  EXPECT_GT(predictedTravel(launch, "ego", "launching", 2.0), 2.0 * v) << "predicted to go on gaining, from " << v;
}

TEST(Race, TheStackPassesAPaceCarCleanlyWithinALapOfCatchingIt) {
  planning::FieldOptions field;
  field.overtaking = true;
  harness::RaceOptions options;
  options.field = field;
  const auto r = harness::runRace(sprint().track, sprint().vehicle, {{"pace", 0, 1.0, 15.0}, {"ego", 1}}, options);
  ASSERT_TRUE(r.finished);
  EXPECT_EQ(r.cars.at(0).name, "ego");
  EXPECT_TRUE(r.contacts.empty()) << r.contacts.size() << " contacts, the first at t = " << r.contacts.at(0).time;
  ASSERT_FALSE(r.overtakes.empty());
  EXPECT_EQ(r.overtakes.front().passer, "ego");
  EXPECT_EQ(r.overtakes.front().passed, "pace");
  int completed = 0;
  for (const auto& pass : r.passes) {
    if (!pass.completed) continue;
    ++completed;
    EXPECT_LT(pass.end_time - pass.caught_time, 63.0) << "from catching to completing the pass";
  }
  EXPECT_GE(completed, 1);
  for (const auto& c : r.cars) {
    EXPECT_EQ(c.barrier_contacts, 0) << c.name;
    EXPECT_EQ(c.track_limit_violations, 0) << c.name;
  }
  EXPECT_GT(r.car("ego").time_in_traffic, 0.0);
}

// Where a pass was won (PassAttempt::level_s, which harness::passPlace reads) is where the passer first drew
// level with the car it passes: behind it at the tick before, level or ahead at that tick.
TEST(Race, APassRecordsWhereThePasserFirstDrewLevel) {
  harness::RaceOptions options;
  options.field.overtaking = true;
  std::map<std::string, std::vector<double>> s_of;  // each car's line s, every tick
  options.on_tick = [&](const harness::RaceTick& tick) { s_of[*tick.car].push_back(tick.on_line.s); };
  const auto r = harness::runRace(sprint().track, sprint().vehicle, {{"pace", 0, 1.0, 15.0}, {"ego", 1}}, options);
  int checked = 0;
  for (const auto& pass : r.passes) {
    if (!pass.completed) continue;
    ASSERT_TRUE(std::isfinite(pass.level_s)) << "a completed pass drew level somewhere";
    const auto& passer = s_of.at(pass.passer);
    const auto& passed = s_of.at(pass.passed);
    const auto tick = static_cast<std::size_t>(std::lround(pass.start_time / sim::WorldOptions().control_dt));
    std::size_t k = tick;
    while (k < passer.size() && passer[k] != pass.level_s) ++k;
    ASSERT_LT(k, passer.size()) << "level_s is where the passer was at a tick of the pass";
    ASSERT_GT(k, 0u);
    EXPECT_GE(planning::aheadOnLap(passer[k], passed[k], r.line_length), 0.0);
    EXPECT_LT(planning::aheadOnLap(passer[k - 1], passed[k - 1], r.line_length), 0.0);
    ++checked;
  }
  EXPECT_GE(checked, 1);
}

// Only cars still racing pass each other: after the flag the winner drives on and laps the slow car still
// racing, which is no pass of the race (the traffic benchmark counted such passes, and their aborts).
TEST(Race, NoPassIsCountedOnceEitherCarHasFinished) {
  harness::RaceOptions options;
  options.field.overtaking = true;
  options.laps = 1;
  // At 35% of the planned speeds the pace car is still on its lap when ego, done with its own, comes round
  // to it again (at about 134 s here, ego finished at 78 s).
  const auto eight = track::loadMapFolder(test::sourceDir() + "/maps/roar_eight");
  const auto r = harness::runRace(eight, sprint().vehicle, {{"pace", 0, 0.35}, {"ego", 1}}, options);
  ASSERT_TRUE(r.finished);
  const double ego_done = r.car("ego").race_time, pace_done = r.car("pace").race_time;
  ASSERT_LT(ego_done + 40.0, pace_done) << "ego finished long before the pace car";
  ASSERT_FALSE(r.passes.empty());
  for (const auto& pass : r.passes) {
    EXPECT_LT(pass.start_time, ego_done) << pass.passer << " on " << pass.passed;
  }
  for (const auto& pass : r.given_up_before_alongside) {
    EXPECT_LT(pass.start_time, ego_done) << pass.passer << " on " << pass.passed << ", given up";
  }
}

// Every pass begins from behind the car passed. A car being passed, the other beside it and going by, once
// took staying beside it for a pass of its own, given up as the other completed: a third of the traffic
// benchmark's aborted attempts (Monza, cars 5% of pace apart, at 14 s).
TEST(Race, EveryPassBeginsFromBehindTheCarPassed) {
  const auto monza = track::loadMapFolder(test::sourceDir() + "/maps/monza");
  harness::RaceOptions options;
  options.field.overtaking = true;
  options.laps = 1;
  options.time_limit = 30.0;
  std::map<std::string, double> s_of;
  std::map<std::string, RaceMode> mode_of;
  int passes_begun = 0;
  options.on_tick = [&](const harness::RaceTick& tick) {
    const std::string& car = *tick.car;
    s_of[car] = tick.on_line.s;
    const auto& d = tick.decision;
    if (d.mode == RaceMode::kPass && mode_of[car] != RaceMode::kPass) {
      ++passes_begun;
      double ahead = s_of.at(d.other) - tick.on_line.s;
      ahead -= std::round(ahead / monza.length()) * monza.length();
      EXPECT_GE(ahead, options.field.overtake.car.length)
          << car << " began a pass on " << d.other << " from beside it at t = " << tick.time;
    }
    mode_of[car] = d.mode;
  };
  harness::runRace(monza, sprint().vehicle, {{"p0", 0, 0.75}, {"p1", 1, 0.80}, {"p2", 2, 0.85}, {"p3", 3, 0.90}},
                   options);
  EXPECT_GT(passes_begun, 0);
}

// A pass the planner begins and gives up before the passer draws alongside is no attempt, but it is not lost
// either: it is recorded apart, from the tick the pass was chosen to the tick it was not. Each record is such
// a run of pass decisions; every run in which the passer stayed well behind the car (by more than a car's
// length and a metre) is one.
TEST(Race, PassesGivenUpBeforeDrawingAlongsideAreRecordedApart) {
  harness::RaceOptions options;
  options.field.overtaking = true;
  options.laps = 1;
  struct Run {
    std::string passer, passed;
    double start = 0.0, end = -1.0;
    double closest = 1e9;  // m the passed car was ahead of the passer at the least
  };
  std::vector<Run> runs;
  std::map<std::string, long> open;  // the run under way per car (index into runs)
  std::map<std::string, double> s_of;
  const double L = sprint().track.length();
  options.on_tick = [&](const harness::RaceTick& tick) {
    const std::string& car = *tick.car;
    s_of[car] = tick.on_line.s;
    const auto& d = tick.decision;
    auto it = open.find(car);
    if (it != open.end() && (d.mode != RaceMode::kPass || d.other != runs[it->second].passed)) {
      runs[it->second].end = tick.time;
      open.erase(it);
      it = open.end();
    }
    if (d.mode != RaceMode::kPass) return;
    if (it == open.end()) {
      runs.push_back({car, d.other, tick.time});
      it = open.emplace(car, static_cast<long>(runs.size()) - 1).first;
    }
    double ahead = s_of.at(d.other) - tick.on_line.s;
    ahead -= std::round(ahead / L) * L;
    runs[it->second].closest = std::min(runs[it->second].closest, ahead);
  };
  // A car 5% faster behind another on Roar Sprint: passes begun there are given up (the road too narrow
  // beside a line that swings across it) before the passer is beside the car it passes.
  const auto r = harness::runRace(sprint().track, sprint().vehicle, {{"slow", 0, 0.75}, {"fast", 1, 0.8}}, options);
  // Once either car has finished, a pass under way is given up with the race, whatever the decision
  // (NoPassIsCountedOnceEitherCarHasFinished): only what was given up before that is matched here.
  double first_flag = std::numeric_limits<double>::infinity();
  for (const auto& c : r.cars)
    if (c.finished) first_flag = std::min(first_flag, c.race_time);
  const double well_behind = sprint().vehicle.chassis.box_size.x() + 1.0;
  int surely_given_up = 0;
  for (const auto& run : runs) surely_given_up += run.end >= 0.0 && run.end < first_flag && run.closest > well_behind;
  EXPECT_GT(surely_given_up, 0) << "no pass given up before alongside in this race: nothing tested";
  EXPECT_GE(static_cast<int>(r.given_up_before_alongside.size()), surely_given_up);
  for (const auto& g : r.given_up_before_alongside) {
    if (g.end_time >= first_flag) continue;
    bool matched = false;
    for (const auto& run : runs) {
      // (A run may hold an attempt and, once that has closed, a pass given up: that one begins within it.)
      matched = matched || (run.passer == g.passer && run.passed == g.passed && run.start <= g.start_time &&
                            run.end == g.end_time);
    }
    EXPECT_TRUE(matched) << g.passer << " on " << g.passed << " " << g.start_time << "-" << g.end_time
                         << ": no run of pass decisions from then to then";
    EXPECT_FALSE(g.completed);
    EXPECT_TRUE(g.samples.empty());
  }
  for (const auto& pass : r.passes) {
    for (const auto& g : r.given_up_before_alongside) {
      EXPECT_FALSE(g.passer == pass.passer && g.start_time == pass.start_time)
          << "the pass from " << pass.start_time << " s is an attempt and given up both";
    }
  }
}

TEST(Race, WithoutOvertakingTheFieldIsAProcession) {
  harness::RaceOptions options;
  options.laps = 1;
  options.field.overtaking = false;
  const auto r = harness::runRace(sprint().track, sprint().vehicle, {{"pace", 0, 1.0, 15.0}, {"ego", 1}}, options);
  ASSERT_TRUE(r.finished);
  EXPECT_EQ(r.cars.at(0).name, "pace");
  EXPECT_TRUE(r.overtakes.empty());
  EXPECT_TRUE(r.passes.empty());
  EXPECT_TRUE(r.contacts.empty());
}

// What traffic costs a car: held behind a car at 15 m/s, a lap of Roar Sprint takes the stack's car far
// longer than alone from the same grid slot; the car ahead, with nobody in front, loses nothing.
// The passing speed is against the car alone at the same place on the same round of the line: on the
// opening lap a car alone is still gaining speed from the grid. Past the last round run alone, the last.
TEST(Race, PassingSpeedIsAgainstFreeAirOnTheSameRound) {
  const double bin = 2.0;
  const std::vector<std::vector<double>> free_air{{20.0, 20.0, std::nan("")}, {40.0, 40.0, 40.0}};
  harness::PassAttempt pass;
  pass.samples = {{0, 1.0, 18.0}, {1, 1.0, 36.0}};  // 90% of the grid lap's 20, 90% of the flying lap's 40
  EXPECT_NEAR(harness::passingSpeedShare(pass, free_air, bin), 0.9, 1e-12);
  pass.samples = {{3, 3.0, 30.0}};  // a round past those run alone: the last one's
  EXPECT_NEAR(harness::passingSpeedShare(pass, free_air, bin), 0.75, 1e-12);
  pass.samples = {{0, 5.0, 30.0}};  // no free-air speed there
  EXPECT_TRUE(std::isnan(harness::passingSpeedShare(pass, free_air, bin)));
  // And a race records its cars' speeds round by round: two laps from the grid are at least two rounds.
  harness::RaceOptions options;
  options.laps = 2;
  const auto alone = harness::runRace(sprint().track, sprint().vehicle, {{"alone", 1}}, options).car("alone");
  ASSERT_GE(alone.round_speeds.size(), 2u);
  std::size_t seen = 0;
  for (double v : alone.round_speeds[1]) seen += std::isfinite(v);
  EXPECT_GT(seen, alone.round_speeds[1].size() * 9 / 10) << "a whole round should be through most bins";
}

TEST(Race, LapTimeLossIsTheTimeTrafficCostsAgainstTheSameCarAlone) {
  harness::RaceOptions options;
  options.laps = 1;
  options.field.overtaking = false;
  const harness::RaceCar pace{"pace", 0, 1.0, 15.0}, ego{"ego", 1};
  const auto r = harness::runRace(sprint().track, sprint().vehicle, {pace, ego}, options);
  const auto pace_alone = harness::runRace(sprint().track, sprint().vehicle, {pace}, options).car("pace");
  const auto ego_alone = harness::runRace(sprint().track, sprint().vehicle, {ego}, options).car("ego");
  ASSERT_TRUE(r.finished);
  EXPECT_GT(harness::lapTimeLoss(r.car("ego"), ego_alone), 20.0);
  EXPECT_NEAR(harness::lapTimeLoss(r.car("pace"), pace_alone), 0.0, 0.05);
  harness::RaceCarResult unfinished = r.car("ego");
  unfinished.finished = false;
  EXPECT_TRUE(std::isnan(harness::lapTimeLoss(unfinished, ego_alone)));
}

// How far a reverse grid finished from pace order: the pairs that finished the other way round.
TEST(Race, PairsOutOfOrderCountsThePairsFinishedTheOtherWayRound) {
  harness::RaceResult race;
  for (const char* name : {"c", "a", "b"}) {
    race.cars.emplace_back();
    race.cars.back().name = name;
  }
  EXPECT_EQ(harness::pairsOutOfOrder(race, {"a", "b", "c"}), 2);  // c ahead of a and of b
  EXPECT_EQ(harness::pairsOutOfOrder(race, {"c", "a", "b"}), 0);
  EXPECT_EQ(harness::pairsOutOfOrder(race, {"b", "a", "c"}), 3);
  EXPECT_NE(test::errorOf([&] { harness::pairsOutOfOrder(race, {"a", "d"}); }).find("'d'"), std::string::npos);
}

TEST(Race, RefusesBadFields) {
  EXPECT_NE(test::errorOf([] { harness::runRace(sprint().track, sprint().vehicle, {}, {}); }).find("no cars"),
            std::string::npos);
  EXPECT_NE(test::errorOf([] {
              harness::runRace(sprint().track, sprint().vehicle, {{"a", 0}, {"a", 1}}, {});
            }).find("twice"),
            std::string::npos);
  EXPECT_NE(test::errorOf([] {
              harness::runRace(sprint().track, sprint().vehicle, {{"a", 0}, {"b", 0}}, {});
            }).find("grid slot 0"),
            std::string::npos);
  EXPECT_NE(test::errorOf([] {
              harness::runRace(sprint().track, sprint().vehicle, {{"a", 0, 0.0}}, {});
            }).find("pace"),
            std::string::npos);
}

// A driver lost anywhere on the lap at racing speed (roar_sim holds its last control for control_timeout,
// then stops the car). Every car comes to rest; most stop clear of the barrier, but one left at the limit
// of braking or of grip on the way into a corner can slide into it: 15 of the 154 places on Roar Sprint.
// That count may only fall.
TEST(SafeStop, ACarLeftAtRacingSpeedStopsAndMostlyClearOfTheBarrier) {
  const auto& line = sprint().line;
  int hits = 0, tried = 0;
  for (double s = 0.0; s < line.length; s += 10.0) {
    sim::WorldOptions o;
    o.control_timeout = 0.5;
    sim::World world(sprint().track, o);
    const auto p = planning::sampleAt(line, s);
    track::Pose pose;
    pose.position = onLineAt(s);
    pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(p.yaw, Eigen::Vector3d::UnitZ()));
    world.spawnVehicle("ego", sprint().vehicle, pose);
    vehicle::VehicleControl last;  // what the controller last said: its line's steer and pedals
    (p.acceleration < 0 ? last.brake : last.throttle) = std::min(1.0, std::abs(p.acceleration) / 15.0);
    last.steer = std::atan(sprint().vehicle.wheelbase() * p.curvature) / sprint().vehicle.steering.maxAngleAt(p.speed);
    world.setControl("ego", last);
    world.setVehicleVelocity("ego", {p.speed * std::cos(p.yaw), p.speed * std::sin(p.yaw), 0},
                             {0, 0, p.speed * p.curvature});
    bool hit = false;
    for (int i = 0; i < 400; ++i) {
      world.step();
      for (const auto& c : world.contacts("ego")) hit = hit || c.other == "barrier";
    }
    ++tried;
    hits += hit;
    EXPECT_LT(world.vehicleState("ego").speed, 0.5) << "left at s = " << s << " m";
  }
  EXPECT_EQ(tried, 154);
  EXPECT_LE(hits, 15) << "places of " << tried << " where the stopping car met the barrier";
}

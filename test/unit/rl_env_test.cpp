// The racing environment: spaces against what it returns, determinism, resets, rewards, termination,
// rejected actions and the vectorised environment.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <mutex>
#include <regex>
#include <thread>

#include "roar/rl/async_vector_env.h"
#include "roar/rl/racing_env.h"
#include "roar/rl/vector_env.h"
#include "roar/track/map_folder.h"
#include "test_support.h"

using namespace roar;
using rl::Space;
using rl::Value;

namespace {

const track::Track& sprint() {
  static const track::Track t = track::loadMapFolder(test::sourceDir() + "/maps/roar_sprint");
  return t;
}

rl::EnvOptions stateOptions() { return rl::readEnvOptions(test::sourceDir() + "/config/rl/state.yaml"); }

// Full throttle, steering at the waypoint 10 m ahead: a crude driver that makes progress.
Value chase(const Space& actions, const Value& obs, double throttle = 0.5) {
  const auto& wp = obs.at("waypoints_information").at("waypoint_10").numbers;
  Value a = rl::zeros(actions);
  a.at("throttle").numbers[0] = throttle;
  a.at("steer").numbers[0] = std::clamp(1.5 * std::atan2(wp[1], wp[0]), -1.0, 1.0);
  return a;
}

// What a step said, as numbers (the observation in double precision, not flattened to float).
std::vector<double> trace(const rl::StepResult& r) {
  std::vector<double> out = {r.reward, r.info.track_s, r.info.lateral, r.info.speed};
  for (const auto& key : r.observation.keys) {
    const Value& v = r.observation.at(key);
    out.insert(out.end(), v.numbers.begin(), v.numbers.end());
    for (const auto& inner : v.entries) out.insert(out.end(), inner.numbers.begin(), inner.numbers.end());
  }
  return out;
}

}  // namespace

TEST(RlEnv, WhatResetAndStepReturnLiesInTheSpaces) {
  rl::EnvOptions options = rl::readEnvOptions(test::sourceDir() + "/config/rl/camera.yaml");
  rl::RacingEnv env(sprint(), test::sedan(), options);
  const Space& obs = env.observationSpace();
  EXPECT_EQ(obs.keys, (std::vector<std::string>{"angular_velocity", "camera_depth", "camera_rgb", "imu", "lidar",
                                                "speed", "velocity", "waypoints_information"}));
  EXPECT_EQ(obs.at("camera_rgb").shape, (std::vector<int>{84, 84, 3}));
  EXPECT_EQ(obs.at("camera_rgb").dtype, rl::DType::kUInt8);
  EXPECT_EQ(obs.at("camera_depth").shape, (std::vector<int>{84, 84}));
  EXPECT_EQ(obs.at("lidar").shape, std::vector<int>{64});
  EXPECT_EQ(obs.at("lidar").high[0], 50.0);
  EXPECT_EQ(obs.at("waypoints_information").keys,
            (std::vector<std::string>{"waypoint_10", "waypoint_20", "waypoint_40"}));
  rl::ResetResult reset = env.reset(11);
  rl::check(obs, reset.observation, "reset observation");
  Value o = reset.observation;
  for (int i = 0; i < 60; ++i) {
    const rl::StepResult r = env.step(chase(env.actionSpace(), o));
    rl::check(obs, r.observation, "step observation");
    o = r.observation;
  }
  // The scene is seen: the road ahead is grey, the sky blue; some LiDAR beams hit the barriers.
  const auto& rgb = o.at("camera_rgb").numbers;
  const auto& depth = o.at("camera_depth").numbers;
  EXPECT_GT(rgb[2], rgb[0]) << "the top-left pixel is sky";
  EXPECT_LT(depth[83 * 84 + 42], 10.0) << "the road just ahead is near";
  const auto& lidar = o.at("lidar").numbers;
  EXPECT_LT(*std::min_element(lidar.begin(), lidar.end()), 50.0);
  EXPECT_GT(o.at("speed").numbers[0], 5.0);
  // IMU: a car on a flat road reads about +g upwards.
  EXPECT_NEAR(o.at("imu").numbers[2], 9.81, 3.0);
}

TEST(RlEnv, TheSameSeedGivesTheSameEpisodeBitForBit) {
  rl::RacingEnv env(sprint(), test::sedan(), stateOptions());
  auto episode = [&](std::uint64_t seed) {
    std::vector<std::vector<double>> out;
    Value o = env.reset(seed).observation;
    std::mt19937_64 actions(99);
    for (int i = 0; i < 150; ++i) {
      Value a = chase(env.actionSpace(), o, 0.8);
      a.at("steer").numbers[0] =
          std::clamp(a.at("steer").numbers[0] + std::uniform_real_distribution<double>(-0.3, 0.3)(actions), -1.0, 1.0);
      const rl::StepResult r = env.step(a);
      out.push_back(trace(r));
      o = r.observation;
      if (r.done()) break;
    }
    return out;
  };
  const auto first = episode(7);
  const auto other = episode(8);
  const auto again = episode(7);
  EXPECT_EQ(first, again);
  EXPECT_NE(first, other) << "another seed spawns elsewhere";
  rl::RacingEnv fresh(sprint(), test::sedan(), stateOptions());
  rl::ResetResult a = fresh.reset(7);
  EXPECT_EQ(rl::flatten(fresh.observationSpace(), a.observation),
            rl::flatten(env.observationSpace(), env.reset(7).observation))
      << "a used environment resets to what a new one does";
}

// step(action, &result) writes into the result it is given (VectorEnv and rl_train step that way): the
// same episode as step(action), whatever the result held before, with LiDAR and camera too.
TEST(RlEnv, SteppingIntoAnEarlierResultGivesTheSameEpisode) {
  rl::EnvOptions options = stateOptions();
  options.observation.lidar.beams = 16;
  options.observation.camera.width = options.observation.camera.height = 16;
  options.observation.camera.depth = true;
  rl::RacingEnv by_value(sprint(), test::sedan(), options), in_place(sprint(), test::sedan(), options);
  Value o = by_value.reset(5).observation;
  rl::StepResult reused;
  reused.observation = in_place.reset(5).observation;
  for (int i = 0; i < 60; ++i) {
    const Value a = chase(by_value.actionSpace(), o, 0.9);
    const rl::StepResult r = by_value.step(a);
    in_place.step(a, &reused);
    EXPECT_EQ(trace(r), trace(reused)) << "step " << i;
    EXPECT_EQ(rl::flatten(by_value.observationSpace(), r.observation),
              rl::flatten(in_place.observationSpace(), reused.observation))
        << "step " << i;
    o = r.observation;
  }
}

TEST(RlEnv, ResetPutsTheCarAtRestOnItsSpawnAndClearsTheEpisode) {
  rl::EnvOptions options = stateOptions();
  options.observation.lidar.beams = 16;
  rl::RacingEnv env(sprint(), test::sedan(), options);
  const rl::ResetResult first = env.reset(21);
  Value o = first.observation;
  double driven = 0.0;
  for (int i = 0; i < 100; ++i) {
    const rl::StepResult r = env.step(chase(env.actionSpace(), o, 1.0));
    o = r.observation;
    driven = r.info.progress;
    if (r.done()) break;
  }
  EXPECT_GT(driven, 50.0);
  EXPECT_GT(o.at("speed").numbers[0], 10.0);
  const rl::ResetResult again = env.reset(21);
  EXPECT_LT(again.observation.at("speed").numbers[0], 0.05) << "at rest";
  EXPECT_EQ(again.info.progress, 0.0);
  EXPECT_EQ(again.info.episode_steps, 0);
  EXPECT_EQ(again.info.episode_return, 0.0);
  EXPECT_EQ(again.info.laps, 0);
  EXPECT_NEAR(again.info.track_s, first.info.track_s, 1e-9) << "the same spawn point";
  EXPECT_EQ(again.observation.at("lidar").numbers, first.observation.at("lidar").numbers)
      << "the sensors see the spawn";
  const vehicle::VehicleState state = env.world().vehicleState(rl::RacingEnv::kCar);
  EXPECT_LT(state.speed, 0.05);
  const rl::StepResult step = env.step(rl::zeros(env.actionSpace()));
  EXPECT_EQ(step.info.episode_steps, 1) << "the step count starts again";
}

TEST(RlEnv, ProgressIsRewardedAndDrivingIntoTheBarrierEndsTheEpisode) {
  rl::RacingEnv env(sprint(), test::sedan(), stateOptions());
  Value o = env.reset(4).observation;
  double reward = 0.0;
  rl::StepInfo info;
  for (int i = 0; i < 60; ++i) {
    const rl::StepResult r = env.step(chase(env.actionSpace(), o));
    reward += r.reward;
    info = r.info;
    o = r.observation;
    ASSERT_FALSE(r.done());
  }
  EXPECT_GT(info.progress, 20.0);
  // Progress near the centre line earns close to 20 per metre.
  EXPECT_NEAR(reward, info.episode_return, 1e-9);
  EXPECT_GT(reward, 10.0 * info.progress);
  EXPECT_LE(reward, 20.0 * info.progress + 1e-6);
  // Hard left at full throttle: into the run-off and the barrier.
  rl::StepResult r;
  for (int i = 0; i < 400; ++i) {
    Value a = rl::zeros(env.actionSpace());
    a.at("throttle").numbers[0] = 1.0;
    a.at("steer").numbers[0] = 1.0;
    r = env.step(a);
    if (r.done()) break;
  }
  ASSERT_TRUE(r.terminated) << "the episode ends at the barrier or off the track";
  EXPECT_TRUE(r.info.collided || r.info.off_track);
  EXPECT_LT(r.reward, 0.0);
}

TEST(RlEnv, TheTimeLimitTruncates) {
  rl::EnvOptions options = stateOptions();
  options.termination.time_limit = 2.0;
  rl::RacingEnv env(sprint(), test::sedan(), options);
  env.reset(1);
  int steps = 0;
  rl::StepResult r;
  do {
    r = env.step(rl::zeros(env.actionSpace()));
    ++steps;
  } while (!r.done() && steps < 1000);
  EXPECT_TRUE(r.truncated);
  EXPECT_FALSE(r.terminated);
  EXPECT_EQ(steps, 40) << "2 s of 0.05 s steps";
}

TEST(RlEnv, AnActionOutsideTheSpaceIsRejectedAndNothingMoves) {
  rl::RacingEnv env(sprint(), test::sedan(), stateOptions());
  EXPECT_NE(test::errorOf([&] { env.step(rl::zeros(env.actionSpace())); }).find("before the first reset"),
            std::string::npos);
  env.reset(2);
  const std::uint64_t tick = env.world().tick();
  Value a = rl::zeros(env.actionSpace());
  a.at("steer").numbers[0] = 1.5;
  EXPECT_EQ(test::errorOf([&] { env.step(a); }), "action['steer'][0] = 1.5 is outside [-1, 1]");
  a.at("steer").numbers[0] = std::nan("");
  EXPECT_EQ(test::errorOf([&] { env.step(a); }), "action['steer'][0] is NaN");
  Value missing = rl::zeros(env.actionSpace());
  missing.keys.erase(missing.keys.begin());
  missing.entries.erase(missing.entries.begin());
  EXPECT_EQ(test::errorOf([&] { env.step(missing); }), "action['brake'] is missing");
  Value gear = rl::zeros(env.actionSpace());
  gear.at("target_gear") = Value::of({2});
  EXPECT_EQ(test::errorOf([&] { env.step(gear); }), "action: unknown key 'target_gear'");
  EXPECT_EQ(env.world().tick(), tick);
}

TEST(RlVectorEnv, StepsInParallelLikeOneAtATimeAndResetsFinishedEpisodes) {
  rl::EnvOptions options = stateOptions();
  options.termination.time_limit = 1.0;  // every 20 steps
  auto make = [&](int n, int threads) {
    std::vector<std::unique_ptr<rl::RacingEnv>> envs;
    for (int i = 0; i < n; ++i) envs.push_back(std::make_unique<rl::RacingEnv>(sprint(), test::sedan(), options));
    return rl::VectorEnv(std::move(envs), threads);
  };
  rl::VectorEnv parallel = make(4, 2), serial = make(4, 1);
  std::vector<rl::ResetResult> p0 = parallel.reset(100), s0 = serial.reset(100);
  std::vector<Value> po, so;
  for (std::size_t i = 0; i < 4; ++i) {
    po.push_back(p0[i].observation);
    so.push_back(s0[i].observation);
    EXPECT_EQ(p0[i].info.track_s, serial.env(i).reset(100 + i).info.track_s) << "env i is seeded with seed + i";
  }
  serial.reset(100);
  int finished = 0;
  for (int step = 0; step < 30; ++step) {
    std::vector<Value> pa, sa;
    for (std::size_t i = 0; i < 4; ++i) {
      pa.push_back(chase(parallel.actionSpace(), po[i]));
      sa.push_back(chase(serial.actionSpace(), so[i]));
    }
    const rl::VectorStepResult pr = parallel.step(pa), sr = serial.step(sa);
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_EQ(pr.steps[i].reward, sr.steps[i].reward);
      EXPECT_EQ(pr.steps[i].info.track_s, sr.steps[i].info.track_s);
      po[i] = pr.steps[i].observation;
      so[i] = sr.steps[i].observation;
      if (pr.steps[i].done()) {
        ++finished;
        EXPECT_TRUE(pr.steps[i].truncated);
        ASSERT_TRUE(pr.final_observations[i].has_value());
        EXPECT_GT(pr.final_observations[i]->at("speed").numbers[0], 1.0) << "the last observation of the old episode";
        EXPECT_LT(po[i].at("speed").numbers[0], 0.05) << "the first of the new one, at rest";
      } else {
        EXPECT_FALSE(pr.final_observations[i].has_value());
      }
    }
  }
  EXPECT_EQ(finished, 4) << "each environment ended its 20-step episode once in 30 steps";
  std::vector<Value> bad(4, rl::zeros(parallel.actionSpace()));
  bad[2].at("brake").numbers[0] = -1;
  EXPECT_EQ(test::errorOf([&] { parallel.step(bad); }), "actions[2]['brake'][0] = -1 is outside [0, 1]");
}

// EnvPool's way: recv() hands back the first environments to be done; an environment stepped
// asynchronously gives the same results as one stepped in VectorEnv's lockstep (each is deterministic on
// its own), auto-resets the same way, and misuse is refused by name.
TEST(RlAsyncVectorEnv, BatchesAsTheyAreDoneWithTheSameResultsAsLockstep) {
  rl::EnvOptions options = stateOptions();
  options.termination.time_limit = 1.0;  // every 20 steps
  auto envs = [&](int n) {
    std::vector<std::unique_ptr<rl::RacingEnv>> out;
    for (int i = 0; i < n; ++i) out.push_back(std::make_unique<rl::RacingEnv>(sprint(), test::sedan(), options));
    return out;
  };
  rl::AsyncVectorEnv async(envs(4), 2);
  rl::VectorEnv lockstep(envs(4), 1);
  std::vector<rl::ResetResult> l0 = lockstep.reset(7);
  async.reset(7);
  EXPECT_EQ(async.inFlight(), 4u);
  std::vector<Value> ao(4), lo(4);
  for (const std::size_t id : async.recv(4)) ao[id] = async.result(id).step.observation;
  for (std::size_t i = 0; i < 4; ++i) {
    lo[i] = l0[i].observation;
    EXPECT_EQ(ao[i].at("speed").numbers, lo[i].at("speed").numbers);
  }
  // Lockstep reference: 30 steps of all four. Async: environments 0 and 1 stepped in batches of 1 and 2
  // as they come back, 2 and 3 in one batch, until each has done 30 steps.
  std::vector<std::vector<double>> lockstep_rewards(4), async_rewards(4);
  int finals = 0;
  for (int step = 0; step < 30; ++step) {
    std::vector<Value> actions;
    for (std::size_t i = 0; i < 4; ++i) actions.push_back(chase(lockstep.actionSpace(), lo[i]));
    const rl::VectorStepResult& r = lockstep.step(actions);
    for (std::size_t i = 0; i < 4; ++i) {
      lockstep_rewards[i].push_back(r.steps[i].reward);
      lo[i] = r.steps[i].observation;
    }
  }
  std::vector<int> steps(4, 0);
  auto sendOne = [&](std::size_t i) { async.send({chase(async.actionSpace(), ao[i])}, {i}); };
  for (std::size_t i = 0; i < 4; ++i) sendOne(i);
  while (async.inFlight() > 0) {
    const std::size_t batch = async.inFlight() >= 2 ? 2 : 1;
    for (const std::size_t id : async.recv(batch)) {
      ASSERT_LT(id, 4u);
      const rl::AsyncResult& r = async.result(id);
      EXPECT_EQ(r.env_id, id);
      async_rewards[id].push_back(r.step.reward);
      ao[id] = r.step.observation;
      if (r.final_observation) ++finals;
      if (++steps[id] < 30) sendOne(id);
    }
  }
  EXPECT_EQ(async_rewards, lockstep_rewards);
  EXPECT_EQ(finals, 4) << "each environment ended its 20-step episode once and was reset";
  // Misuse, refused by name with nothing sent.
  async.send({chase(async.actionSpace(), ao[1])}, {1});
  EXPECT_NE(test::errorOf([&] {
              async.send({chase(async.actionSpace(), ao[1])}, {1});
            }).find("environment 1 is still stepping"),
            std::string::npos);
  EXPECT_NE(test::errorOf([&] { async.send({rl::zeros(async.actionSpace())}, {9}); }).find("env_ids[0] = 9"),
            std::string::npos);
  EXPECT_NE(test::errorOf([&] { async.recv(2); }).find("batch_size 2 with 1 environment(s) in flight"),
            std::string::npos);
  std::vector<Value> bad(1, rl::zeros(async.actionSpace()));
  bad[0].at("brake").numbers[0] = -1;
  EXPECT_EQ(test::errorOf([&] { async.send(bad, {2}); }), "actions[0]['brake'][0] = -1 is outside [0, 1]");
  EXPECT_EQ(async.inFlight(), 1u);
  EXPECT_EQ(async.recv(1).front(), 1u);
}

// A learner's thread is away in its own code between recv() and send(): the workers step every environment
// sent meanwhile, its own share included, so no core idles while work waits.
TEST(RlAsyncVectorEnv, WorkersStepTheCallersEnvironmentsWhileItIsAway) {
  std::vector<std::unique_ptr<rl::RacingEnv>> envs;
  for (int i = 0; i < 4; ++i) envs.push_back(std::make_unique<rl::RacingEnv>(sprint(), test::sedan(), stateOptions()));
  rl::AsyncVectorEnv async(std::move(envs), 2);  // the caller's thread and one worker
  async.reset(3);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (async.ready() < 4 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_EQ(async.ready(), 4u) << "environments waited for the caller to come back";
  const std::vector<std::size_t> ids = async.recv(4);
  std::vector<Value> actions;
  for (const std::size_t id : ids) actions.push_back(chase(async.actionSpace(), async.result(id).step.observation));
  async.send(actions, ids);
  while (async.ready() < 4 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_EQ(async.ready(), 4u);
  EXPECT_EQ(async.recv(4).size(), 4u);
}

// A result sink copies each result where the caller wants it, on the thread that stepped it, before recv()
// can return it: results are numbered in the order recv() returns them, batch after batch, each once, and
// with the caller's thread away the worker's thread copies what it stepped.
TEST(RlAsyncVectorEnv, ASinkCopiesEachResultBeforeRecvReturnsItNumberedInRecvsOrder) {
  std::vector<std::unique_ptr<rl::RacingEnv>> envs;
  for (int i = 0; i < 4; ++i) envs.push_back(std::make_unique<rl::RacingEnv>(sprint(), test::sedan(), stateOptions()));
  rl::AsyncVectorEnv async(std::move(envs), 2);
  async.reset(5);
  async.recv(4);
  const std::size_t first = async.received();
  EXPECT_EQ(first, 4u);
  constexpr std::size_t kResults = 4 * 25;
  std::vector<std::size_t> ids(kResults, 99);
  std::vector<double> speeds(kResults, -1.0);
  std::vector<std::thread::id> copiers(kResults);
  std::vector<int> calls(kResults, 0);
  async.setResultSink([&](std::size_t number, const rl::AsyncResult& r) {
    if (number < first || number - first >= kResults) return;  // the misuse check's, at the end
    ids[number - first] = r.env_id;
    speeds[number - first] = r.step.observation.at("speed").numbers[0];
    copiers[number - first] = std::this_thread::get_id();
    ++calls[number - first];
  });
  std::vector<Value> actions;
  for (std::size_t i = 0; i < 4; ++i) actions.push_back(chase(async.actionSpace(), async.result(i).step.observation));
  async.send(actions, {0, 1, 2, 3});
  std::size_t next = 0;
  bool worker_copied = false;
  while (next < kResults) {
    // Away from the pool for a moment now and then: the worker steps (and copies) meanwhile.
    if (next % 8 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const std::vector<std::size_t> done = async.recv(2);
    std::vector<Value> again;
    for (const std::size_t id : done) {
      ASSERT_EQ(ids[next], id) << "result " << next << ": recv() returns results in their numbers' order";
      EXPECT_EQ(speeds[next], async.result(id).step.observation.at("speed").numbers[0]) << "copied before recv()";
      worker_copied = worker_copied || copiers[next] != std::this_thread::get_id();
      ++next;
      again.push_back(chase(async.actionSpace(), async.result(id).step.observation));
    }
    if (next + async.inFlight() + done.size() <= kResults) async.send(again, done);
  }
  while (async.inFlight() > 0) async.recv(async.inFlight());
  for (std::size_t k = 0; k < kResults; ++k) EXPECT_EQ(calls[k], 1) << "result " << k;
  EXPECT_TRUE(worker_copied) << "every result was copied by the caller's thread";
  EXPECT_NE(test::errorOf([&] {
              async.send({chase(async.actionSpace(), async.result(0).step.observation)}, {0});
              async.setResultSink(nullptr);
            }).find("in flight"),
            std::string::npos);
  async.recv(1);
}

TEST(RlEnv, EveryNumberOfTheOptionsAtEveryExtremeIsRefusedByNameOrStepsFinite) {
  // Property test (issue 17): each number of config/rl/state.yaml set to 0, -1, 1e-30, 1e30, 1e300, NaN
  // and inf in turn: refused naming the key, or an environment whose observations and rewards stay finite
  // for 200 steps of a driver chasing the waypoints.
  std::ifstream file(test::sourceDir() + "/config/rl/state.yaml");
  const std::string original((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::regex number(R"(([a-z_]+): \[?(-?[0-9.]+))");
  int refused = 0, stepped = 0, fields = 0;
  fields = test::forEachNumberAtExtremes(
      original, number, [&](const std::string& key, const std::string& text, const std::string& extreme) {
        const std::string what = key + " = " + extreme;
        std::unique_ptr<rl::RacingEnv> env;
        try {
          env = std::make_unique<rl::RacingEnv>(sprint(), test::sedan(), rl::parseEnvOptions(text, "state.yaml"));
        } catch (const std::exception& e) {
          EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << what << ": " << e.what();
          ++refused;
          return;
        }
        ++stepped;
        auto finite = [](const Value& v, const auto& self) -> bool {
          for (double x : v.numbers) {
            if (!std::isfinite(x)) return false;
          }
          for (const auto& inner : v.entries) {
            if (!self(inner, self)) return false;
          }
          return true;
        };
        Value obs = env->reset(3).observation;
        ASSERT_TRUE(finite(obs, finite)) << what << ": the first observation";
        for (int k = 0; k < 200; ++k) {
          const rl::StepResult r = env->step(chase(env->actionSpace(), obs));
          ASSERT_TRUE(std::isfinite(r.reward) && finite(r.observation, finite)) << what << ": step " << k;
          obs = r.done() ? env->reset().observation : r.observation;
        }
      });
  std::printf("rl options property test: %d numbers x 7 extremes: %d refused by name, %d stepped finite\n", fields,
              refused, stepped);
}

// The hand-back of results takes no lock: with more threads than cores (so waiting threads sleep and are
// woken rather than spin) and batches of every size, each environment sent comes back exactly once, numbered
// in order without a gap, and none is lost or waits for ever.
TEST(RlAsyncVectorEnv, ManyThreadsOnFewCoresHandEachResultBackOnce) {
  rl::EnvOptions options = stateOptions();
  options.termination.time_limit = 0.5;  // auto-resets along the way
  const std::size_t count = 12;
  std::vector<std::unique_ptr<rl::RacingEnv>> envs;
  for (std::size_t i = 0; i < count; ++i)
    envs.push_back(std::make_unique<rl::RacingEnv>(sprint(), test::sedan(), options));
  const int threads = static_cast<int>(std::thread::hardware_concurrency()) * 4;
  rl::AsyncVectorEnv async(std::move(envs), threads);
  std::vector<std::size_t> numbers_seen;
  std::mutex numbers_mutex;
  async.setResultSink([&](std::size_t number, const rl::AsyncResult&) {
    std::lock_guard<std::mutex> lock(numbers_mutex);
    numbers_seen.push_back(number);
  });
  async.reset(5);
  std::vector<int> in_flight(count, 1), sent(count, 1), returned(count, 0);
  auto receive = [&](std::size_t batch, std::vector<Value>* actions) {
    const std::size_t before = async.received();
    const std::vector<std::size_t> ids = async.recv(batch);
    EXPECT_EQ(ids.size(), batch);
    EXPECT_EQ(async.received(), before + batch);
    for (const std::size_t id : ids) {
      EXPECT_LT(id, count);
      if (id >= count) continue;
      EXPECT_EQ(in_flight[id], 1) << "environment " << id << " came back without being sent";
      in_flight[id] = 0;
      ++returned[id];
      EXPECT_EQ(async.result(id).env_id, id);
      if (actions) actions->push_back(chase(async.actionSpace(), async.result(id).step.observation));
    }
    return ids;
  };
  auto sendBack = [&](const std::vector<Value>& actions, const std::vector<std::size_t>& ids) {
    async.send(actions, ids);
    for (const std::size_t id : ids) in_flight[id] = 1, ++sent[id];
  };
  std::size_t batch = 1;
  std::vector<Value> held_action;
  std::vector<std::size_t> held;  // one environment kept back a round, so fewer are in flight for a while
  for (int round = 0; round < 400 && !HasFailure(); ++round) {
    batch = batch % async.inFlight() + 1;  // 1, 2, ... up to all in flight
    std::vector<Value> actions;
    std::vector<std::size_t> ids = receive(batch, &actions);
    if (!held.empty()) sendBack(held_action, held), held.clear(), held_action.clear();
    if (round % 2 == 1 && async.inFlight() + ids.size() >= 2) {
      held = {ids.back()}, held_action = {actions.back()};
      ids.pop_back(), actions.pop_back();
    }
    if (!ids.empty()) sendBack(actions, ids);
  }
  if (!held.empty()) sendBack(held_action, held);
  receive(async.inFlight(), nullptr);
  for (std::size_t i = 0; i < count; ++i) EXPECT_EQ(returned[i], sent[i]) << "environment " << i;
  std::sort(numbers_seen.begin(), numbers_seen.end());
  for (std::size_t k = 0; k < numbers_seen.size(); ++k) ASSERT_EQ(numbers_seen[k], k) << "result numbers have a gap";
  EXPECT_EQ(numbers_seen.size(), async.received());
}

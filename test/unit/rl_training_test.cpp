// The MLP policy and its file, and evolution strategies learning on a small track.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "roar/rl/evolution.h"
#include "roar/rl/policy.h"
#include "roar/rl/policy_laps.h"
#include "test_support.h"

using namespace roar;

namespace {

rl::EnvOptions shortEpisodes() {
  rl::EnvOptions o;
  o.world.control_timeout = 0.0;
  o.termination.time_limit = 8.0;
  o.observation.waypoint_distances = {5, 15, 30};
  return o;
}

std::string tempPath(const std::string& name) { return ::testing::TempDir() + "/" + name; }

}  // namespace

TEST(RlPolicy, OutputsStayInRangeAndTheFileRoundTripsExactly) {
  rl::ObservationOptions observation;
  observation.waypoint_distances = {10, 20};
  rl::MlpPolicy policy(observation, {6, 4});
  EXPECT_EQ(policy.inputs(), 1u + 3u + 3u + 2u * 4u);
  EXPECT_EQ(policy.params().size(), 6u * (policy.inputs() + 1) + 4u * 7u + 2u * 5u);
  std::mt19937 rng(5);
  for (float& p : policy.params()) p = std::normal_distribution<float>(0.0f, 2.0f)(rng);
  std::vector<float> obs(policy.inputs(), 30.0f);
  const auto out = policy.outputs(obs);
  EXPECT_LE(std::abs(out[0]), 1.0f);
  EXPECT_LE(std::abs(out[1]), 1.0f);
  const std::string path = tempPath("policy.yaml");
  policy.save(path);
  const rl::MlpPolicy back = rl::MlpPolicy::load(path);
  EXPECT_EQ(back.params(), policy.params());
  EXPECT_EQ(back.hidden(), policy.hidden());
  EXPECT_EQ(back.observation().waypoint_distances, observation.waypoint_distances);
  EXPECT_EQ(back.outputs(obs), out);
  // The action: pedal above zero is throttle, below it brake.
  const rl::Space actions = rl::actionSpace({}, 8);
  const rl::Value a = back.act(actions, rl::unflatten(back.observationSpace(), obs));
  EXPECT_TRUE(rl::contains(actions, a));
  EXPECT_EQ(a.at("throttle").numbers[0] > 0.0, out[1] > 0.0f);
  EXPECT_EQ(a.at("brake").numbers[0] > 0.0, out[1] < 0.0f);
  EXPECT_NE(test::errorOf([&] {
              back.act(rl::actionSpace({true}, 8), rl::unflatten(back.observationSpace(), obs));
            }).find("automatic gearbox"),
            std::string::npos);
}

TEST(RlPolicy, BrokenFilesAreNamed) {
  auto write = [](const std::string& name, const std::string& text) {
    std::ofstream(tempPath(name)) << text;
    return tempPath(name);
  };
  rl::MlpPolicy good(rl::ObservationOptions(), {4});
  good.save(tempPath("good.yaml"));
  std::ifstream in(tempPath("good.yaml"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(test::errorOf([&] {
              rl::MlpPolicy::load(write("wrong.yaml", "format: something else\n"));
            }).find("not a policy file"),
            std::string::npos);
  std::string short_params = text.substr(0, text.find("params:")) + "params: [1, 2, 3]\n";
  const std::string e = test::errorOf([&] { rl::MlpPolicy::load(write("short.yaml", short_params)); });
  EXPECT_NE(e.find("short.yaml: params: 3 numbers, the network needs"), std::string::npos) << e;
  std::string bad_obs = text;
  bad_obs.replace(bad_obs.find("speed: true"), 11, "sped: true");
  EXPECT_NE(test::errorOf([&] {
              rl::MlpPolicy::load(write("obs.yaml", bad_obs));
            }).find("observation.sped: is not a known key (did you mean 'speed'?)"),
            std::string::npos);
  EXPECT_NE(test::errorOf([&] { rl::MlpPolicy::load("/nonexistent/policy.yaml"); }).find("/nonexistent/policy.yaml"),
            std::string::npos);
  // The one strict reader: a misspelt or foreign key is refused, and so is a number no float holds.
  std::string misspelt = text;
  misspelt.replace(misspelt.find("spread:"), 7, "sprad:");
  const std::string m = test::errorOf([&] { rl::MlpPolicy::load(write("misspelt.yaml", misspelt)); });
  EXPECT_NE(m.find("misspelt.yaml: spread: is missing (is 'sprad' a misspelling of it?)"), std::string::npos) << m;
  const std::string f =
      test::errorOf([&] { rl::MlpPolicy::load(write("foreign.yaml", text + "learning_rate: 0.1\n")); });
  EXPECT_NE(f.find("foreign.yaml: learning_rate: is not a known key"), std::string::npos) << f;
  std::string huge = text;  // the first parameter replaced by 1e300, the count kept
  const std::size_t first = huge.find("params: [") + 9;
  huge.replace(first, huge.find(',', first) - first, "1e300");
  const std::string h = test::errorOf([&] { rl::MlpPolicy::load(write("huge.yaml", huge)); });
  EXPECT_NE(h.find("huge.yaml: params: "), std::string::npos) << h;
  EXPECT_NE(h.find("is not a finite float"), std::string::npos) << h;
  std::string zero_layer = text;
  zero_layer.replace(zero_layer.find("hidden: [4]"), 11, "hidden: [0]");
  const std::string z = test::errorOf([&] { rl::MlpPolicy::load(write("zero.yaml", zero_layer)); });
  EXPECT_NE(z.find("zero.yaml: hidden: a hidden layer needs 1 to 4096 units, not 0"), std::string::npos) << z;
}

TEST(RlEvolution, AShortRunOnASmallTrackImprovesTheReturn) {
  const track::Track circle = test::circleTrack(50.0, 12.0);
  const vehicle::VehicleParams sedan = test::sedan();
  auto make = [&] { return std::make_unique<rl::RacingEnv>(circle, sedan, shortEpisodes()); };
  rl::EvolutionOptions options;
  options.directions = 6;
  options.hidden = {8};
  options.learning_rate = 0.05;
  options.seed = 3;
  options.threads = 2;
  rl::EvolutionStrategy es(make, options);
  auto env = make();
  auto score = [&](const rl::MlpPolicy& policy) {
    double total = 0.0;
    for (std::uint64_t seed : {11u, 12u, 13u}) total += rl::rollout(*env, policy, seed).episode_return;
    return total / 3.0;
  };
  const double before = score(es.policy());
  std::vector<rl::GenerationReport> reports;
  for (int g = 0; g < 6; ++g) reports.push_back(es.runGeneration());
  const double after = score(es.policy());
  EXPECT_EQ(reports.back().generation, 6);
  EXPECT_GT(reports.front().env_steps, 0);
  EXPECT_GT(after, before + 100.0) << "before " << before << ", after " << after;
  EXPECT_GT(reports.back().mean_return, reports.front().mean_return);

  // Deterministic for a seed: a second run takes the same steps.
  rl::EvolutionStrategy again(make, options);
  for (int g = 0; g < 2; ++g) again.runGeneration();
  rl::EvolutionStrategy first(make, options);
  for (int g = 0; g < 2; ++g) first.runGeneration();
  EXPECT_EQ(again.policy().params(), first.policy().params());
}

// rl_train's test and a batch's policy cell: laps from the pole position, judged as race control judges a car.
TEST(RlPolicyLaps, FromThePoleJudgedAsRaceControlJudges) {
  const track::Track circle = test::circleTrack(50.0, 12.0);
  rl::ObservationOptions observation;
  observation.waypoint_distances = {5, 15};
  rl::MlpPolicy standing(observation, {1});  // zero weights: steer 0, pedal 0
  const rl::EnvOptions options = rl::lapEnvironment(shortEpisodes(), standing, 6.0);
  EXPECT_EQ(options.spawn, rl::SpawnMode::kGrid);
  EXPECT_EQ(options.observation.waypoint_distances, observation.waypoint_distances);
  rl::RacingEnv env(circle, test::sedan(), options);
  const rl::PolicyLaps stood = rl::driveLaps(env, standing, 2);
  EXPECT_TRUE(stood.clean);
  EXPECT_TRUE(stood.laps.empty());
  EXPECT_EQ(stood.best(), 0.0);
  EXPECT_TRUE(stood.ended == "time limit" || stood.ended == "stalled") << stood.ended;
  EXPECT_NEAR(stood.sim_time, 6.0, 0.06);

  rl::MlpPolicy floored = standing;
  floored.params().back() = 5.0f;  // the pedal's bias: full throttle, straight ahead off the circle
  const rl::PolicyLaps left = rl::driveLaps(env, floored, 2);
  EXPECT_FALSE(left.clean);
  EXPECT_TRUE(left.ended == "off track" || left.ended == "collision") << left.ended;
  EXPECT_LT(left.sim_time, 6.0);
  EXPECT_GT(left.progress, 1.0);
}

// Spaces, actions and environment files of the RL module.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "roar/rl/action.h"
#include "roar/rl/env_options.h"
#include "roar/rl/observation.h"
#include "roar/rl/space.h"
#include "test_support.h"

using namespace roar;
using rl::Space;
using rl::Value;

namespace {

Space mixedSpace() {
  return Space::dict({{"speed", Space::box(0.0, 100.0, {1})},
                      {"gear", Space::discrete(5, 1)},
                      {"flags", Space::multiBinary(2)},
                      {"nested", Space::dict({{"b", Space::box(-1.0, 1.0, {2, 2})},
                                              {"a", Space::box(0.0, 255.0, {3}, rl::DType::kUInt8)}})}});
}

}  // namespace

TEST(RlSpace, DictKeysAreSortedAndFlattenLikeGymnasium) {
  const Space s = mixedSpace();
  EXPECT_EQ(s.keys, (std::vector<std::string>{"flags", "gear", "nested", "speed"}));
  EXPECT_EQ(s.at("nested").keys, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(s.elements(), 2u + 1u + (3u + 4u) + 1u);
  EXPECT_EQ(s.flatDim(), 2u + 5u + (3u + 4u) + 1u) << "a Discrete flattens one-hot";
  Value v;
  v.at("speed") = Value::of({42.0});
  v.at("gear") = Value::of({3});
  v.at("flags") = Value::of({1, 0});
  v.at("nested").at("b") = Value::of({0.5, -0.5, 0.25, 1.0});
  v.at("nested").at("a") = Value::of({0, 128, 255});
  rl::check(s, v);
  const std::vector<float> flat = rl::flatten(s, v);
  const std::vector<float> expected = {1, 0, /*gear 3 of 1..5*/ 0, 0, 1, 0, 0, 0, 128, 255, 0.5f, -0.5f, 0.25f, 1, 42};
  EXPECT_EQ(flat, expected);
  const Value back = rl::unflatten(s, flat);
  EXPECT_EQ(rl::flatten(s, back), flat);
  EXPECT_EQ(back.at("gear").numbers, std::vector<double>{3});
  const Space box = rl::flattenSpace(s);
  EXPECT_EQ(box.shape, std::vector<int>{15});
  EXPECT_EQ(box.high[2], 1.0) << "one-hot entries lie in [0, 1]";
  EXPECT_EQ(box.high[9], 255.0);
}

TEST(RlSpace, SamplesAndZerosLieInTheSpace) {
  const Space s = Space::dict({{"x", Space::box(-std::numeric_limits<double>::infinity(), 3.0, {4})},
                               {"y", Space::box(0.0, std::numeric_limits<double>::infinity(), {2})},
                               {"z", mixedSpace()}});
  std::mt19937_64 rng(3);
  for (int i = 0; i < 200; ++i) EXPECT_TRUE(rl::contains(s, rl::sample(s, rng)));
  EXPECT_TRUE(rl::contains(s, rl::zeros(s)));
  EXPECT_EQ(rl::zeros(Space::box(2.0, 5.0, {1})).numbers[0], 2.0) << "zero is outside: the lower bound";
}

TEST(RlSpace, ValuesOutsideTheSpaceAreNamed) {
  const Space s = mixedSpace();
  Value good = rl::zeros(s);
  auto errorWith = [&](const std::function<void(Value&)>& spoil) {
    Value v = good;
    spoil(v);
    return test::errorOf([&] { rl::check(s, v, "obs"); });
  };
  EXPECT_EQ(errorWith([](Value&) {}), "");
  EXPECT_EQ(errorWith([](Value& v) { v.at("speed").numbers[0] = 101; }), "obs['speed'][0] = 101 is outside [0, 100]");
  EXPECT_EQ(errorWith([](Value& v) { v.at("speed").numbers[0] = std::nan(""); }), "obs['speed'][0] is NaN");
  EXPECT_EQ(errorWith([](Value& v) { v.at("gear").numbers[0] = 6; }), "obs['gear'] = 6 is not one of 1 .. 5");
  EXPECT_EQ(errorWith([](Value& v) { v.at("gear").numbers[0] = 2.5; }), "obs['gear'] = 2.5 is not one of 1 .. 5");
  EXPECT_EQ(errorWith([](Value& v) { v.at("flags").numbers[1] = 0.5; }), "obs['flags'][1] = 0.5 is not 0 or 1");
  EXPECT_EQ(errorWith([](Value& v) { v.at("nested").at("b").numbers.pop_back(); }),
            "obs['nested']['b'] has 3 numbers; its space (shape [2, 2]) has 4");
  EXPECT_EQ(errorWith([](Value& v) { v.at("wings") = Value::of({1}); }), "obs: unknown key 'wings'");
  Value missing;
  missing.at("speed") = Value::of({1});
  EXPECT_NE(test::errorOf([&] { rl::check(s, missing, "obs"); }).find("obs['flags'] is missing"), std::string::npos);
  EXPECT_NE(test::errorOf([] { Space::box({1.0}, {0.0}, {1}); }).find("not an interval"), std::string::npos);
  EXPECT_NE(test::errorOf([] {
              Space::dict({{"a", Space::discrete(2)}, {"a", Space::discrete(3)}});
            }).find("'a' is given twice"),
            std::string::npos);
}

TEST(RlSpace, YamlDescribesTheSpaceInGymnasiumsTerms) {
  const std::string yaml =
      rl::toYaml(Space::dict({{"steer", Space::box(-1.0, 1.0, {1})}, {"gear", Space::discrete(6, 1)}}));
  EXPECT_EQ(yaml,
            "type: Dict\nspaces:\n"
            "  gear:\n    type: Discrete\n    dtype: int64\n    n: 6\n    start: 1\n"
            "  steer:\n    type: Box\n    dtype: float32\n    shape: [1]\n    low: [-1]\n    high: [1]\n");
  EXPECT_NE(rl::toYaml(Space::box(0.0, std::numeric_limits<double>::infinity(), {1})).find("high: [.inf]"),
            std::string::npos);
}

TEST(RlAction, RoarPysActionSpecAndItsControls) {
  const Space automatic = rl::actionSpace({}, 8);
  EXPECT_EQ(automatic.keys, (std::vector<std::string>{"brake", "hand_brake", "reverse", "steer", "throttle"}));
  EXPECT_EQ(automatic.at("throttle").low, std::vector<double>{0.0});
  EXPECT_EQ(automatic.at("steer").low, std::vector<double>{-1.0});
  EXPECT_EQ(automatic.at("reverse").kind, Space::Kind::kMultiBinary);
  const Space manual = rl::actionSpace({true}, 8);
  EXPECT_EQ(manual.at("target_gear").n, 8);
  EXPECT_EQ(manual.at("target_gear").start, 1);

  Value a = rl::zeros(manual);
  a.at("throttle").numbers[0] = 0.7;
  a.at("steer").numbers[0] = -0.25;
  a.at("hand_brake").numbers[0] = 0.6;
  a.at("target_gear").numbers[0] = 3;
  vehicle::VehicleControl c = rl::toControl(manual, a);
  EXPECT_EQ(c.throttle, 0.7);
  EXPECT_EQ(c.steer, -0.25);
  EXPECT_TRUE(c.hand_brake) << "above 0.5";
  EXPECT_TRUE(c.manual_gear_shift);
  EXPECT_EQ(c.gear, 3);
  a.at("reverse").numbers[0] = 1;
  EXPECT_EQ(rl::toControl(manual, a).gear, -1);
  EXPECT_FALSE(rl::toControl(automatic, rl::toAction(automatic, c)).manual_gear_shift);
  a.at("throttle").numbers[0] = 1.2;
  EXPECT_EQ(test::errorOf([&] { rl::toControl(manual, a); }), "action['throttle'][0] = 1.2 is outside [0, 1]");
}

TEST(RlEnvOptions, EveryShippedFileLoadsAndBadOnesNameTheKey) {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::sourceDir() + "/config/rl")) {
    if (entry.path().extension() != ".yaml") continue;
    const rl::EnvOptions o = rl::readEnvOptions(entry.path().string());
    EXPECT_FALSE(rl::observationSpace(o.observation).keys.empty()) << entry.path();
    ++files;
  }
  EXPECT_GE(files, 2);
  const rl::EnvOptions camera = rl::readEnvOptions(test::sourceDir() + "/config/rl/camera.yaml");
  EXPECT_EQ(camera.observation.camera.width, 84);
  EXPECT_EQ(camera.world.control_timeout, 0.0) << "the agent acts every step";

  auto error = [](const std::string& yaml) { return test::errorOf([&] { rl::parseEnvOptions(yaml, "bad.yaml"); }); };
  EXPECT_EQ(error("{}"), "");
  EXPECT_NE(error("observation: {camera: {widht: 84}}")
                .find("bad.yaml: observation.camera.widht: is not a known key (did you mean 'width'?)"),
            std::string::npos);
  EXPECT_NE(error("reward: {progress_weight: fast}").find("bad.yaml: reward.progress_weight: is not a number"),
            std::string::npos);
  EXPECT_NE(error("spawn: anywhere").find("bad.yaml: spawn: must be random or grid"), std::string::npos);
  EXPECT_NE(error("observation: {camera: {width: 84, height: 0}}")
                .find("bad.yaml: observation: camera.width and camera.height"),
            std::string::npos);
  EXPECT_NE(error("observation: {camera: {width: 84, height: 84, fov: 200}}").find("camera.fov must be in (0, 180)"),
            std::string::npos);
  EXPECT_NE(error("observation: {speed: false, velocity: false, angular_velocity: false, waypoint_distances: []}")
                .find("nothing is observed"),
            std::string::npos);
  EXPECT_NE(error("termination: {time_limit: -1}").find("termination.time_limit"), std::string::npos);
  EXPECT_NE(error("physics_dt: 0.1").find("physics_dt must be positive and no larger than control_dt"),
            std::string::npos);
  EXPECT_NE(error("observation: [1, 2]").find("bad.yaml: observation: must be a mapping"), std::string::npos);
  EXPECT_NE(
      test::errorOf([] { rl::readEnvOptions("/nonexistent/env.yaml"); }).find("/nonexistent/env.yaml: no such file"),
      std::string::npos);
}

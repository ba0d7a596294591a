// roar_bench: speed figures of roar_ros (Google Benchmark). Tests never check timings; this prints them.
//   PhysicsRealTimeFactor/cars:N  N sedans racing the default circuit (each tracking the planner's line),
//                                 one thread: real_time_factor = simulated seconds per wall second.
//   RayCast/incoherent|coherent   rays per second of the ray scene of the default circuit: LiDAR-like rays in
//                                 all directions, and camera rays in 4x4 pixel packets.
//   CameraFrame/...               one 84x84 RGB + depth + semantic frame (one cast), one 800x600 RGB frame.
//   SensorSuiteRealTimeFactor     one car driving with config/sensors/default.yaml: three 84x84 cameras at
//                                 20 Hz, a 32-laser LiDAR at 56,000 points/s, IMU and GNSS at 100 Hz.
//   PlanRacingTrajectory/<map>    the planner's start-up: minimum-curvature line and speed profile.
//   RlEnvSteps/camera:C/threads:T the RL environment's steps per second on Roar Sprint, state observations
//                                 (C=0) or with an 84x84 RGB camera (C=1), one environment on one thread
//                                 or two environments per thread on T threads.
// After the benchmarks, the racing table: the stack (planner, tracker, lap timer) races every shipped
// circuit in lockstep for --laps=N (default 10) and prints achieved and promised laps, the lap of a
// minimum-time line searched from the planner's (min_time; vs_min = promised / min_time), the car's
// quasi-steady-state bound on the minimum-curvature line (qss_bound, sim/lap_bound.h; vs_qss = best / bound),
// tracking error and barrier contacts; --model=NAME races that car (default the sedan), --maps-dir=DIR the
// circuits in DIR (imported ones) instead of the shipped ones; --grip-use=F overrides the share of the road's friction
// the plan uses,
// --stanley races with Stanley instead of pure pursuit,
// --minimum-time races the minimum-time line, --no-yardstick skips the minimum-time search (min_time 0). --race-only
// skips the benchmarks; --no-race skips the table.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <thread>

#include "roar/config/number.h"
#include "roar/config/package_layout.h"
#include "roar/control/tracker_sizing.h"
#include "roar/harness/time_trial.h"
#include "roar/planning/minimum_time.h"
#include "roar/rl/vector_env.h"
#include "roar/sensors/camera.h"
#include "roar/sensors/sensor_rig.h"
#include "roar/sensors/vehicle_looks.h"
#include "roar/sensors/vehicle_motion.h"
#include "roar/sim/lap_bound.h"
#include "roar/sim/world.h"
#include "roar/track/map_folder.h"
#include "roar/vehicle/vehicle_config.h"
#include "scaling_table.h"
#include "traffic_table.h"

using namespace roar;

namespace {

config::PackageLayout layout() {
  const char* env = std::getenv("ROAR_SOURCE_DIR");
  return {env ? env : ROAR_SOURCE_DIR};
}

// The car the benchmarks drive: the default model.
vehicle::VehicleParams defaultCar() {
  return vehicle::loadVehicleModel(config::kDefaultModel, layout().urdf(), layout().vehicles());
}

// A driver for the car on the track: the planner's racing trajectory and the tracker.
control::TrajectoryTracker racingDriver(const track::Track& track, const vehicle::VehicleParams& car) {
  const auto limits = planning::vehicleLimits(car, track.info().friction, harness::TimeTrialOptions().grip_use);
  control::TrajectoryTracker tracker(control::trackerFor(car), limits);
  tracker.setTrajectory(planning::planRacingTrajectory(track, limits, {}));
  return tracker;
}

control::TrackerInput trackerInput(const vehicle::VehicleState& s) {
  const Eigen::Vector3d forward = s.pose.orientation * Eigen::Vector3d::UnitX();
  return {s.pose.position.head<2>(), std::atan2(forward.y(), forward.x()), s.forward_speed,
          s.body_angular_velocity.z()};
}

void PhysicsRealTimeFactor(benchmark::State& state) {
  const int cars = static_cast<int>(state.range(0));
  const track::Track track = track::loadMapFolder(layout().maps() + "/" + config::kDefaultMap);
  const vehicle::VehicleParams car = defaultCar();
  sim::World world(track, {});
  const control::TrajectoryTracker driver = racingDriver(track, car);
  std::vector<control::TrajectoryTracker> drivers;
  std::vector<std::string> names;
  for (int i = 0; i < cars; ++i) {
    names.push_back("car" + std::to_string(i));
    // Spread round the lap so the cars do not queue behind each other.
    world.spawnVehicle(names.back(), car, track::poseOnTrack(track.poseAt(i * track.length() / cars)));
    drivers.push_back(driver);
  }
  std::int64_t ticks = 0;
  for (auto _ : state) {
    for (int i = 0; i < cars; ++i) {
      world.setControl(names[i], drivers[i].update(trackerInput(world.vehicleState(names[i]))));
    }
    world.step();
    ++ticks;
  }
  state.counters["real_time_factor"] =
      benchmark::Counter(static_cast<double>(ticks) * world.options().control_dt, benchmark::Counter::kIsRate);
  state.counters["car_seconds_per_s"] =
      benchmark::Counter(static_cast<double>(ticks) * world.options().control_dt * cars, benchmark::Counter::kIsRate);
}

track::Track defaultTrack() { return track::loadMapFolder(layout().maps() + "/" + config::kDefaultMap); }

// A sensor's pose: 1.9 m above the pole position, looking down the main straight.
Eigen::Isometry3d sensorPose(const track::Track& track) {
  const auto p = track.gridSpawnPoints(1)[0];
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x(), p.position.y(), 1.9);
  t.linear() = Eigen::AngleAxisd(p.heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return t;
}

void RayCast(benchmark::State& state) {
  const bool coherent = state.range(0) == 1;
  const track::Track track = defaultTrack();
  sensors::RayScene scene(track);
  const Eigen::Isometry3d pose = sensorPose(track);
  std::vector<Eigen::Vector3f> dirs;
  if (coherent) {
    sensors::CameraSpec spec;  // 800 x 600, 90 degrees: the rays in the renderer's 4x4 tile order
    const auto k = sensors::intrinsicsOf(spec);
    for (int ty = 0; ty < spec.height; ty += 4)
      for (int tx = 0; tx < spec.width; tx += 4)
        for (int y = ty; y < ty + 4; ++y)
          for (int x = tx; x < tx + 4; ++x) {
            const Eigen::Vector3d optical((x + 0.5 - k.cx) / k.fx, (y + 0.5 - k.cy) / k.fy, 1.0);
            dirs.push_back(
                (pose.linear() * sensors::opticalFromBody().transpose() * optical.normalized()).cast<float>());
          }
  } else {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> az(-M_PI, M_PI), el(-0.52f, 0.17f);  // LiDAR-like: -30..+10 degrees
    for (int i = 0; i < 480000; ++i) {
      const float a = az(rng), e = el(rng);
      dirs.emplace_back(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
    }
  }
  std::vector<sensors::RayHit> hits(dirs.size());
  for (auto _ : state) {
    scene.cast(pose.translation(), dirs.data(), dirs.size(), -1, 1000.0f, coherent, hits.data());
    benchmark::DoNotOptimize(hits.data());
  }
  state.counters["rays_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * dirs.size()), benchmark::Counter::kIsRate);
}

void CameraFrame(benchmark::State& state) {
  const bool small = state.range(0) == 84;
  const track::Track track = defaultTrack();
  sensors::RayScene scene(track);
  sensors::CameraSpec spec;
  spec.width = small ? 84 : 800;
  spec.height = small ? 84 : 600;
  sensors::CameraRenderer camera(spec);
  sensors::CameraChannels channels;
  channels.rgb = true;
  channels.depth = channels.semantic = small;
  sensors::CameraFrame frame;
  const Eigen::Isometry3d pose = sensorPose(track);
  for (auto _ : state) {
    camera.render(scene, pose, -1, channels, &frame);
    benchmark::DoNotOptimize(frame.rgb.data());
  }
}

// Counts nothing: the benchmark measures producing the readings, not publishing them.
struct NullSink : sensors::SensorSink {
  void camera(const sensors::SensorSpec&, double, const sensors::CameraFrame&,
              const sensors::CameraIntrinsics&) override {}
  void lidar(const sensors::SensorSpec&, double, const std::vector<sensors::LidarPoint>&) override {}
  void imu(const sensors::SensorSpec&, double, const sensors::ImuSample&) override {}
  void gnss(const sensors::SensorSpec&, double, const sensors::GnssFix&) override {}
  void velocity(const sensors::SensorSpec&, double, const sensors::Velocity&) override {}
  void vector(const sensors::SensorSpec&, double, const Eigen::Vector3d&) override {}
  void occupancy(const sensors::SensorSpec&, double, const sensors::OccupancyFrame&) override {}
};

void SensorSuiteRealTimeFactor(benchmark::State& state) {
  const track::Track track = defaultTrack();
  const vehicle::VehicleParams car = defaultCar();
  sim::World world(track, {});
  world.spawnVehicle("ego", car, track::poseOnTrack(track.gridSpawnPoints(1)[0]));
  sensors::RayScene scene(track);
  const int id = scene.addVehicle(sensors::readVehicleLooks(layout().urdf() + "/" + config::kDefaultModel + ".urdf"),
                                  {0.1f, 0.2f, 0.8f});
  sensors::SensorRig rig(sensors::readSensorSet(layout().sensors() + "/default.yaml"),
                         {world.options().control_dt, world.options().physics_dt, world.options().gravity},
                         track.info().origin);
  control::TrajectoryTracker driver = racingDriver(track, car);
  NullSink sink;
  std::int64_t ticks = 0;
  for (auto _ : state) {
    world.setControl("ego", driver.update(trackerInput(world.vehicleState("ego"))));
    world.step([&](double t) { rig.sampleMotion(t, sensors::motionOf(world.vehicleState("ego")), sink); });
    const Eigen::Isometry3d pose = sensors::poseOf(world.vehicleState("ego"));
    scene.setVehiclePose(id, pose);
    scene.commit();
    rig.sampleRays(world.time(), scene, pose, id, sink);
    ++ticks;
  }
  state.counters["real_time_factor"] =
      benchmark::Counter(static_cast<double>(ticks) * world.options().control_dt, benchmark::Counter::kIsRate);
}

}  // namespace

namespace {

// The RL environment on Roar Sprint: steps per second of one environment (one thread) and of a vectorised
// one (two environments per thread), observing config/rl/state.yaml (state and waypoints) or that plus an
// 84x84 RGB camera. The car chases the waypoint 10 m ahead, so it drives (and auto-resets) like an agent.
rl::EnvOptions benchEnv(bool camera) {
  rl::EnvOptions o = rl::readEnvOptions(layout().rl() + "/state.yaml");
  if (camera) {
    o.observation.camera.width = o.observation.camera.height = 84;
    o.observation.camera.rgb = true;
  }
  return o;
}

rl::Value chaseAction(const rl::Space& actions, const rl::Value& obs) {
  const auto& wp = obs.at("waypoints_information").at("waypoint_10").numbers;
  rl::Value a = rl::zeros(actions);
  a.at("throttle").numbers[0] = 0.6;
  a.at("steer").numbers[0] = std::clamp(1.5 * std::atan2(wp[1], wp[0]), -1.0, 1.0);
  return a;
}

void RlEnvSteps(benchmark::State& state) {
  const bool camera = state.range(0) == 1;
  const int threads = static_cast<int>(state.range(1));
  const track::Track track = track::loadMapFolder(layout().maps() + "/roar_sprint");
  const vehicle::VehicleParams car = defaultCar();
  std::vector<std::unique_ptr<rl::RacingEnv>> envs;
  const int count = threads == 1 ? 1 : 2 * threads;
  for (int i = 0; i < count; ++i) envs.push_back(std::make_unique<rl::RacingEnv>(track, car, benchEnv(camera)));
  rl::VectorEnv vec(std::move(envs), threads);
  std::vector<rl::Value> actions;
  for (auto& r : vec.reset(1)) actions.push_back(chaseAction(vec.actionSpace(), r.observation));
  std::int64_t steps = 0;
  for (auto _ : state) {
    // Acting on the results where they lie: VectorEnv::step writes the observations in place.
    const rl::VectorStepResult& r = vec.step(actions);
    for (std::size_t i = 0; i < actions.size(); ++i)
      actions[i] = chaseAction(vec.actionSpace(), r.steps[i].observation);
    steps += static_cast<std::int64_t>(actions.size());
  }
  state.counters["steps_per_s"] = benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsRate);
  state.counters["steps_per_s_per_thread"] =
      benchmark::Counter(static_cast<double>(steps) / threads, benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK(RlEnvSteps)
    ->ArgNames({"camera", "threads"})
    ->Args({0, 1})
    ->Args({0, 2})
    ->Args({1, 1})
    ->Args({1, 2})
    ->MinTime(3.0)
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

BENCHMARK(RayCast)->ArgName("coherent")->Arg(0)->Arg(1)->MinTime(2.0)->Unit(benchmark::kMillisecond);
BENCHMARK(CameraFrame)->ArgName("width")->Arg(84)->Arg(800)->MinTime(2.0)->Unit(benchmark::kMicrosecond);
BENCHMARK(SensorSuiteRealTimeFactor)->MinTime(3.0)->Unit(benchmark::kMicrosecond);
BENCHMARK(PhysicsRealTimeFactor)->ArgName("cars")->Arg(1)->Arg(10)->MinTime(3.0)->Unit(benchmark::kMicrosecond);

namespace {

void PlanRacingTrajectory(benchmark::State& state, const std::string& map) {
  const auto track = track::loadMapFolder(layout().maps() + "/" + map);
  const auto limits =
      planning::vehicleLimits(defaultCar(), track.info().friction, harness::TimeTrialOptions().grip_use);
  for (auto _ : state) benchmark::DoNotOptimize(planning::planRacingTrajectory(track, limits, {}));
  state.counters["track_km"] = track.length() / 1000.0;
}
BENCHMARK_CAPTURE(PlanRacingTrajectory, roar_ring, std::string("roar_ring"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(PlanRacingTrajectory, roar_speedway, std::string("roar_speedway"))->Unit(benchmark::kMillisecond);

struct RacingTableOptions {
  int laps = 10;
  double grip_use = harness::TimeTrialOptions().grip_use;
  control::LateralMethod lateral = control::TrackerOptions().lateral;
  bool minimum_time = false;  // the planner races the minimum-time line
  bool yardstick = true;      // the minimum-time search's lap beside the plan's
  std::string maps_dir;       // empty: the shipped maps
  std::string model = config::kDefaultModel;
};

void printRacingTable(const RacingTableOptions& table) {
  const std::string maps_dir = table.maps_dir.empty() ? layout().maps() : table.maps_dir;
  const auto car = vehicle::loadVehicleModel(table.model, layout().urdf(), layout().vehicles());
  std::printf("\nRacing stack, %s, %d laps per circuit, lockstep, grip_use %.2f, %s (lap times in simulated seconds)\n",
              table.model.c_str(), table.laps, table.grip_use,
              table.lateral == control::LateralMethod::kStanley ? "Stanley" : "pure pursuit");
  std::printf("%-16s %6s %9s %9s %9s %7s %9s %8s %9s %8s %10s %10s %9s\n", "circuit", "km", "best_lap", "mean_lap",
              "promised", "ratio", "min_time", "vs_min", "qss_bound", "vs_qss", "max_err_m", "rms_err_m", "contacts");
  for (const auto& map : track::listMaps(maps_dir)) {
    const auto track = track::loadMapFolder(maps_dir + "/" + map);
    harness::TimeTrialOptions options;
    options.laps = table.laps;
    options.grip_use = table.grip_use;
    options.tracker.lateral = table.lateral;
    options.planner.minimum_time = table.minimum_time;
    const auto r = harness::runTimeTrial(track, car, options);
    double mean = 0.0;
    for (double t : r.lap_times) mean += t / static_cast<double>(r.lap_times.size());
    // The yardstick: a minimum-time line searched from the planner's, with the same car model.
    const auto limits = planning::vehicleLimits(car, track.info().friction, options.grip_use);
    planning::MinimumTimeResult fastest;
    double bound = 0.0;
    if (track.closed()) {  // the search refines circuits' lines; the bound is a lap's
      const auto line = planning::minimumCurvatureLine(track, options.planner.line);
      if (table.yardstick) fastest = planning::minimumTimeLine(track, line, limits, options.planner.line);
      // The bound: the car's own model in quasi-steady state on the minimum-curvature line, no planner in it.
      bound = sim::quasiSteadyStateLap(line.curvature, line.step, true, car, track.info().friction).lap_time;
    }
    std::fflush(stdout);
    std::printf("%-16s %6.2f %9.2f %9.2f %9.2f %7.3f %9.2f %8.3f %9.2f %8.3f %10.2f %10.2f %9d%s\n", map.c_str(),
                track.raceDistance() / 1000.0, r.best_lap(), mean, r.promised_lap, mean / r.promised_lap,
                fastest.lap_time, fastest.lap_time > 0 ? r.promised_lap / fastest.lap_time : 0.0, bound,
                bound > 0 ? r.best_lap() / bound : 0.0, r.max_lateral_error, r.rms_lateral_error, r.barrier_contacts,
                r.finished ? "" : "  (did not finish)");
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  RacingTableOptions racing;
  bool race = true, benchmarks = true, traffic = false, scaling = false;
  bench::ScalingOptions scaling_options;
  scaling_options.max_threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  bench::TrafficTableOptions traffic_options;
  std::vector<char*> rest;
  // A bad value is refused before anything runs, naming the option.
  try {
    for (int i = 0; i < argc; ++i) {
      if (std::strncmp(argv[i], "--laps=", 7) == 0) {
        racing.laps = static_cast<int>(config::wholeNumberArgument("--laps", argv[i] + 7, 1));
      } else if (std::strncmp(argv[i], "--grip-use=", 11) == 0) {
        racing.grip_use = config::numberArgument("--grip-use", argv[i] + 11);
      } else if (std::strcmp(argv[i], "--no-yardstick") == 0) {
        racing.yardstick = false;
      } else if (std::strcmp(argv[i], "--minimum-time") == 0) {
        racing.minimum_time = true;
      } else if (std::strcmp(argv[i], "--stanley") == 0) {
        racing.lateral = control::LateralMethod::kStanley;
      } else if (std::strncmp(argv[i], "--maps-dir=", 11) == 0) {
        racing.maps_dir = argv[i] + 11;
      } else if (std::strncmp(argv[i], "--model=", 8) == 0) {
        racing.model = argv[i] + 8;
      } else if (std::strcmp(argv[i], "--race-only") == 0) {
        benchmarks = false;
      } else if (std::strcmp(argv[i], "--no-race") == 0) {
        race = false;
      } else if (std::strcmp(argv[i], "--traffic") == 0) {
        traffic = true;
        race = benchmarks = false;
      } else if (std::strncmp(argv[i], "--seeds=", 8) == 0) {
        traffic_options.seeds = static_cast<int>(config::wholeNumberArgument("--seeds", argv[i] + 8, 1));
      } else if (std::strncmp(argv[i], "--traffic-laps=", 15) == 0) {
        traffic_options.laps = static_cast<int>(config::wholeNumberArgument("--traffic-laps", argv[i] + 15, 1));
      } else if (std::strncmp(argv[i], "--pace-step=", 12) == 0) {
        traffic_options.pace_step = config::numberArgument("--pace-step", argv[i] + 12);
      } else if (std::strncmp(argv[i], "--map=", 6) == 0) {
        traffic_options.only_map = argv[i] + 6;
      } else if (std::strncmp(argv[i], "--field=", 8) == 0) {
        traffic_options.only_field = argv[i] + 8;
      } else if (std::strncmp(argv[i], "--overtake=", 11) == 0) {
        bench::setOvertakeOption(&traffic_options.overtake, argv[i] + 11);
      } else if (std::strcmp(argv[i], "--scaling") == 0) {
        scaling = true;
        race = benchmarks = false;
      } else if (std::strncmp(argv[i], "--max-threads=", 14) == 0) {
        scaling_options.max_threads = static_cast<int>(config::wholeNumberArgument("--max-threads", argv[i] + 14, 1));
      } else if (std::strncmp(argv[i], "--seconds=", 10) == 0) {
        scaling_options.seconds = std::max(0.5, config::numberArgument("--seconds", argv[i] + 10));
      } else if (std::strncmp(argv[i], "--envs-per-thread=", 18) == 0) {
        scaling_options.envs_per_thread =
            static_cast<int>(config::wholeNumberArgument("--envs-per-thread", argv[i] + 18, 1));
      } else if (std::strncmp(argv[i], "--repeats=", 10) == 0) {
        scaling_options.repeats = static_cast<int>(config::wholeNumberArgument("--repeats", argv[i] + 10, 1));
      } else if (std::strcmp(argv[i], "--verbose") == 0) {
        traffic_options.verbose = true;
      } else if (std::strcmp(argv[i], "--batch") == 0) {
        traffic_options.batch.enabled = true;
      } else if (std::strncmp(argv[i], "--batch-workers=", 16) == 0) {
        traffic_options.batch.enabled = true;
        traffic_options.batch.workers =
            static_cast<int>(config::wholeNumberArgument("--batch-workers", argv[i] + 16, 1, 256));
      } else if (std::strncmp(argv[i], "--scheduler=", 12) == 0) {
        traffic_options.batch.enabled = true;
        traffic_options.batch.scheduler = argv[i] + 12;
        if (traffic_options.batch.scheduler.rfind("tcp://", 0) != 0) {
          throw std::invalid_argument("--scheduler=" + traffic_options.batch.scheduler + ": expected tcp://HOST:PORT");
        }
      } else {
        rest.push_back(argv[i]);
      }
    }
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "roar_bench: %s\n", e.what());
    return 2;
  }
  int rest_count = static_cast<int>(rest.size());
  if (benchmarks) {
    benchmark::Initialize(&rest_count, rest.data());
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
  }
  if (race) {
    try {
      printRacingTable(racing);
    } catch (const std::exception& e) {  // a model or maps folder that cannot be read
      std::fprintf(stderr, "roar_bench: %s\n", e.what());
      return 2;
    }
  }
  if (scaling) {
    const track::Track sprint = track::loadMapFolder(layout().maps() + "/roar_sprint");
    const vehicle::VehicleParams car = defaultCar();
    bench::printScalingTable(
        [&](bool camera) { return std::make_unique<rl::RacingEnv>(sprint, car, benchEnv(camera)); }, chaseAction,
        scaling_options);
  }
  if (traffic) {
    try {
      bench::printTrafficTable(layout().maps(), layout().urdf(), layout().vehicles(), traffic_options);
    } catch (const std::invalid_argument& e) {  // a bad field or pace step, refused before any race
      std::fprintf(stderr, "roar_bench: %s\n", e.what());
      return 2;
    } catch (const std::runtime_error& e) {  // the batch failed
      std::fprintf(stderr, "roar_bench: --traffic as a batch: %s\n", e.what());
      return 1;
    }
  }
  return 0;
}

// roar_bench: speed figures of roar_ros (Google Benchmark). Tests never check timings; this prints them.
//   PhysicsRealTimeFactor/cars:N  N sedans driving the default circuit (each with the centre-line follower),
//                                 one thread: real_time_factor = simulated seconds per wall second.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "roar/control/centreline_follower.h"
#include "roar/sim/vehicle_config.h"
#include "roar/sim/world.h"
#include "roar/track/map_folder.h"

using namespace roar;

namespace {

std::string sourceDir() {
  const char* env = std::getenv("ROAR_SOURCE_DIR");
  return env ? env : ROAR_SOURCE_DIR;
}

void PhysicsRealTimeFactor(benchmark::State& state) {
  const int cars = static_cast<int>(state.range(0));
  const track::Track track = track::loadMapFolder(sourceDir() + "/maps/roar_ring");
  const sim::VehicleParams car =
      sim::loadVehicleModel("sedan", sourceDir() + "/urdf", sourceDir() + "/config/vehicles");
  sim::World world(track, {});
  control::FollowerOptions fo;
  fo.wheelbase = car.wheelbase();
  fo.max_steer_angle = car.steering.max_angle;
  std::vector<std::unique_ptr<control::CentrelineFollower>> drivers;
  std::vector<std::string> names;
  for (int i = 0; i < cars; ++i) {
    names.push_back("car" + std::to_string(i));
    // Spread round the lap so the cars do not queue behind each other.
    world.spawnVehicle(names.back(), car, sim::poseOnTrack(track.poseAt(i * track.length() / cars)));
    drivers.push_back(std::make_unique<control::CentrelineFollower>(track, fo));
  }
  std::int64_t ticks = 0;
  for (auto _ : state) {
    for (int i = 0; i < cars; ++i) {
      const auto s = world.vehicleState(names[i]);
      const Eigen::Vector3d fwd = s.pose.orientation * Eigen::Vector3d::UnitX();
      world.setControl(names[i],
                       drivers[i]->update({s.pose.position.head<2>(), std::atan2(fwd.y(), fwd.x()), s.forward_speed}));
    }
    world.step();
    ++ticks;
  }
  state.counters["real_time_factor"] =
      benchmark::Counter(static_cast<double>(ticks) * world.options().control_dt, benchmark::Counter::kIsRate);
  state.counters["car_seconds_per_s"] = benchmark::Counter(static_cast<double>(ticks) * world.options().control_dt * cars,
                                                           benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK(PhysicsRealTimeFactor)->ArgName("cars")->Arg(1)->Arg(10)->MinTime(3.0)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();

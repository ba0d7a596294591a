// roar_core.run_time_trial and roar_core.run_race: a map's time trial or race, run through the C++ stack in
// this process (harness::runTimeTrial, harness::runRace) with the GIL released, results as plain dicts.
#include "race_binding.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "roar/control/tracker_option_table.h"
#include "roar/harness/race.h"
#include "roar/harness/time_trial.h"
#include "roar/harness/traffic.h"
#include "roar/planning/overtaking/option_table.h"
#include "roar/track/map_folder.h"
#include "roar/track/pose.h"
#include "roar/vehicle/vehicle_config.h"

namespace py = pybind11;
using namespace roar;

namespace {

struct Setup {
  track::Track track;
  vehicle::VehicleParams vehicle;
};

Setup setUp(const std::string& map, const std::string& maps_dir, const std::string& model, const std::string& urdf_dir,
            const std::string& config_dir) {
  return {track::loadMapFolder(track::resolveMapFolder(map, maps_dir)),
          vehicle::loadVehicleModel(model, urdf_dir, config_dir)};
}

void checkRace(int laps, double grip_use) {
  if (laps < 1 || laps > 100) throw py::value_error("laps must be 1 to 100, got " + std::to_string(laps));
  if (!(grip_use > 0.0 && grip_use <= 1.0))
    throw py::value_error("grip_use must be in (0, 1], got " + std::to_string(grip_use));
}

// Settings of control::setTrackerOption by name ({"lookahead_time": 0.4, "lateral_control": "stanley"}) applied
// to `options`: a ValueError naming the option.
void setTrackerOptions(control::TrackerOptions* options, const py::dict& settings) {
  for (const auto& [key, value] : settings) {
    if (py::isinstance<py::bool_>(value))
      throw py::value_error("controller " + std::string(py::str(key)) + ": True/False is not a number or a law");
    try {
      control::setTrackerOption(options, py::str(key), py::str(value), "controller");
    } catch (const std::invalid_argument& e) {
      throw py::value_error(e.what());
    }
  }
}

py::dict runTimeTrial(const std::string& map, const std::string& maps_dir, const std::string& model,
                      const std::string& urdf_dir, const std::string& config_dir, int laps, double grip_use,
                      const py::dict& controller, bool trace) {
  checkRace(laps, grip_use);
  harness::TimeTrialOptions options;
  options.laps = laps;
  options.grip_use = grip_use;
  setTrackerOptions(&options.tracker, controller);
  // Per tick: t, x, y, yaw, speed, steer, throttle, brake (columns of the `trace` array).
  std::vector<std::array<double, 8>> ticks;
  if (trace) {
    options.on_tick = [&ticks](double t, const vehicle::VehicleState& s) {
      const auto& c = s.applied_control;
      ticks.push_back({t, s.pose.position.x(), s.pose.position.y(), track::yawOf(s.pose.orientation), s.speed, c.steer,
                       c.throttle, c.brake});
    };
  }
  const Setup setup = setUp(map, maps_dir, model, urdf_dir, config_dir);
  harness::TimeTrialResult r;
  {
    py::gil_scoped_release unlocked;
    r = harness::runTimeTrial(setup.track, setup.vehicle, options);
  }
  py::dict d;
  d["finished"] = r.finished;
  d["lap_times"] = r.lap_times;
  d["best_lap"] = r.best_lap();
  d["promised_lap"] = r.promised_lap;
  d["barrier_contacts"] = r.barrier_contacts;
  d["worst_offroad"] = r.worst_offroad;
  d["max_lateral_error"] = r.max_lateral_error;
  d["rms_lateral_error"] = r.rms_lateral_error;
  d["sim_time"] = r.sim_time;
  if (trace) {
    py::array_t<double> columns({static_cast<py::ssize_t>(ticks.size()), static_cast<py::ssize_t>(8)});
    std::copy(ticks.begin(), ticks.end(), reinterpret_cast<std::array<double, 8>*>(columns.mutable_data()));
    d["trace"] = columns;
  }
  return d;
}

harness::RaceCar raceCar(const py::dict& car, std::size_t index) {
  harness::RaceCar c;
  const std::string where = "cars[" + std::to_string(index) + "]";
  for (const auto& [key, value] : car) {
    const std::string k = py::str(key);
    if (k == "name") {
      c.name = py::str(value);
    } else if (k == "grid_slot") {
      c.grid_slot = value.cast<int>();
    } else if (k == "pace") {
      c.pace = value.cast<double>();
    } else if (k == "max_speed") {
      c.max_speed = value.cast<double>();
    } else {
      throw py::value_error(where + ": unknown key '" + k + "' (name, grid_slot, pace, max_speed)");
    }
  }
  if (c.name.empty()) throw py::value_error(where + ": a car needs a name");
  if (!(c.pace > 0.0 && c.pace <= 1.0)) throw py::value_error(where + ".pace must be in (0, 1]");
  if (c.grid_slot < 0) throw py::value_error(where + ".grid_slot must not be negative");
  if (!(c.max_speed >= 0.0)) throw py::value_error(where + ".max_speed must not be negative");
  return c;
}

// Settings of planning::overtakeOptionTable by name ({"passing.stall_time": 2.0}) applied to `options`: a
// ValueError naming the option for an unknown name or a value out of its range. Flags take True or False.
void setOvertakeOptions(planning::OvertakeOptions* options, const py::dict& settings) {
  for (const auto& [key, value] : settings) {
    const std::string text =
        py::isinstance<py::bool_>(value) ? (value.cast<bool>() ? "1" : "0") : std::string(py::str(value));
    try {
      planning::setOvertakeOption(options, py::str(key), text, "overtake");
    } catch (const std::invalid_argument& e) {
      throw py::value_error(e.what());
    }
  }
}

py::dict trackerOptions(const py::dict& settings) {
  control::TrackerOptions options;
  setTrackerOptions(&options, settings);
  py::dict d;
  d["lateral_control"] = control::lateralMethodName(options.lateral);
  for (const auto& entry : control::trackerOptionTable(&options))
    d[py::str(entry.name)] = *std::get<double*>(entry.field);
  return d;
}

py::dict overtakeOptions(const py::dict& settings) {
  planning::OvertakeOptions options;
  setOvertakeOptions(&options, settings);
  py::dict d;
  for (const auto& entry : planning::overtakeOptionTable(&options)) {
    std::visit([&](auto* field) { d[py::str(entry.name)] = *field; }, entry.field);
  }
  return d;
}

py::dict runRace(const std::string& map, const std::string& maps_dir, const std::string& model,
                 const std::string& urdf_dir, const std::string& config_dir, const std::vector<py::dict>& car_dicts,
                 int laps, double grip_use, bool overtaking, const py::dict& overtake, const py::dict& controller) {
  checkRace(laps, grip_use);
  if (car_dicts.empty() || car_dicts.size() > 20) throw py::value_error("a race needs 1 to 20 cars");
  std::vector<harness::RaceCar> cars;
  for (std::size_t i = 0; i < car_dicts.size(); ++i) cars.push_back(raceCar(car_dicts[i], i));
  harness::RaceOptions options;
  options.laps = laps;
  options.grip_use = grip_use;
  options.field.overtaking = overtaking;
  setOvertakeOptions(&options.field.overtake, overtake);
  setTrackerOptions(&options.tracker, controller);
  const Setup setup = setUp(map, maps_dir, model, urdf_dir, config_dir);
  harness::RaceResult r;
  {
    py::gil_scoped_release unlocked;
    r = harness::runRace(setup.track, setup.vehicle, cars, options);
  }
  py::list results;
  for (const auto& c : r.cars) {
    py::dict d;
    d["name"] = c.name;
    d["position"] = c.position;
    d["finished"] = c.finished;
    d["race_time"] = c.race_time;
    d["lap_times"] = c.lap_times;
    d["car_contacts"] = c.car_contacts;
    d["barrier_contacts"] = c.barrier_contacts;
    d["track_limit_violations"] = c.track_limit_violations;
    d["time_in_traffic"] = c.time_in_traffic;
    results.append(d);
  }
  py::dict d;
  d["finished"] = r.finished;
  d["cars"] = results;
  d["overtakes"] = static_cast<int>(r.overtakes.size());
  d["passes_completed"] = static_cast<int>(
      std::count_if(r.passes.begin(), r.passes.end(), [](const harness::PassAttempt& p) { return p.completed; }));
  d["contacts"] = static_cast<int>(r.contacts.size());
  d["sim_time"] = r.sim_time;
  return d;
}

// One race of roar_bench --traffic's table (harness::TrafficCircuit::race) as the dict of its totals, by
// harness::trafficFigures' names.
py::dict trafficRace(const std::string& map, const std::string& maps_dir, const std::string& model,
                     const std::string& urdf_dir, const std::string& config_dir, const std::string& field, int seed,
                     int laps, double pace_step, const py::dict& overtake) {
  checkRace(laps, 0.85);
  if (seed < 0) throw py::value_error("seed must not be negative, got " + std::to_string(seed));
  harness::TrafficField cars;
  try {
    cars = harness::trafficField(field, seed, pace_step);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  planning::OvertakeOptions options;
  setOvertakeOptions(&options, overtake);
  const Setup setup = setUp(map, maps_dir, model, urdf_dir, config_dir);
  harness::TrafficTotals totals;
  {
    py::gil_scoped_release unlocked;
    harness::TrafficCircuit circuit(map, setup.track, setup.vehicle, laps, options);
    totals = circuit.race(cars, seed);
  }
  std::array<int, 12> won{};
  py::dict d;
  for (auto& [name, figure] : harness::trafficFigures(&totals, &won)) {
    std::visit([&](auto* value) { d[py::str(name)] = *value; }, figure);
  }
  return d;
}

}  // namespace

void bindRaces(py::module_& m) {
  m.def("run_time_trial", &runTimeTrial, py::arg("map"), py::arg("maps_dir"), py::arg("model"), py::arg("urdf_dir"),
        py::arg("config_dir"), py::arg("laps") = 1, py::arg("grip_use") = 0.85, py::arg("controller") = py::dict(),
        py::arg("trace") = false,
        "The stack's time trial of a car model on a map (an out-lap, then `laps` flying laps), the tracker's options "
        "set by name (tracker_options): a dict of finished, "
        "lap_times, best_lap, promised_lap, barrier_contacts, worst_offroad, max_ and rms_lateral_error, sim_time; "
        "with trace=True also `trace`, one row a tick of t, x, y, yaw, speed, steer, throttle, brake");
  m.def("run_race", &runRace, py::arg("map"), py::arg("maps_dir"), py::arg("model"), py::arg("urdf_dir"),
        py::arg("config_dir"), py::arg("cars"), py::arg("laps") = 2, py::arg("grip_use") = 0.85,
        py::arg("overtaking") = true, py::arg("overtake") = py::dict(), py::arg("controller") = py::dict(),
        "The stack's race of cars of a model (each a dict of name, grid_slot, pace, max_speed), overtaking on "
        "unless overtaking is False, the overtaking planner's and the tracker's options set by name "
        "(overtake_options, tracker_options): a "
        "dict of finished, cars (in finishing order: name, position, finished, race_time, lap_times, "
        "car_contacts, barrier_contacts, track_limit_violations, time_in_traffic), overtakes, passes_completed, "
        "contacts, sim_time");
  m.attr("TRAFFIC_FIELDS") = harness::trafficFieldKinds();
  m.attr("TRAFFIC_PACE_STEPS") = py::make_tuple(harness::kMinPaceStep, harness::kMaxPaceStep);
  m.def("traffic_race", &trafficRace, py::arg("map"), py::arg("maps_dir"), py::arg("model"), py::arg("urdf_dir"),
        py::arg("config_dir"), py::arg("field"), py::arg("seed"), py::arg("laps") = 3, py::arg("pace_step") = 0.05,
        py::arg("overtake") = py::dict(),
        "One race of roar_bench --traffic's table: the field (pace_car, reverse_grid, five_percent) drawn from the "
        "seed on the map, and what the table counts of it (races, attempts, completed, ..., catch_to_pass, "
        "passing_share, lap_loss, won: the completed passes by place, side and inside).");
  m.def("overtake_options", &overtakeOptions, py::arg("settings") = py::dict(),
        "Every option of the overtaking planner by name (passing.stall_time, ...) with its value once `settings` "
        "(a dict of name: value) are applied to the defaults; ValueError naming an unknown option or a value out of "
        "its range.");
  m.def("tracker_options", &trackerOptions, py::arg("settings") = py::dict(),
        "Every option of the trajectory tracker by name (lateral_control, lookahead_min, ..., the controller node's "
        "live settings) with its value once `settings` are applied to the defaults; ValueError naming an unknown "
        "option or a value out of its range.");
}

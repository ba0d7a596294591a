// roar_core.World: the simulator's world in the Python process, without ROS: a map, cars by model or CARLA
// blueprint, controls in, states out, one fixed tick at a time. What bench/carla_fidelity.py replays CARLA's
// telemetry through; the same sim::World the simulator node and the in-process race step. And
// roar_core.follow_recorded_lap: the time trial's tracker driving a recorded lap (harness::driveTrajectory).
#include "world_binding.h"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <string>

#include "roar/harness/time_trial.h"
#include "roar/planning/trajectory.h"
#include "roar/sim/world.h"
#include "roar/track/map_folder.h"
#include "roar/vehicle/vehicle_config.h"

namespace py = pybind11;
using namespace roar;

namespace {

class PyWorld {
 public:
  PyWorld(const std::string& map, const std::string& maps_dir, double control_dt, double physics_dt)
      : world_(track::loadMapFolder(track::resolveMapFolder(map, maps_dir)), options(control_dt, physics_dt)) {}

  void spawn(const std::string& name, const std::string& model, const std::string& urdf_dir,
             const std::string& config_dir, double x, double y, double z, double yaw, bool on_ground) {
    track::Pose pose;
    pose.position = Eigen::Vector3d(x, y, z);
    pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    world_.spawnVehicle(name, vehicle::loadVehicleModel(model, urdf_dir, config_dir), pose,
                        on_ground ? sim::Placement::kOnGround : sim::Placement::kAsGiven);
  }

  void reset(const std::string& name, double x, double y, double z, double yaw) {
    track::Pose pose;
    pose.position = Eigen::Vector3d(x, y, z);
    pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    world_.resetVehicle(name, pose);
  }

  void setVelocity(const std::string& name, const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) {
    world_.setVehicleVelocity(name, linear, angular);
  }

  void move(const std::string& name, double x, double y, double yaw, double speed) {
    try {
      world_.moveVehicle(name, Eigen::Vector2d(x, y), yaw, speed);
    } catch (const std::invalid_argument& e) {
      throw py::value_error(e.what());
    }
  }

  // Controls as the simulator's own checks take them: out of range clamped, NaN refused.
  void setControl(const std::string& name, double throttle, double steer, double brake, bool hand_brake, bool reverse) {
    vehicle::VehicleControl c;
    c.throttle = throttle;
    c.steer = steer;
    c.brake = brake;
    c.hand_brake = hand_brake;
    c.reverse = reverse;
    const auto checked = vehicle::checkControl(c, 1);
    if (checked.rejected) throw py::value_error("set_control: " + checked.problems.front());
    world_.setControl(name, checked.control);
  }

  void step(int ticks) {
    if (ticks < 0) throw py::value_error("step: ticks must not be negative, got " + std::to_string(ticks));
    py::gil_scoped_release unlocked;
    for (int i = 0; i < ticks; ++i) world_.step();
  }

  py::dict state(const std::string& name) const {
    const vehicle::VehicleState s = world_.vehicleState(name);
    py::dict d;
    d["position"] = s.pose.position;
    d["yaw"] = track::yawOf(s.pose.orientation);
    d["linear_velocity"] = s.linear_velocity;
    d["angular_velocity"] = s.angular_velocity;
    d["body_linear_velocity"] = s.body_linear_velocity;
    d["body_angular_velocity"] = s.body_angular_velocity;
    d["speed"] = s.speed;
    d["forward_speed"] = s.forward_speed;
    d["gear"] = s.gear;
    d["engine_rpm"] = s.engine_rpm;
    d["steering_angle"] = s.steering_angle;
    d["on_track"] = s.on_track;
    py::list wheels;
    for (const auto& w : s.wheels) {
      py::dict wd;
      wd["in_contact"] = w.in_contact;
      wd["on_road"] = w.on_road;
      wd["load"] = w.load;
      wd["slip_ratio"] = w.slip_ratio;
      wd["slip_angle"] = w.slip_angle;
      wheels.append(wd);
    }
    d["wheels"] = wheels;
    return d;
  }

  // The last tick's contacts of the car's body: (other, impulse N s) per other body.
  py::list contacts(const std::string& name) const {
    py::list out;
    for (const auto& c : world_.contacts(name)) out.append(py::make_tuple(c.other, c.impulse.norm()));
    return out;
  }

  double time() const { return world_.time(); }

 private:
  static sim::WorldOptions options(double control_dt, double physics_dt) {
    sim::WorldOptions o;
    o.control_dt = control_dt;
    o.physics_dt = physics_dt;
    o.control_timeout = 0.0;  // a Python loop may pause between ticks; the car keeps its control
    return o;
  }
  sim::World world_;
};

py::dict followRecordedLap(const std::string& map, const std::string& maps_dir, const std::string& model,
                           const std::string& urdf_dir, const std::string& config_dir,
                           const std::vector<Eigen::Vector2d>& positions, const std::vector<double>& speeds,
                           const std::vector<double>& pedals, int laps) {
  if (laps < 1 || laps > 100)
    throw py::value_error("follow_recorded_lap: laps must be 1 to 100, got " + std::to_string(laps));
  const track::Track track = track::loadMapFolder(track::resolveMapFolder(map, maps_dir));
  const vehicle::VehicleParams vehicle = vehicle::loadVehicleModel(model, urdf_dir, config_dir);
  planning::Trajectory trajectory;
  try {
    trajectory = planning::recordedTrajectory(positions, speeds, pedals);
  } catch (const planning::TrajectoryError& e) {
    throw py::value_error(std::string("follow_recorded_lap: ") + e.what());
  }
  harness::TimeTrialOptions options;
  options.laps = laps;
  std::vector<std::array<double, 7>> trace;  // time, x, y, speed, and the control applied: throttle, brake, steer
  options.on_tick = [&trace](double time, const vehicle::VehicleState& s) {
    const auto& c = s.applied_control;
    trace.push_back({time, s.pose.position.x(), s.pose.position.y(), s.speed, c.throttle, c.brake, c.steer});
  };
  harness::TimeTrialResult r;
  {
    py::gil_scoped_release unlocked;
    r = harness::driveTrajectory(track, vehicle, std::move(trajectory), options);
  }
  py::dict d;
  d["lap_times"] = r.lap_times;
  d["recorded_lap"] = r.promised_lap;
  d["finished"] = r.finished;
  d["barrier_contacts"] = r.barrier_contacts;
  d["worst_offroad"] = r.worst_offroad;
  d["max_lateral_error"] = r.max_lateral_error;
  d["rms_lateral_error"] = r.rms_lateral_error;
  d["trace"] = trace;
  return d;
}

}  // namespace

void bindWorld(py::module_& m) {
  py::register_exception<sim::SpawnError>(m, "SpawnError", PyExc_ValueError);
  py::register_exception<vehicle::VehicleConfigError>(m, "VehicleConfigError", PyExc_ValueError);
  py::class_<PyWorld>(m, "World", "A map's world with cars in it, stepped a fixed tick at a time (no ROS)")
      .def(py::init<const std::string&, const std::string&, double, double>(), py::arg("map"), py::arg("maps_dir"),
           py::arg("control_dt") = 0.05, py::arg("physics_dt") = 0.005)
      .def("spawn", &PyWorld::spawn, py::arg("name"), py::arg("model"), py::arg("urdf_dir"), py::arg("config_dir"),
           py::arg("x"), py::arg("y"), py::arg("z") = 0.0, py::arg("yaw") = 0.0, py::arg("on_ground") = true,
           "Places a car of a model (or CARLA blueprint) at rest; on_ground: set on the ground at x, y and yaw")
      .def("reset", &PyWorld::reset, py::arg("name"), py::arg("x"), py::arg("y"), py::arg("z") = 0.0,
           py::arg("yaw") = 0.0, "Puts the car back at rest on the ground at x, y and yaw")
      .def("set_velocity", &PyWorld::setVelocity, py::arg("name"), py::arg("linear"), py::arg("angular"),
           "base_link's velocities (m/s, rad/s, map frame), the wheels rolling with the road")
      .def("move", &PyWorld::move, py::arg("name"), py::arg("x"), py::arg("y"), py::arg("yaw"), py::arg("speed"),
           "Moves the moving car to x, y facing yaw at the speed, keeping its slip, yaw rate and inner states")
      .def("set_control", &PyWorld::setControl, py::arg("name"), py::arg("throttle") = 0.0, py::arg("steer") = 0.0,
           py::arg("brake") = 0.0, py::arg("hand_brake") = false, py::arg("reverse") = false,
           "The control from the next tick on (steer positive to the left)")
      .def("step", &PyWorld::step, py::arg("ticks") = 1)
      .def("state", &PyWorld::state, py::arg("name"))
      .def("contacts", &PyWorld::contacts, py::arg("name"))
      .def_property_readonly("time", &PyWorld::time);
  m.def(
      "follow_recorded_lap", &followRecordedLap, py::arg("map"), py::arg("maps_dir"), py::arg("model"),
      py::arg("urdf_dir"), py::arg("config_dir"), py::arg("positions"), py::arg("speeds"),
      py::arg("pedals") = std::vector<double>{}, py::arg("laps") = 1,
      "A car of the model tracks a recorded lap (positions (N, 2) at a fixed rate, speeds m/s, and the pedals "
      "(throttle - brake) that drove it, fed forward when given) from the grid: an out-lap, then `laps` timed laps. A "
      "dict of lap_times, recorded_lap (the lap's own time), finished, "
      "barrier_contacts, worst_offroad (m beyond the road's edge), max_ and rms_lateral_error (m) and trace (time, x, "
      "y, speed, throttle, brake and steer each tick)");
}

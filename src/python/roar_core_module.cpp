// roar_core: roar_ros's readers for Python, so that Python reads a map name, a scenario's cars and a sensor
// set exactly as the C++ nodes do (one reader each) instead of reading the files again; and the simulator's
// world (world_binding.h).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "race_binding.h"
#include "roar/config/package_layout.h"
#include "roar/scenario/scenario.h"
#include "roar/sensors/sensor_spec.h"
#include "roar/track/map_folder.h"
#include "world_binding.h"

namespace py = pybind11;
using namespace roar;

namespace {

// The package's folders of the names a scenario uses (a node's defaults, config/ and maps/ of root).
scenario::ScenarioContext contextOf(const std::string& root) {
  return scenario::contextOf(config::PackageLayout{root});
}

py::dict scenarioDict(const scenario::Scenario& scenario) {
  py::list cars;
  for (const auto& car : scenario.cars) {
    py::dict c;
    c["name"] = car.name;
    c["model"] = car.model;
    c["spawn_point"] = car.spawn_point;
    c["sensors"] = car.sensors;
    c["driven"] = car.driven;
    c["max_speed"] = car.max_speed;
    c["pace"] = car.pace;
    c["agent"] = car.agent;
    cars.append(c);
  }
  py::dict d;
  d["name"] = scenario.name;
  d["description"] = scenario.description;
  d["map"] = scenario.map;
  d["laps"] = scenario.laps;
  d["cars"] = cars;
  return d;
}

py::dict loadScenario(const std::string& name_or_path, const std::string& root) {
  return scenarioDict(scenario::loadScenario(
      scenario::resolveScenario(name_or_path, config::PackageLayout{root}.scenarios()), contextOf(root)));
}

py::list readSensorSet(const std::string& name_or_path, const std::string& sensors_dir) {
  py::list out;
  for (const auto& spec : sensors::readSensorSet(sensors::resolveSensorSet(name_or_path, sensors_dir))) {
    py::dict s;
    s["name"] = spec.name;
    s["type"] = sensors::typeName(spec.type);
    out.append(s);
  }
  return out;
}

}  // namespace

PYBIND11_MODULE(roar_core, m) {
  m.doc() = "roar_ros's readers of map names, scenarios and sensor sets (the C++ nodes' own)";
  py::register_exception<track::MapError>(m, "MapError", PyExc_ValueError);
  py::register_exception<scenario::ScenarioError>(m, "ScenarioError", PyExc_ValueError);
  py::register_exception<sensors::SensorSpecError>(m, "SensorSpecError", PyExc_ValueError);
  m.def("resolve_map_folder", &track::resolveMapFolder, py::arg("map"), py::arg("maps_dir"),
        "The folder of a map: a map folder as it is, else the folder of that name in maps_dir (MapError if none)");
  m.def("list_maps", &track::listMaps, py::arg("maps_dir"), "The names of the maps in maps_dir, sorted");
  m.def("load_scenario", &loadScenario, py::arg("name_or_path"), py::arg("package_root"),
        "A scenario (a file, or a name in config/scenarios) read and checked as the nodes read it: a dict of "
        "name, description, map, laps and cars (each name, model, spawn_point, sensors, driven, max_speed, pace, "
        "agent); ScenarioError names the file and field");
  m.def("read_sensor_set", &readSensorSet, py::arg("name_or_path"), py::arg("sensors_dir"),
        "A sensor set (a file, or a name in sensors_dir): its sensors' names and types");
  m.attr("DEFAULT_MODEL") = config::kDefaultModel;
  m.attr("DEFAULT_MAP") = config::kDefaultMap;
  m.def(
      "package_layout",
      [](const std::string& root) {
        const config::PackageLayout layout{root};
        py::dict d;
        d["maps"] = layout.maps();
        d["urdf"] = layout.urdf();
        d["vehicles"] = layout.vehicles();
        d["sensors"] = layout.sensors();
        d["scenarios"] = layout.scenarios();
        d["rl"] = layout.rl();
        d["policies"] = layout.policies();
        return d;
      },
      py::arg("root"),
      "The package's folders under root (config::PackageLayout): maps, urdf, vehicles, sensors, "
      "scenarios, rl");
  bindWorld(m);
  bindRaces(m);
}

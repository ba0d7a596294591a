#include "roar/sim/vehicle_config.h"

#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace roar::sim {
namespace fs = std::filesystem;

namespace {

const char* const kWheelLinks[4] = {"wheel_front_left", "wheel_front_right", "wheel_rear_left", "wheel_rear_right"};

Eigen::Isometry3d toIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  t.linear() = Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z).toRotationMatrix();
  return t;
}

// Pose of `link` in base_link, chaining the joint origins at zero joint positions.
Eigen::Isometry3d linkInBase(const urdf::ModelInterface& model, const std::string& link, const std::string& source) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  urdf::LinkConstSharedPtr current = model.getLink(link);
  while (current && current->name != "base_link") {
    const auto joint = current->parent_joint;
    if (!joint) throw VehicleConfigError(source + ": link '" + link + "' is not connected to base_link");
    t = toIsometry(joint->parent_to_joint_origin_transform) * t;
    current = model.getLink(joint->parent_link_name);
  }
  if (!current) throw VehicleConfigError(source + ": link '" + link + "' is not connected to base_link");
  return t;
}

class YamlReader {
 public:
  YamlReader(YAML::Node root, std::string source) : root_(std::move(root)), source_(std::move(source)) {}

  YAML::Node node(const std::string& path) const {
    // yaml-cpp's Node::operator= writes into the tree; reset() only rebinds the handle.
    YAML::Node n;
    n.reset(root_);
    std::stringstream ss(path);
    std::string part;
    while (std::getline(ss, part, '.')) {
      const YAML::Node& parent = n;
      const YAML::Node child = parent.IsMap() ? parent[part] : YAML::Node();
      if (!child || !child.IsDefined()) throw VehicleConfigError(source_ + ": missing field '" + path + "'");
      n.reset(child);
    }
    return n;
  }

  double number(const std::string& path) const {
    try {
      const double v = node(path).as<double>();
      if (!std::isfinite(v)) throw VehicleConfigError(source_ + ": field '" + path + "' is not finite");
      return v;
    } catch (const YAML::Exception&) {
      throw VehicleConfigError(source_ + ": field '" + path + "' is not a number");
    }
  }

  double positive(const std::string& path) const {
    const double v = number(path);
    if (v <= 0) throw VehicleConfigError(source_ + ": field '" + path + "' must be positive");
    return v;
  }

  double fraction(const std::string& path) const {
    const double v = number(path);
    if (v < 0 || v > 1) throw VehicleConfigError(source_ + ": field '" + path + "' must be in [0, 1]");
    return v;
  }

  bool flag(const std::string& path, bool fallback) const {
    if (!root_.IsMap()) return fallback;
    try {
      return node(path).as<bool>();
    } catch (const VehicleConfigError&) {
      return fallback;
    } catch (const YAML::Exception&) {
      throw VehicleConfigError(source_ + ": field '" + path + "' is not true or false");
    }
  }

  std::vector<double> numbers(const std::string& path) const {
    const YAML::Node n = node(path);
    if (!n.IsSequence() || n.size() == 0) {
      throw VehicleConfigError(source_ + ": field '" + path + "' must be a non-empty list of numbers");
    }
    std::vector<double> out;
    for (std::size_t i = 0; i < n.size(); ++i) {
      try {
        out.push_back(n[i].as<double>());
      } catch (const YAML::Exception&) {
        throw VehicleConfigError(source_ + ": field '" + path + "[" + std::to_string(i) + "]' is not a number");
      }
    }
    return out;
  }

  const std::string& source() const { return source_; }

 private:
  YAML::Node root_;
  std::string source_;
};

}  // namespace

void readVehicleUrdfString(const std::string& urdf_xml, const std::string& source, VehicleParams* params) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf_xml);
  if (!model) throw VehicleConfigError(source + ": not a valid URDF (urdfdom could not parse it)");
  const auto base = model->getLink("base_link");
  if (!base) throw VehicleConfigError(source + ": no link named 'base_link'");
  if (!base->inertial) throw VehicleConfigError(source + ": base_link has no <inertial>");
  const auto& inertial = *base->inertial;
  params->chassis.mass = inertial.mass;
  params->chassis.inertia = Eigen::Vector3d(inertial.ixx, inertial.iyy, inertial.izz);
  params->chassis.centre_of_mass =
      Eigen::Vector3d(inertial.origin.position.x, inertial.origin.position.y, inertial.origin.position.z);
  const auto box = base->collision ? std::dynamic_pointer_cast<urdf::Box>(base->collision->geometry) : nullptr;
  if (!box) throw VehicleConfigError(source + ": base_link needs a <collision> with a <box> for the body");
  params->chassis.box_size = Eigen::Vector3d(box->dim.x, box->dim.y, box->dim.z);
  const auto& origin = base->collision->origin.position;
  params->chassis.box_centre = Eigen::Vector3d(origin.x, origin.y, origin.z);

  for (int w = 0; w < 4; ++w) {
    const auto link = model->getLink(kWheelLinks[w]);
    if (!link) throw VehicleConfigError(source + ": no wheel link named '" + std::string(kWheelLinks[w]) + "'");
    const auto cyl = link->collision ? std::dynamic_pointer_cast<urdf::Cylinder>(link->collision->geometry) : nullptr;
    if (!cyl) throw VehicleConfigError(source + ": link '" + link->name + "' needs a <collision> <cylinder> for the tyre");
    WheelParams& wheel = params->wheels[w];
    wheel.name = link->name;
    wheel.position = linkInBase(*model, link->name, source).translation();
    wheel.radius = cyl->radius;
    wheel.width = cyl->length;
    wheel.front = w < 2;
    wheel.left = w % 2 == 0;
  }
}

void readVehicleUrdf(const std::string& urdf_path, VehicleParams* params) {
  std::ifstream in(urdf_path);
  if (!in) throw VehicleConfigError(urdf_path + ": cannot open the URDF");
  std::stringstream ss;
  ss << in.rdbuf();
  readVehicleUrdfString(ss.str(), urdf_path, params);
}

void readVehicleYaml(const std::string& yaml_path, VehicleParams* params) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::Exception& e) {
    throw VehicleConfigError(yaml_path + ": " + e.what());
  }
  if (!root.IsMap()) throw VehicleConfigError(yaml_path + ": expected a mapping of vehicle sections");
  const YamlReader r(root, yaml_path);
  VehicleParams& p = *params;
  p.front_drive_share = r.fraction("drivetrain.front_drive_share");
  p.traction_control = r.flag("drivetrain.traction_control", true);
  p.rear_grip_share = r.fraction("drivetrain.rear_grip_share");

  p.engine.idle_rpm = r.positive("engine.idle_rpm");
  p.engine.redline_rpm = r.positive("engine.redline_rpm");
  p.engine.engine_brake_torque = r.number("engine.engine_brake_torque_nm");
  const YAML::Node curve = r.node("engine.torque_curve_rpm_nm");
  if (!curve.IsSequence() || curve.size() < 2) {
    throw VehicleConfigError(yaml_path + ": field 'engine.torque_curve_rpm_nm' must list at least 2 [rpm, N m] pairs");
  }
  p.engine.torque_curve.clear();
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const std::string field = "engine.torque_curve_rpm_nm[" + std::to_string(i) + "]";
    if (!curve[i].IsSequence() || curve[i].size() != 2) throw VehicleConfigError(yaml_path + ": field '" + field + "' must be [rpm, N m]");
    try {
      p.engine.torque_curve.emplace_back(curve[i][0].as<double>(), curve[i][1].as<double>());
    } catch (const YAML::Exception&) {
      throw VehicleConfigError(yaml_path + ": field '" + field + "' is not a pair of numbers");
    }
    if (i > 0 && p.engine.torque_curve[i].first <= p.engine.torque_curve[i - 1].first) {
      throw VehicleConfigError(yaml_path + ": field '" + field + "': rpm must rise along the curve");
    }
  }

  p.gearbox.ratios = r.numbers("gearbox.ratios");
  p.gearbox.reverse_ratio = r.positive("gearbox.reverse_ratio");
  p.gearbox.final_drive = r.positive("gearbox.final_drive");
  p.gearbox.efficiency = r.fraction("gearbox.efficiency");
  p.gearbox.shift_up_rpm = r.positive("gearbox.shift_up_rpm");
  p.gearbox.shift_down_rpm = r.positive("gearbox.shift_down_rpm");
  p.gearbox.shift_time = r.number("gearbox.shift_time_s");
  p.gearbox.kickdown = r.flag("gearbox.kickdown", true);

  p.brakes.max_torque_front = r.positive("brakes.max_torque_front_nm");
  p.brakes.max_torque_rear = r.positive("brakes.max_torque_rear_nm");
  p.brakes.hand_brake_torque = r.positive("brakes.hand_brake_torque_nm");
  p.brakes.abs = r.flag("brakes.abs", true);
  p.brakes.rear_grip_share = r.fraction("brakes.rear_grip_share");

  p.steering.max_angle = r.positive("steering.max_angle_rad");
  p.steering.max_rate = r.positive("steering.max_rate_rad_per_s");

  p.suspension.stiffness = r.positive("suspension.stiffness_n_per_m");
  p.suspension.damping = r.positive("suspension.damping_n_s_per_m");
  p.suspension.travel = r.positive("suspension.travel_m");
  p.suspension.droop = r.positive("suspension.droop_m");
  p.suspension.anti_roll_front = r.number("suspension.anti_roll_front_n_per_m");
  p.suspension.anti_roll_rear = r.number("suspension.anti_roll_rear_n_per_m");

  p.tyre.long_b = r.positive("tyre.longitudinal.b");
  p.tyre.long_c = r.positive("tyre.longitudinal.c");
  p.tyre.long_e = r.number("tyre.longitudinal.e");
  p.tyre.lat_b = r.positive("tyre.lateral.b");
  p.tyre.lat_c = r.positive("tyre.lateral.c");
  p.tyre.lat_e = r.number("tyre.lateral.e");
  p.tyre.nominal_load = r.positive("tyre.nominal_load_n");
  p.tyre.load_sensitivity = r.fraction("tyre.load_sensitivity");
  p.tyre.rolling_resistance = r.fraction("tyre.rolling_resistance");
  p.tyre.wheel_inertia = r.positive("tyre.wheel_inertia_kg_m2");

  p.aero.drag_area = r.number("aero.drag_area_m2");
  p.aero.downforce_area = r.number("aero.downforce_area_m2");
  p.aero.front_downforce_share = r.fraction("aero.front_downforce_share");
  p.aero.air_density = r.positive("aero.air_density_kg_per_m3");
}

void validate(const VehicleParams& p, const std::string& source) {
  auto fail = [&](const std::string& what) { throw VehicleConfigError(source + ": " + what); };
  if (!(p.chassis.mass > 0)) fail("base_link mass must be positive");
  if (!(p.chassis.inertia.minCoeff() > 0)) fail("base_link inertia (ixx, iyy, izz) must be positive");
  if (!(p.chassis.box_size.minCoeff() > 0)) fail("body box size must be positive");
  for (const auto& w : p.wheels) {
    if (!(w.radius > 0) || !(w.width > 0)) fail("wheel '" + w.name + "' needs a positive radius and width");
  }
  if (!(p.wheelbase() > 0)) fail("front wheels must be ahead of the rear wheels (wheelbase <= 0)");
  if (!(p.track_width() > 0)) fail("left wheels must be on +y (track width <= 0)");
  if (p.gearbox.ratios.empty()) fail("gearbox.ratios is empty");
  for (std::size_t i = 0; i < p.gearbox.ratios.size(); ++i) {
    if (!(p.gearbox.ratios[i] > 0)) fail("gearbox.ratios[" + std::to_string(i) + "] must be positive");
    if (i > 0 && p.gearbox.ratios[i] >= p.gearbox.ratios[i - 1]) fail("gearbox.ratios must fall from first to top gear");
  }
  if (p.engine.redline_rpm <= p.engine.idle_rpm) fail("engine.redline_rpm must exceed engine.idle_rpm");
  if (p.gearbox.shift_up_rpm > p.engine.redline_rpm) fail("gearbox.shift_up_rpm must not exceed engine.redline_rpm");
  if (p.gearbox.shift_down_rpm >= p.gearbox.shift_up_rpm) fail("gearbox.shift_down_rpm must be below shift_up_rpm");
  if (p.gearbox.shift_time < 0) fail("gearbox.shift_time_s must not be negative");
  if (p.steering.max_angle >= M_PI / 2) fail("steering.max_angle_rad must be below pi/2");
}

VehicleParams loadVehicleModel(const std::string& model, const std::string& urdf_dir, const std::string& config_dir) {
  const fs::path urdf = fs::path(urdf_dir) / (model + ".urdf");
  const fs::path yaml = fs::path(config_dir) / (model + ".yaml");
  if (model.empty() || !fs::exists(urdf) || !fs::exists(yaml)) {
    std::string known;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(config_dir, ec)) {
      if (e.path().extension() == ".yaml" && fs::exists(fs::path(urdf_dir) / (e.path().stem().string() + ".urdf"))) {
        known += (known.empty() ? "" : ", ") + e.path().stem().string();
      }
    }
    throw VehicleConfigError("unknown vehicle model '" + model + "': needs " + urdf.string() + " and " + yaml.string() +
                             " (known models: " + (known.empty() ? "none" : known) + ")");
  }
  VehicleParams params;
  params.model = model;
  readVehicleUrdf(urdf.string(), &params);
  readVehicleYaml(yaml.string(), &params);
  validate(params, urdf.string() + " + " + yaml.string());
  return params;
}

}  // namespace roar::sim

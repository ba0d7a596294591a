#include "roar/vehicle/vehicle_config.h"

#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "roar/config/text_file.h"
#include "roar/config/yaml_section.h"

namespace roar::vehicle {
namespace fs = std::filesystem;

namespace {

const char* const kWheelLinks[4] = {"wheel_front_left", "wheel_front_right", "wheel_rear_left", "wheel_rear_right"};

Eigen::Isometry3d toIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  t.linear() =
      Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z).toRotationMatrix();
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

using Section = config::YamlSection<VehicleConfigError>;

std::string show(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

// A required number within [lo, hi] (its physical range), named with its value and the range when outside.
double inRange(Section& s, const std::string& key, double lo, double hi, const std::string& unit = "") {
  const double v = s.require<double>(key);
  if (!(v >= lo && v <= hi)) s.fail(s.where(key), show(v) + " is outside [" + show(lo) + ", " + show(hi) + "]" + unit);
  return v;
}

// The same but above lo (lo itself refused).
double above(Section& s, const std::string& key, double lo, double hi, const std::string& unit = "") {
  const double v = inRange(s, key, lo, hi, unit);
  if (v == lo) s.fail(s.where(key), "must be above " + show(lo) + unit);
  return v;
}

// steering.speed_curve_kmh_share (optional): CARLA's steering curve, [km/h, share] pairs of rising speed.
vehicle::SteeringCurve readSpeedCurve(Section& steering, const std::string& source) {
  vehicle::SteeringCurve curve;
  if (!steering.has("speed_curve_kmh_share")) return curve;
  const YAML::Node node = steering.raw("speed_curve_kmh_share");
  const std::string where = source + ": steering.speed_curve_kmh_share";
  if (!node.IsSequence() || node.size() < 1) throw VehicleConfigError(where + ": must list [km/h, share] pairs");
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string field = where + "[" + std::to_string(i) + "]";
    double kmh = 0.0, share = 0.0;
    try {
      if (!node[i].IsSequence() || node[i].size() != 2) throw YAML::Exception(YAML::Mark(), "");
      kmh = node[i][0].as<double>();
      share = node[i][1].as<double>();
    } catch (const YAML::Exception&) {
      throw VehicleConfigError(field + ": must be [km/h, share]");
    }
    if (!(kmh >= 0 && kmh <= 500) || !(share > 0 && share <= 1))
      throw VehicleConfigError(field + ": [" + show(kmh) + ", " + show(share) + "] is outside [0, 500] km/h, (0, 1]");
    if (!curve.empty() && kmh / 3.6 <= curve.back().first)
      throw VehicleConfigError(field + ": speeds must rise along the curve");
    curve.emplace_back(kmh / 3.6, share);
  }
  return curve;
}

bool flag(Section& s, const std::string& key, bool fallback) {
  bool v = fallback;
  s.read(key, &v);
  return v;
}

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
    if (!cyl)
      throw VehicleConfigError(source + ": link '" + link->name + "' needs a <collision> <cylinder> for the tyre");
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
  readVehicleUrdfString(config::readTextFile<VehicleConfigError>(urdf_path, config::kMaxUrdfBytes), urdf_path, params);
}

void readVehicleYaml(const std::string& yaml_path, VehicleParams* params) {
  YAML::Node root;
  try {
    root = YAML::Load(config::readTextFile<VehicleConfigError>(yaml_path, config::kMaxYamlBytes));
  } catch (const YAML::Exception& e) {
    throw VehicleConfigError(yaml_path + ": " + e.what());
  }
  if (!root.IsMap()) throw VehicleConfigError(yaml_path + ": expected a mapping of vehicle sections");
  Section file(root, "", yaml_path);
  VehicleParams& p = *params;
  file.read("blueprint", &p.blueprint);
  file.read("description", &p.description);
  Section drivetrain = file.child("drivetrain"), engine = file.child("engine"), gearbox = file.child("gearbox"),
          brakes = file.child("brakes"), steering = file.child("steering"), suspension = file.child("suspension"),
          tyre = file.child("tyre"), aero = file.child("aero");
  file.finish();  // a misspelt section is named as such, not as the fields it lacks

  p.front_drive_share = inRange(drivetrain, "front_drive_share", 0, 1);
  p.traction_control = flag(drivetrain, "traction_control", true);
  p.rear_grip_share = inRange(drivetrain, "rear_grip_share", 0, 1);
  std::string differential = "open";
  drivetrain.read("differential", &differential);
  if (differential == "limited_slip") {
    p.differential.type = DifferentialType::kLimitedSlip;
    // PhysX's biases: the ratio of output speeds the differential allows before it moves torque.
    for (auto [key, bias] :
         {std::pair{"centre_bias", &p.differential.centre_bias}, std::pair{"front_bias", &p.differential.front_bias},
          std::pair{"rear_bias", &p.differential.rear_bias}}) {
      if (drivetrain.has(key)) *bias = inRange(drivetrain, key, 1, 100);
    }
  } else if (differential != "open") {
    drivetrain.fail("drivetrain.differential", "'" + differential + "' is neither open nor limited_slip");
  }
  drivetrain.finish();

  p.engine.idle_rpm = above(engine, "idle_rpm", 0, 5000, " rpm");
  p.engine.redline_rpm = above(engine, "redline_rpm", 0, 25000, " rpm");
  p.engine.engine_brake_torque = inRange(engine, "engine_brake_torque_nm", 0, 2000, " N m");
  if (engine.has("response_time_s")) p.engine.response_time = inRange(engine, "response_time_s", 0, 2, " s");
  if (engine.has("inertia_kg_m2")) p.engine.inertia = above(engine, "inertia_kg_m2", 0, 10, " kg m^2");
  const YAML::Node curve = engine.raw("torque_curve_rpm_nm");
  engine.finish();
  if (!curve || !curve.IsSequence() || curve.size() < 2) {
    throw VehicleConfigError(yaml_path + ": engine.torque_curve_rpm_nm: must list at least 2 [rpm, N m] pairs");
  }
  p.engine.torque_curve.clear();
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const std::string field = "engine.torque_curve_rpm_nm[" + std::to_string(i) + "]";
    if (!curve[i].IsSequence() || curve[i].size() != 2)
      throw VehicleConfigError(yaml_path + ": " + field + ": must be [rpm, N m]");
    double rpm, torque;
    try {
      rpm = curve[i][0].as<double>();
      torque = curve[i][1].as<double>();
    } catch (const YAML::Exception&) {
      throw VehicleConfigError(yaml_path + ": " + field + ": is not a pair of numbers");
    }
    if (!(rpm >= 0 && rpm <= 25000) || !(torque >= 0 && torque <= 5000)) {
      throw VehicleConfigError(yaml_path + ": " + field + ": [" + show(rpm) + ", " + show(torque) +
                               "] is outside [0, 25000] rpm, [0, 5000] N m");
    }
    if (i > 0 && rpm <= p.engine.torque_curve[i - 1].first) {
      throw VehicleConfigError(yaml_path + ": " + field + ": rpm must rise along the curve");
    }
    p.engine.torque_curve.emplace_back(rpm, torque);
  }

  p.gearbox.ratios = gearbox.require<std::vector<double>>("ratios");
  if (p.gearbox.ratios.empty() || p.gearbox.ratios.size() > 12)
    gearbox.fail("gearbox.ratios", "must list 1 to 12 gears");
  for (double r : p.gearbox.ratios) {
    if (!(r > 0 && r <= 20)) gearbox.fail("gearbox.ratios", show(r) + " is outside (0, 20]");
  }
  p.gearbox.reverse_ratio = above(gearbox, "reverse_ratio", 0, 20);
  p.gearbox.final_drive = above(gearbox, "final_drive", 0, 20);
  p.gearbox.efficiency = above(gearbox, "efficiency", 0, 1);
  p.gearbox.shift_up_rpm = above(gearbox, "shift_up_rpm", 0, 25000, " rpm");
  p.gearbox.shift_down_rpm = above(gearbox, "shift_down_rpm", 0, 25000, " rpm");
  p.gearbox.shift_time = inRange(gearbox, "shift_time_s", 0, 2, " s");
  p.gearbox.kickdown = flag(gearbox, "kickdown", true);
  if (gearbox.has("engage_time_s")) p.gearbox.engage_time = inRange(gearbox, "engage_time_s", 0, 5, " s");
  if (gearbox.has("clutch_strength_nm_s_per_rad"))
    p.gearbox.clutch_strength = above(gearbox, "clutch_strength_nm_s_per_rad", 0, 1000, " N m s/rad");
  gearbox.finish();

  p.brakes.max_torque_front = above(brakes, "max_torque_front_nm", 0, 20000, " N m");
  p.brakes.max_torque_rear = above(brakes, "max_torque_rear_nm", 0, 20000, " N m");
  p.brakes.hand_brake_torque = above(brakes, "hand_brake_torque_nm", 0, 20000, " N m");
  p.brakes.abs = flag(brakes, "abs", true);
  p.brakes.rear_grip_share = inRange(brakes, "rear_grip_share", 0, 1);
  if (brakes.has("pedal_rate_per_s")) p.brakes.pedal_rate = inRange(brakes, "pedal_rate_per_s", 0, 1000, " /s");
  if (brakes.has("rise_time_s")) p.brakes.rise_time = inRange(brakes, "rise_time_s", 0, 2, " s");
  if (brakes.has("release_time_s")) p.brakes.release_time = inRange(brakes, "release_time_s", 0, 2, " s");
  brakes.finish();

  p.steering.max_angle = above(steering, "max_angle_rad", 0, 1.4, " rad");
  p.steering.max_rate = above(steering, "max_rate_rad_per_s", 0, 20, " rad/s");
  if (steering.has("response_time_s")) p.steering.response_time = inRange(steering, "response_time_s", 0, 2, " s");
  p.steering.speed_curve = readSpeedCurve(steering, yaml_path);
  steering.finish();

  p.suspension.stiffness = inRange(suspension, "stiffness_n_per_m", 1e3, 1e6, " N/m");
  p.suspension.damping = inRange(suspension, "damping_n_s_per_m", 10, 1e5, " N s/m");
  p.suspension.travel = above(suspension, "travel_m", 0, 0.5, " m");
  p.suspension.droop = above(suspension, "droop_m", 0, 0.5, " m");
  p.suspension.anti_roll_front = inRange(suspension, "anti_roll_front_n_per_m", 0, 1e6, " N/m");
  p.suspension.anti_roll_rear = inRange(suspension, "anti_roll_rear_n_per_m", 0, 1e6, " N/m");
  if (suspension.has("roll_influence")) p.suspension.roll_influence = inRange(suspension, "roll_influence", 0, 1);
  suspension.finish();

  std::string tyre_curve = "magic_formula";
  tyre.read("curve", &tyre_curve);
  if (tyre_curve == "carsimed") {
    // CarSimEd's tyre in CARLA's names (WheelPhysicsControl's lat_stiff_value, lat_stiff_max_load,
    // long_stiff_value).
    p.tyre.curve = TyreCurve::kCarSimEd;
    Section stiffness = tyre.child("carsimed");
    p.tyre.lateral_stiffness = above(stiffness, "lat_stiff_value", 0, 1000, " per rad");
    p.tyre.lateral_stiffness_max_load = above(stiffness, "lat_stiff_max_load", 0, 10);
    p.tyre.longitudinal_stiffness = above(stiffness, "long_stiff_value", 0, 1e6, " kg");
    stiffness.finish();
  } else if (tyre_curve == "magic_formula") {
    for (const char* direction : {"longitudinal", "lateral"}) {
      Section curve_params = tyre.child(direction);
      const bool lon = direction[1] == 'o';
      (lon ? p.tyre.long_b : p.tyre.lat_b) = above(curve_params, "b", 0, 100);
      (lon ? p.tyre.long_c : p.tyre.lat_c) = above(curve_params, "c", 0, 5);
      (lon ? p.tyre.long_e : p.tyre.lat_e) = inRange(curve_params, "e", -10, 1);
      curve_params.finish();
    }
  } else {
    tyre.fail("tyre.curve", "'" + tyre_curve + "' is neither magic_formula nor carsimed");
  }
  p.tyre.nominal_load = above(tyre, "nominal_load_n", 0, 1e5, " N");
  p.tyre.load_sensitivity = inRange(tyre, "load_sensitivity", 0, 1);
  p.tyre.rolling_resistance = inRange(tyre, "rolling_resistance", 0, 0.1);
  p.tyre.wheel_inertia = above(tyre, "wheel_inertia_kg_m2", 0, 50, " kg m^2");
  if (tyre.has("grip")) p.tyre.grip = above(tyre, "grip", 0, 5);
  tyre.finish();

  p.aero.drag_area = inRange(aero, "drag_area_m2", 0, 10, " m^2");
  p.aero.downforce_area = inRange(aero, "downforce_area_m2", -10, 20, " m^2");
  p.aero.front_downforce_share = inRange(aero, "front_downforce_share", 0, 1);
  p.aero.air_density = above(aero, "air_density_kg_per_m3", 0, 2, " kg/m^3");
  aero.finish();
}

void validate(const VehicleParams& p, const std::string& source) {
  auto fail = [&](const std::string& what) { throw VehicleConfigError(source + ": " + what); };
  auto range = [&](const std::string& what, double v, double lo, double hi, const std::string& unit) {
    if (!(v >= lo && v <= hi)) fail(what + " " + show(v) + " is outside [" + show(lo) + ", " + show(hi) + "]" + unit);
  };
  range("base_link mass", p.chassis.mass, 50, 50000, " kg");
  for (int i = 0; i < 3; ++i) {
    range(std::string("base_link inertia ") + "xyz"[i] + "x yz"[i], p.chassis.inertia[i], 1, 1e6, " kg m^2");
    range("body box size", p.chassis.box_size[i], 0.1, 30, " m");
    range("body box centre", p.chassis.box_centre[i], -15, 15, " m");
    range("centre of mass", p.chassis.centre_of_mass[i], -15, 15, " m");
  }
  for (const auto& w : p.wheels) {
    range("wheel '" + w.name + "' radius", w.radius, 0.05, 2, " m");
    range("wheel '" + w.name + "' width", w.width, 0.02, 1, " m");
    for (int i = 0; i < 3; ++i) range("wheel '" + w.name + "' position", w.position[i], -15, 15, " m");
  }
  if (!(p.wheelbase() > 0.5))
    fail("front wheels must be at least 0.5 m ahead of the rear wheels (wheelbase " + show(p.wheelbase()) + " m)");
  if (!(p.track_width() > 0.3))
    fail("left wheels must be on +y, at least 0.3 m from the right ones (track width " + show(p.track_width()) + " m)");
  if (p.gearbox.ratios.empty()) fail("gearbox.ratios is empty");
  for (std::size_t i = 0; i < p.gearbox.ratios.size(); ++i) {
    if (!(p.gearbox.ratios[i] > 0)) fail("gearbox.ratios[" + std::to_string(i) + "] must be positive");
    if (i > 0 && p.gearbox.ratios[i] >= p.gearbox.ratios[i - 1])
      fail("gearbox.ratios must fall from first to top gear");
  }
  if (p.engine.redline_rpm <= p.engine.idle_rpm) fail("engine.redline_rpm must exceed engine.idle_rpm");
  if (p.gearbox.shift_up_rpm > p.engine.redline_rpm) fail("gearbox.shift_up_rpm must not exceed engine.redline_rpm");
  if (p.gearbox.shift_down_rpm >= p.gearbox.shift_up_rpm) fail("gearbox.shift_down_rpm must be below shift_up_rpm");
  if (p.gearbox.shift_time < 0) fail("gearbox.shift_time_s must not be negative");
  if (p.steering.max_angle >= M_PI / 2) fail("steering.max_angle_rad must be below pi/2");
}

std::vector<VehicleModelInfo> listVehicleModels(const std::string& urdf_dir, const std::string& config_dir) {
  std::vector<VehicleModelInfo> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(config_dir, ec)) {
    if (e.path().extension() != ".yaml" || !fs::exists(fs::path(urdf_dir) / (e.path().stem().string() + ".urdf")))
      continue;
    VehicleModelInfo info;
    info.model = e.path().stem().string();
    try {
      std::string text, problem;
      if (!config::tryReadTextFile(e.path().string(), config::kMaxYamlBytes, &text, &problem)) continue;
      const YAML::Node root = YAML::Load(text);
      if (root.IsMap() && root["blueprint"]) info.blueprint = root["blueprint"].as<std::string>();
      if (root.IsMap() && root["description"]) info.description = root["description"].as<std::string>();
    } catch (const YAML::Exception&) {
      // A broken file is still a model: loading it names the problem.
    }
    out.push_back(info);
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.model < b.model; });
  return out;
}

std::string resolveVehicleModel(const std::string& model_or_blueprint, const std::string& urdf_dir,
                                const std::string& config_dir) {
  const auto models = listVehicleModels(urdf_dir, config_dir);
  std::string known;
  for (const auto& m : models) {
    if (!model_or_blueprint.empty() && (m.model == model_or_blueprint || m.blueprint == model_or_blueprint))
      return m.model;
    known += (known.empty() ? "" : ", ") + m.model + (m.blueprint.empty() ? "" : " (" + m.blueprint + ")");
  }
  throw VehicleConfigError("unknown vehicle model or blueprint '" + model_or_blueprint + "': " + config_dir +
                           " has no such model (known models and blueprints: " + (known.empty() ? "none" : known) +
                           ")");
}

VehicleParams loadVehicleModel(const std::string& model_or_blueprint, const std::string& urdf_dir,
                               const std::string& config_dir) {
  const std::string model = resolveVehicleModel(model_or_blueprint, urdf_dir, config_dir);
  const fs::path urdf = fs::path(urdf_dir) / (model + ".urdf");
  const fs::path yaml = fs::path(config_dir) / (model + ".yaml");
  VehicleParams params;
  params.model = model;
  readVehicleUrdf(urdf.string(), &params);
  readVehicleYaml(yaml.string(), &params);
  validate(params, urdf.string() + " + " + yaml.string());
  return params;
}

}  // namespace roar::vehicle

#include "roar/sensors/sensor_spec.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>

namespace roar::sensors {

namespace {

struct TypeEntry {
  const char* name;
  SensorType type;
};
constexpr TypeEntry kTypes[] = {
    {"camera_rgb", SensorType::kCameraRgb},     {"camera_grey", SensorType::kCameraGrey},
    {"camera_depth", SensorType::kCameraDepth}, {"camera_semantic", SensorType::kCameraSemantic},
    {"lidar", SensorType::kLidar},              {"imu", SensorType::kImu},
    {"gnss", SensorType::kGnss},                {"velocimeter", SensorType::kVelocimeter},
};

class Fields {
 public:
  Fields(const YAML::Node& node, std::string where) : node_(node), where_(std::move(where)) {}

  double number(const char* key, double fallback) const {
    const YAML::Node v = node_[key];
    if (!v) return fallback;
    double out;
    try {
      out = v.as<double>();
    } catch (const YAML::Exception&) {
      throw SensorSpecError(where_ + ": field '" + key + "' is not a number");
    }
    if (!std::isfinite(out)) throw SensorSpecError(where_ + ": field '" + key + "' is not finite");
    return out;
  }

  int integer(const char* key, int fallback) const {
    const double v = number(key, fallback);
    if (v != std::floor(v) || std::abs(v) > 1e9) throw SensorSpecError(where_ + ": field '" + key + "' must be a whole number");
    return static_cast<int>(v);
  }

  Eigen::Vector3d vector3(const char* key) const {
    const YAML::Node v = node_[key];
    if (!v) return Eigen::Vector3d::Zero();
    if (!v.IsSequence() || v.size() != 3) throw SensorSpecError(where_ + ": field '" + key + "' must be [x, y, z]");
    try {
      return {v[0].as<double>(), v[1].as<double>(), v[2].as<double>()};
    } catch (const YAML::Exception&) {
      throw SensorSpecError(where_ + ": field '" + key + "' must be three numbers");
    }
  }

 private:
  const YAML::Node& node_;
  std::string where_;
};

constexpr double kDeg = M_PI / 180.0;

}  // namespace

const char* typeName(SensorType type) {
  for (const auto& t : kTypes) {
    if (t.type == type) return t.name;
  }
  return "unknown";
}

bool isCamera(SensorType type) {
  return type == SensorType::kCameraRgb || type == SensorType::kCameraGrey || type == SensorType::kCameraDepth ||
         type == SensorType::kCameraSemantic;
}

SensorSpec parseSensorSpec(const YAML::Node& node, const std::string& source) {
  if (!node.IsMap()) throw SensorSpecError(source + ": a sensor must be a mapping with name and type");
  SensorSpec spec;
  try {
    spec.name = node["name"] ? node["name"].as<std::string>() : "";
  } catch (const YAML::Exception&) {
    throw SensorSpecError(source + ": field 'name' must be a string");
  }
  if (spec.name.empty() || spec.name.find_first_of(" /") != std::string::npos) {
    throw SensorSpecError(source + ": every sensor needs a 'name' without spaces or '/'");
  }
  const std::string where = source + ": sensor '" + spec.name + "'";
  std::string type;
  try {
    type = node["type"] ? node["type"].as<std::string>() : "";
  } catch (const YAML::Exception&) {
    throw SensorSpecError(where + ": field 'type' must be a string");
  }
  bool known = false;
  std::string listed;
  for (const auto& t : kTypes) {
    listed += (listed.empty() ? "" : ", ") + std::string(t.name);
    if (type == t.name) spec.type = t.type, known = true;
  }
  if (!known) throw SensorSpecError(where + ": unknown type '" + type + "' (known: " + listed + ")");

  const Fields f(node, where);
  spec.mount.position = Eigen::Vector3d(f.number("x", 0.0), f.number("y", 0.0), f.number("z", 0.0));
  spec.mount.roll = f.number("roll", 0.0) * kDeg;
  spec.mount.pitch = f.number("pitch", 0.0) * kDeg;
  spec.mount.yaw = f.number("yaw", 0.0) * kDeg;
  spec.rate = f.number("rate", spec.rate);
  spec.seed = static_cast<unsigned>(f.integer("seed", 0));
  spec.camera.fov_deg = f.number("fov", spec.camera.fov_deg);
  spec.camera.width = f.integer("image_width", spec.camera.width);
  spec.camera.height = f.integer("image_height", spec.camera.height);
  auto& l = spec.lidar;
  l.num_lasers = f.integer("num_lasers", l.num_lasers);
  l.max_distance = f.number("max_distance", l.max_distance);
  l.points_per_second = f.number("points_per_second", l.points_per_second);
  l.rotation_frequency = f.number("rotation_frequency", l.rotation_frequency);
  l.upper_fov = f.number("upper_fov", l.upper_fov);
  l.lower_fov = f.number("lower_fov", l.lower_fov);
  l.horizontal_fov = f.number("horizontal_fov", l.horizontal_fov);
  l.noise_std = f.number("noise_std", l.noise_std);
  spec.imu.accel_noise_std = f.number("accel_noise_std", 0.0);
  spec.imu.gyro_noise_std = f.number("gyro_noise_std", 0.0);
  spec.imu.accel_bias = f.vector3("accel_bias");
  spec.imu.gyro_bias = f.vector3("gyro_bias");
  spec.gnss.horizontal_noise_std = f.number("horizontal_noise_std", 0.0);
  spec.gnss.vertical_noise_std = f.number("vertical_noise_std", 0.0);
  validate(spec, source);
  return spec;
}

void validate(const SensorSpec& spec, const std::string& source) {
  const std::string where = source + ": sensor '" + spec.name + "'";
  auto fail = [&](const std::string& field, const std::string& rule) {
    throw SensorSpecError(where + ": field '" + field + "' " + rule);
  };
  if (!(spec.rate > 0) || spec.rate > 10000) fail("rate", "must be in (0, 10000] Hz");
  if (isCamera(spec.type)) {
    if (!(spec.camera.fov_deg > 0 && spec.camera.fov_deg < 180)) fail("fov", "must be in (0, 180) degrees");
    if (spec.camera.width <= 0 || spec.camera.width > 8192) fail("image_width", "must be in [1, 8192]");
    if (spec.camera.height <= 0 || spec.camera.height > 8192) fail("image_height", "must be in [1, 8192]");
  }
  if (spec.type == SensorType::kLidar) {
    const auto& l = spec.lidar;
    if (l.num_lasers < 1 || l.num_lasers > 256) fail("num_lasers", "must be in [1, 256]");
    if (!(l.max_distance > 0) || l.max_distance > 1000) fail("max_distance", "must be in (0, 1000] m");
    if (!(l.points_per_second >= l.num_lasers) || l.points_per_second > 1e8) {
      fail("points_per_second", "must be at least num_lasers and at most 1e8");
    }
    if (!(l.rotation_frequency > 0) || l.rotation_frequency > 1000) fail("rotation_frequency", "must be in (0, 1000] Hz");
    if (l.upper_fov > 90 || l.lower_fov < -90 || !(l.upper_fov > l.lower_fov)) {
      fail("upper_fov", "must be above lower_fov, both within [-90, 90] degrees");
    }
    if (!(l.horizontal_fov > 0 && l.horizontal_fov <= 360)) fail("horizontal_fov", "must be in (0, 360] degrees");
    if (l.noise_std < 0) fail("noise_std", "must not be negative");
  }
  if (spec.imu.accel_noise_std < 0) fail("accel_noise_std", "must not be negative");
  if (spec.imu.gyro_noise_std < 0) fail("gyro_noise_std", "must not be negative");
  if (spec.gnss.horizontal_noise_std < 0) fail("horizontal_noise_std", "must not be negative");
  if (spec.gnss.vertical_noise_std < 0) fail("vertical_noise_std", "must not be negative");
}

std::vector<SensorSpec> parseSensorSetYaml(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw SensorSpecError(source + ": " + e.what());
  }
  const YAML::Node list = root.IsMap() ? root["sensors"] : root;
  if (!list || !list.IsSequence()) throw SensorSpecError(source + ": expected 'sensors:' with a list of sensors");
  std::vector<SensorSpec> out;
  std::set<std::string> names;
  for (std::size_t i = 0; i < list.size(); ++i) {
    out.push_back(parseSensorSpec(list[i], source));
    if (!names.insert(out.back().name).second) {
      throw SensorSpecError(source + ": sensor name '" + out.back().name + "' is used twice");
    }
  }
  return out;
}

std::vector<SensorSpec> readSensorSet(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw SensorSpecError(path + ": cannot read the sensor set");
  } catch (const YAML::Exception& e) {
    throw SensorSpecError(path + ": " + e.what());
  }
  return parseSensorSetYaml(YAML::Dump(root), path);
}

}  // namespace roar::sensors

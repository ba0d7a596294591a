#include "roar/sensors/sensor_spec.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>

#include "roar/config/text_file.h"
#include "roar/config/yaml_section.h"

namespace roar::sensors {

namespace {

struct TypeEntry {
  const char* name;
  SensorType type;
};
constexpr TypeEntry kTypes[] = {
    {"camera_rgb", SensorType::kCameraRgb},
    {"camera_grey", SensorType::kCameraGrey},
    {"camera_depth", SensorType::kCameraDepth},
    {"camera_semantic", SensorType::kCameraSemantic},
    {"lidar", SensorType::kLidar},
    {"imu", SensorType::kImu},
    {"gnss", SensorType::kGnss},
    {"velocimeter", SensorType::kVelocimeter},
    {"accelerometer", SensorType::kAccelerometer},
    {"gyroscope", SensorType::kGyroscope},
    {"roll_pitch_yaw", SensorType::kRollPitchYaw},
    {"location", SensorType::kLocation},
    {"occupancy_map", SensorType::kOccupancyMap},
    {"radar", SensorType::kRadar},
};

using Section = config::YamlSection<SensorSpecError>;

constexpr double kDeg = M_PI / 180.0;

constexpr double kMinSensorRate = 0.01;  // Hz: a reading every 100 s; slower, a sensor all but never reports
constexpr int kMaxImageSide = 4096;
constexpr long kMaxImagePixels = 4096L * 2048L;  // 8.4 million rays a frame
constexpr double kMaxLidarPointsPerSecond = 1e7;
constexpr double kMaxRadarPointsPerSecond = 1e6;
constexpr int kMaxOccupancySide = 2048;

Eigen::Vector3d readVector3(Section& s, const char* key) {
  std::vector<double> v = {0.0, 0.0, 0.0};
  s.read(key, &v);
  if (v.size() != 3) s.fail(key, "must be [x, y, z]");
  return {v[0], v[1], v[2]};
}

std::string show(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

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

bool castsRays(SensorType type) {
  return isCamera(type) || type == SensorType::kLidar || type == SensorType::kOccupancyMap ||
         type == SensorType::kRadar;
}

bool seesFromAnywhere(SensorType type) {
  return isCamera(type) || type == SensorType::kLidar || type == SensorType::kRadar;
}

SensorSpec parseSensorSpec(const YAML::Node& node, const std::string& source, const MountBounds& bounds) {
  if (!node.IsMap()) throw SensorSpecError(source + ": a sensor must be a mapping with name and type");
  SensorSpec spec;
  Section top(node, "", source);
  if (top.has("name") && !top.raw("name").IsScalar())
    throw SensorSpecError(source + ": a sensor's 'name' must be a plain name, not empty (~), a list or a mapping");
  top.read("name", &spec.name);
  if (spec.name.empty()) throw SensorSpecError(source + ": every sensor needs a 'name'");
  // The name is part of the sensor's topics (<car>/<name>/...), so it is a ROS name as a car's is.
  static const std::regex kRosName("[A-Za-z][A-Za-z0-9_]{0,63}");
  if (!std::regex_match(spec.name, kRosName)) {
    throw SensorSpecError(source + ": sensor name '" + spec.name +
                          "' must start with a letter and hold only letters, digits and underscores (at most 64)");
  }
  Section s(node, "", source + ": sensor '" + spec.name + "'");
  s.read("name", &spec.name);
  std::string type;
  s.read("type", &type);
  bool known = false;
  std::string listed;
  for (const auto& t : kTypes) {
    listed += (listed.empty() ? "" : ", ") + std::string(t.name);
    if (type == t.name) spec.type = t.type, known = true;
  }
  if (!known) s.fail("type", "unknown type '" + type + "' (known: " + listed + ")");

  Eigen::Vector3d& p = spec.mount.position;
  s.read("x", &p.x());
  s.read("y", &p.y());
  s.read("z", &p.z());
  for (const char* angle : {"roll", "pitch", "yaw"}) {
    double degrees = 0.0;
    s.read(angle, &degrees);
    if (std::abs(degrees) > 360.0) s.fail(angle, show(degrees) + " is outside [-360, 360] degrees");
    (angle[0] == 'r' ? spec.mount.roll : angle[0] == 'p' ? spec.mount.pitch : spec.mount.yaw) = degrees * kDeg;
  }
  s.read("rate", &spec.rate);
  int seed = 0;
  s.read("seed", &seed);
  spec.seed = static_cast<unsigned>(seed);

  switch (spec.type) {
    case SensorType::kCameraRgb:
    case SensorType::kCameraGrey:
    case SensorType::kCameraDepth:
    case SensorType::kCameraSemantic:
      s.read("fov", &spec.camera.fov_deg);
      s.read("image_width", &spec.camera.width);
      s.read("image_height", &spec.camera.height);
      s.read("on_demand", &spec.camera.on_demand);
      break;
    case SensorType::kLidar: {
      auto& l = spec.lidar;
      s.read("num_lasers", &l.num_lasers);
      s.read("max_distance", &l.max_distance);
      s.read("points_per_second", &l.points_per_second);
      s.read("rotation_frequency", &l.rotation_frequency);
      s.read("upper_fov", &l.upper_fov);
      s.read("lower_fov", &l.lower_fov);
      s.read("horizontal_fov", &l.horizontal_fov);
      s.read("noise_std", &l.noise_std);
      break;
    }
    case SensorType::kRadar: {
      auto& r = spec.radar;
      s.read("horizontal_fov", &r.horizontal_fov);
      s.read("vertical_fov", &r.vertical_fov);
      s.read("points_per_second", &r.points_per_second);
      s.read("max_distance", &r.max_distance);
      break;
    }
    case SensorType::kImu:
      s.read("accel_noise_std", &spec.imu.accel_noise_std);
      s.read("gyro_noise_std", &spec.imu.gyro_noise_std);
      spec.imu.accel_bias = readVector3(s, "accel_bias");
      spec.imu.gyro_bias = readVector3(s, "gyro_bias");
      break;
    case SensorType::kGnss:
      s.read("horizontal_noise_std", &spec.gnss.horizontal_noise_std);
      s.read("vertical_noise_std", &spec.gnss.vertical_noise_std);
      break;
    case SensorType::kVelocimeter:
      break;
    case SensorType::kAccelerometer:
    case SensorType::kGyroscope:
    case SensorType::kRollPitchYaw:
    case SensorType::kLocation: {
      auto& v = spec.vector;
      s.read("noise_std", &v.noise_std);
      v.bias = readVector3(s, "bias");
      if (spec.type == SensorType::kAccelerometer || spec.type == SensorType::kGyroscope) {
        std::string frame = "sensor";
        s.read("frame", &frame);
        if (frame != "sensor" && frame != "map") s.fail("frame", "must be 'sensor' or 'map', not '" + frame + "'");
        v.map_frame = frame == "map";
      }
      if (spec.type == SensorType::kAccelerometer) s.read("gravity", &v.gravity);
      break;
    }
    case SensorType::kOccupancyMap:
      s.read("image_width", &spec.occupancy.width);
      s.read("image_height", &spec.occupancy.height);
      s.read("width_m", &spec.occupancy.width_m);
      s.read("height_m", &spec.occupancy.height_m);
      break;
  }
  s.finish();
  validate(spec, source, bounds);
  return spec;
}

void validate(const SensorSpec& spec, const std::string& source, const MountBounds& bounds) {
  const std::string where = source + ": sensor '" + spec.name + "'";
  auto fail = [&](const std::string& field, const std::string& rule) {
    throw SensorSpecError(where + ": " + field + ": " + rule);
  };
  // value outside [lo, hi] (NaN too), with the value and the range in the message.
  auto range = [&](const std::string& field, double value, double lo, double hi, const std::string& unit) {
    if (!(value >= lo && value <= hi))
      fail(field, show(value) + " is outside [" + show(lo) + ", " + show(hi) + "]" + unit);
  };
  for (int axis = 0; axis < 3; ++axis) {
    range(std::string(1, "xyz"[axis]), spec.mount.position[axis], -bounds.max_offset_m, bounds.max_offset_m,
          std::string(" m of ") + bounds.relative_to);
  }
  for (const double angle : {spec.mount.roll, spec.mount.pitch, spec.mount.yaw}) {
    if (!std::isfinite(angle)) fail("roll, pitch, yaw", "must be finite");
  }
  range("rate", spec.rate, kMinSensorRate, 10000, " Hz");
  if (isCamera(spec.type)) {
    if (!(spec.camera.fov_deg > 0 && spec.camera.fov_deg < 180))
      fail("fov", show(spec.camera.fov_deg) + " must be in (0, 180) degrees");
    range("image_width", spec.camera.width, 1, kMaxImageSide, " pixels");
    range("image_height", spec.camera.height, 1, kMaxImageSide, " pixels");
    if (static_cast<long>(spec.camera.width) * spec.camera.height > kMaxImagePixels) {
      fail("image_width", std::to_string(spec.camera.width) + " x " + std::to_string(spec.camera.height) +
                              " is more than " + std::to_string(kMaxImagePixels) + " pixels a frame");
    }
  }
  if (spec.type == SensorType::kLidar) {
    const auto& l = spec.lidar;
    range("num_lasers", l.num_lasers, 1, 256, "");
    if (!(l.max_distance > 0) || l.max_distance > 1000)
      fail("max_distance", show(l.max_distance) + " is outside (0, 1000] m");
    if (!(l.points_per_second >= l.num_lasers) || l.points_per_second > kMaxLidarPointsPerSecond) {
      fail("points_per_second",
           show(l.points_per_second) + " must be at least num_lasers and at most " + show(kMaxLidarPointsPerSecond));
    }
    if (!(l.rotation_frequency > 0) || l.rotation_frequency > 1000) {
      fail("rotation_frequency", show(l.rotation_frequency) + " is outside (0, 1000] Hz");
    }
    if (!(l.upper_fov <= 90 && l.lower_fov >= -90 && l.upper_fov > l.lower_fov)) {
      fail("upper_fov", "must be above lower_fov, both within [-90, 90] degrees");
    }
    if (!(l.horizontal_fov > 0 && l.horizontal_fov <= 360))
      fail("horizontal_fov", show(l.horizontal_fov) + " is outside (0, 360] degrees");
    range("noise_std", l.noise_std, 0, 10, " m");
  }
  if (spec.type == SensorType::kRadar) {
    const auto& r = spec.radar;
    if (!(r.horizontal_fov > 0 && r.horizontal_fov < 180))
      fail("horizontal_fov", show(r.horizontal_fov) + " must be in (0, 180) degrees");
    if (!(r.vertical_fov > 0 && r.vertical_fov < 180))
      fail("vertical_fov", show(r.vertical_fov) + " must be in (0, 180) degrees");
    range("points_per_second", r.points_per_second, 1, kMaxRadarPointsPerSecond, "");
    if (!(r.max_distance > 0) || r.max_distance > 1000)
      fail("max_distance", show(r.max_distance) + " is outside (0, 1000] m");
  }
  if (spec.type == SensorType::kImu) {
    range("accel_noise_std", spec.imu.accel_noise_std, 0, 100, " m/s^2");
    range("gyro_noise_std", spec.imu.gyro_noise_std, 0, 10, " rad/s");
    for (int axis = 0; axis < 3; ++axis) {
      range("accel_bias", spec.imu.accel_bias[axis], -100, 100, " m/s^2");
      range("gyro_bias", spec.imu.gyro_bias[axis], -10, 10, " rad/s");
    }
  }
  if (spec.type == SensorType::kGnss) {
    range("horizontal_noise_std", spec.gnss.horizontal_noise_std, 0, 1000, " m");
    range("vertical_noise_std", spec.gnss.vertical_noise_std, 0, 1000, " m");
  }
  if (spec.type == SensorType::kAccelerometer || spec.type == SensorType::kGyroscope ||
      spec.type == SensorType::kRollPitchYaw || spec.type == SensorType::kLocation) {
    const double limit = spec.type == SensorType::kAccelerometer  ? 100
                         : spec.type == SensorType::kGyroscope    ? 10
                         : spec.type == SensorType::kRollPitchYaw ? M_PI
                                                                  : 1000;
    const char* unit = spec.type == SensorType::kAccelerometer  ? " m/s^2"
                       : spec.type == SensorType::kGyroscope    ? " rad/s"
                       : spec.type == SensorType::kRollPitchYaw ? " rad"
                                                                : " m";
    range("noise_std", spec.vector.noise_std, 0, limit, unit);
    for (int axis = 0; axis < 3; ++axis) range("bias", spec.vector.bias[axis], -limit, limit, unit);
  }
  if (spec.type == SensorType::kOccupancyMap) {
    range("image_width", spec.occupancy.width, 1, kMaxOccupancySide, " pixels");
    range("image_height", spec.occupancy.height, 1, kMaxOccupancySide, " pixels");
    if (!(spec.occupancy.width_m > 0 && spec.occupancy.width_m <= 1000))
      fail("width_m", show(spec.occupancy.width_m) + " is outside (0, 1000] m");
    if (!(spec.occupancy.height_m > 0 && spec.occupancy.height_m <= 1000))
      fail("height_m", show(spec.occupancy.height_m) + " is outside (0, 1000] m");
  }
}

std::vector<SensorSpec> parseSensorSetYaml(const std::string& yaml_text, const std::string& source,
                                           const MountBounds& bounds) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw SensorSpecError(source + ": " + e.what());
  }
  YAML::Node list = root;
  if (root.IsMap()) {
    Section file(root, "", source);
    list.reset(file.raw("sensors"));  // reset: assigning a YAML::Node would overwrite the root it refers to
    file.finish();                    // before the list is looked at: a misspelt `sensors:` is named as such
  }
  if (!list || !list.IsSequence()) throw SensorSpecError(source + ": expected 'sensors:' with a list of sensors");
  if (list.size() == 0) throw SensorSpecError(source + ": the list of sensors is empty (name no set for no sensors)");
  std::vector<SensorSpec> out;
  std::set<std::string> names;
  for (std::size_t i = 0; i < list.size(); ++i) {
    out.push_back(parseSensorSpec(list[i], source, bounds));
    if (!names.insert(out.back().name).second) {
      throw SensorSpecError(source + ": sensor name '" + out.back().name + "' is used twice");
    }
  }
  return out;
}

SensorLoad loadOf(const SensorSpec& spec) {
  SensorLoad load;
  if (isCamera(spec.type)) {
    load.samples = static_cast<double>(spec.camera.width) * spec.camera.height;
  } else if (spec.type == SensorType::kOccupancyMap) {
    load.samples = static_cast<double>(spec.occupancy.width) * spec.occupancy.height;
  } else if (spec.type == SensorType::kLidar) {
    return {spec.lidar.points_per_second, spec.lidar.points_per_second / spec.rate};
  } else if (spec.type == SensorType::kRadar) {
    return {spec.radar.points_per_second, spec.radar.points_per_second / spec.rate};
  }
  load.rays_per_second = load.samples * spec.rate;
  return load;
}

SensorLoad totalLoad(const std::vector<SensorSpec>& specs) {
  SensorLoad total;
  for (const auto& spec : specs) total += loadOf(spec);
  return total;
}

void checkBudget(const SensorLoad& in_use, const SensorSpec& adding, const SensorBudget& budget) {
  SensorLoad total = in_use;
  total += loadOf(adding);
  auto millions = [](double v) { return show(std::round(v / 1e5) / 10) + " million"; };
  if (total.samples > budget.samples) {
    throw SensorSpecError("sensor '" + adding.name + "': " + budget.whose + " sensors would hold " +
                          millions(total.samples) + " pixels or points a frame, more than its budget of " +
                          millions(budget.samples) + "; make images smaller or use fewer sensors");
  }
  if (total.rays_per_second > budget.rays_per_second) {
    throw SensorSpecError("sensor '" + adding.name + "': " + budget.whose + " sensors would cast " +
                          millions(total.rays_per_second) + " rays a simulated second, more than its budget of " +
                          millions(budget.rays_per_second) + "; lower rates or image sizes");
  }
}

std::vector<std::string> listSensorSets(const std::string& sensors_dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(sensors_dir, ec)) {
    if (entry.is_regular_file() && entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

namespace {

// The file of the set `name` in sensors_dir, or an error (after `prefix`) naming the nearest set and `paths`
// (where a path would be taken instead).
std::string setFile(const std::string& name, const std::string& sensors_dir, const std::string& prefix,
                    const std::string& paths) {
  const auto sets = listSensorSets(sensors_dir);
  if (std::find(sets.begin(), sets.end(), name) != sets.end()) return sensors_dir + "/" + name + ".yaml";
  std::string known;
  for (const auto& set : sets) known += (known.empty() ? "" : ", ") + set;
  const std::string near = config::nearestKey(name, sets);
  throw SensorSpecError(prefix + "no sensor set '" + name + "' in " + sensors_dir +
                        (near.empty() ? "" : " (did you mean '" + near + "'?)") + " (sets: " + known + "; " + paths +
                        ")");
}

}  // namespace

std::string sensorSetByName(const std::string& name, const std::string& sensors_dir) {
  return setFile(name, sensors_dir, "sensor_set: ", "a file's path is taken at launch, not from a service");
}

std::string resolveSensorSet(const std::string& name_or_path, const std::string& sensors_dir) {
  const bool path = name_or_path.find('/') != std::string::npos ||
                    (name_or_path.size() > 5 && name_or_path.compare(name_or_path.size() - 5, 5, ".yaml") == 0) ||
                    std::filesystem::is_regular_file(name_or_path);
  return path ? name_or_path : setFile(name_or_path, sensors_dir, "", "or a YAML file's path");
}

std::vector<SensorSpec> readSensorSet(const std::string& path) {
  return parseSensorSetYaml(config::readTextFile<SensorSpecError>(path, config::kMaxYamlBytes), path);
}

}  // namespace roar::sensors

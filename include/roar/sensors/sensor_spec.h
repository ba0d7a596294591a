#pragma once
// What a sensor is: its kind, where it sits on the car, how often it reports and its own parameters.
// Sensor sets are YAML files (config/sensors/<set>.yaml); parsing errors name the file, sensor and field.
#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace roar::sensors {

enum class SensorType { kCameraRgb, kCameraGrey, kCameraDepth, kCameraSemantic, kLidar, kImu, kGnss, kVelocimeter };

const char* typeName(SensorType type);
bool isCamera(SensorType type);

struct Mount {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m, in base_link
  double roll = 0.0, pitch = 0.0, yaw = 0.0;           // rad, applied as yaw * pitch * roll (REP-103 rpy)
};

struct CameraSpec {
  double fov_deg = 90.0;  // horizontal field of view
  int width = 800;
  int height = 600;
};

// ROAR_PY's (CARLA's) LiDAR parameters.
struct LidarSpec {
  int num_lasers = 32;
  double max_distance = 50.0;          // m
  double points_per_second = 56000.0;
  double rotation_frequency = 20.0;    // Hz
  double upper_fov = 10.0;             // deg
  double lower_fov = -30.0;            // deg
  double horizontal_fov = 360.0;       // deg
  double noise_std = 0.0;              // m, range noise
};

struct ImuSpec {
  double accel_noise_std = 0.0;  // m/s^2
  double gyro_noise_std = 0.0;   // rad/s
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
};

struct GnssSpec {
  double horizontal_noise_std = 0.0;  // m
  double vertical_noise_std = 0.0;    // m
};

struct SensorSpec {
  std::string name;
  SensorType type = SensorType::kImu;
  Mount mount;
  double rate = 20.0;  // Hz
  CameraSpec camera;
  LidarSpec lidar;
  ImuSpec imu;
  GnssSpec gnss;
  unsigned seed = 0;  // noise generator seed: the same seed gives the same noise
};

class SensorSpecError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One sensor from a YAML mapping: name, type, x, y, z, roll, pitch, yaw (degrees), rate and the
// type's own fields. `source` prefixes every error.
SensorSpec parseSensorSpec(const YAML::Node& node, const std::string& source);
// A sensor set file: `sensors: [ ... ]`; names must be unique.
std::vector<SensorSpec> readSensorSet(const std::string& path);
std::vector<SensorSpec> parseSensorSetYaml(const std::string& yaml_text, const std::string& source);
// Range checks of one spec; throws SensorSpecError naming the sensor and field.
void validate(const SensorSpec& spec, const std::string& source);

}  // namespace roar::sensors

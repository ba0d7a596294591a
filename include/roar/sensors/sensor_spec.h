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

enum class SensorType {
  kCameraRgb,
  kCameraGrey,
  kCameraDepth,
  kCameraSemantic,
  kLidar,
  kImu,
  kGnss,
  kVelocimeter,
  kAccelerometer,
  kGyroscope,
  kRollPitchYaw,
  kLocation,
  kOccupancyMap,
  kRadar
};

const char* typeName(SensorType type);
bool isCamera(SensorType type);
// Cameras, LiDAR, radar and the occupancy map cast rays once per control tick; the others sample the
// car's motion after physics substeps.
bool castsRays(SensorType type);
// The kinds a sensor fixed in the world (on no car) can be: those that see (cameras, LiDAR, radar). The
// others measure the car they ride on, and the occupancy map is drawn around it.
bool seesFromAnywhere(SensorType type);

struct Mount {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m, in base_link
  double roll = 0.0, pitch = 0.0, yaw = 0.0;           // rad, applied as yaw * pitch * roll (REP-103 rpy)
};

struct CameraSpec {
  double fov_deg = 90.0;  // horizontal field of view
  int width = 800;
  int height = 600;
  // Rendered only when its frames are wanted (someone subscribes) or asked for after the tick
  // (SensorRig::renderCamera): a frame nobody reads costs nothing. ROAR_PY programs' cameras are so.
  bool on_demand = false;
};

// ROAR_PY's (CARLA's) LiDAR parameters.
struct LidarSpec {
  int num_lasers = 32;
  double max_distance = 50.0;  // m
  double points_per_second = 56000.0;
  double rotation_frequency = 20.0;  // Hz
  double upper_fov = 10.0;           // deg
  double lower_fov = -30.0;          // deg
  double horizontal_fov = 360.0;     // deg
  double noise_std = 0.0;            // m, range noise
};

// CARLA's radar (sensor.other.radar) and its defaults: rays spread over an elliptical cone, each hit a
// detection with its velocity along the line of sight.
struct RadarSpec {
  double horizontal_fov = 30.0;  // deg
  double vertical_fov = 30.0;    // deg
  double points_per_second = 1500.0;
  double max_distance = 100.0;  // m
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

// The sensors that read one vector: accelerometer (m/s^2), gyroscope (rad/s), roll_pitch_yaw (rad) and
// location (m, map frame).
struct VectorSpec {
  double noise_std = 0.0;                          // Gaussian, per axis, in the reading's unit
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();  // added to every reading
  // Accelerometer and gyroscope: in the map frame instead of the sensor's (ROAR_PY's readings are).
  bool map_frame = false;
  // Accelerometer: specific force, as a real one reads it (+g upwards at rest); false: the acceleration.
  bool gravity = true;
};

// A bird's-eye image centred on the sensor and turned with the car's heading: forward is up, left is left.
struct OccupancyMapSpec {
  int width = 84;          // pixels across the car
  int height = 84;         // pixels along the car
  double width_m = 40.0;   // metres of the world the image spans across the car
  double height_m = 40.0;  // metres along the car
};

struct SensorSpec {
  std::string name;
  SensorType type = SensorType::kImu;
  Mount mount;
  double rate = 20.0;  // Hz
  CameraSpec camera;
  LidarSpec lidar;
  RadarSpec radar;
  ImuSpec imu;
  GnssSpec gnss;
  VectorSpec vector;
  OccupancyMapSpec occupancy;
  unsigned seed = 0;  // noise generator seed: the same seed gives the same noise
};

class SensorSpecError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What a sensor costs the simulator: the rays it casts a simulated second (its frame at its rate) and the
// samples one frame holds (pixels or points), which set its memory (about 60 bytes a pixel for a camera).
struct SensorLoad {
  double rays_per_second = 0.0;
  double samples = 0.0;
  SensorLoad& operator+=(const SensorLoad& other) {
    rays_per_second += other.rays_per_second;
    samples += other.samples;
    return *this;
  }
};
SensorLoad loadOf(const SensorSpec& spec);
SensorLoad totalLoad(const std::vector<SensorSpec>& specs);

// Each sensor passes validate() alone; these bound their sum, so that many large sensors cannot take the
// machine's memory or stall every tick (sensor_spec_test SensorsBeyondABudgetAreRefusedByName).
struct SensorBudget {
  const char* whose;  // "a car's", "roar_sim's"
  double rays_per_second;
  double samples;
};
inline constexpr SensorBudget kCarSensorBudget{"a car's", 2.0e8, 2.0 * 4096 * 2048};
inline constexpr SensorBudget kSimulatorSensorBudget{"roar_sim's", 4.0e8, 4.0 * 4096 * 2048};
// Throws SensorSpecError naming `adding`, the budget and the figures when `in_use` and `adding` exceed it.
void checkBudget(const SensorLoad& in_use, const SensorSpec& adding, const SensorBudget& budget);

// How far a sensor's mount may lie from what it is mounted on.
struct MountBounds {
  double max_offset_m;
  const char* relative_to;
};
// On a car or on a pole above it, not across the map.
inline constexpr MountBounds kOnACar{20.0, "base_link"};
// Fixed in the world (on no car): anywhere on a map.
inline constexpr MountBounds kInTheWorld{1e5, "the map's origin"};

// One sensor from a YAML mapping: name, type, x, y, z, roll, pitch, yaw (degrees), rate, seed and the
// type's own fields; a key the type does not take is refused. `source` prefixes every error.
SensorSpec parseSensorSpec(const YAML::Node& node, const std::string& source, const MountBounds& bounds = kOnACar);
// A sensor set file: `sensors: [ ... ]`; names must be unique.
std::vector<SensorSpec> readSensorSet(const std::string& path);
// The file of a sensor set: a file's path as it is (a path with a '/' or ending in .yaml, or a file that
// exists), else the set of that name in sensors_dir. The one reading of a set's name, roar_sim's, a
// scenario's and scripts/race_rviz's.
std::string resolveSensorSet(const std::string& name_or_path, const std::string& sensors_dir);
// The file of the set `name` in sensors_dir, and nothing else: what a service caller (any process on the
// ROS graph) may ask for. A path, a name with other characters or an unknown name is refused alike, without
// touching the file system beyond sensors_dir, so a reply tells nothing of other files (sim_services.test).
std::string sensorSetByName(const std::string& name, const std::string& sensors_dir);
std::vector<std::string> listSensorSets(const std::string& sensors_dir);
std::vector<SensorSpec> parseSensorSetYaml(const std::string& yaml_text, const std::string& source,
                                           const MountBounds& bounds = kOnACar);
// Range checks of one spec (physical ranges, and what one core can render); throws SensorSpecError naming
// the sensor, the field, the value and the range.
void validate(const SensorSpec& spec, const std::string& source, const MountBounds& bounds = kOnACar);

}  // namespace roar::sensors

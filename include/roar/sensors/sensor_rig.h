#pragma once
// The sensors of one car. Motion sensors (IMU, GNSS, velocimeter, accelerometer, gyroscope, roll-pitch-yaw,
// location) are sampled after physics substeps, so they may run up to the physics rate; cameras, LiDAR and
// radar and occupancy maps are cast once per control tick when due, so their rate may not exceed the control rate.
// Cameras on one mount with the same intrinsics and rate share one cast. Readings go to a SensorSink (the ROS node
// publishes them; tests collect them).
#include <Eigen/Geometry>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "roar/sensors/camera.h"
#include "roar/sensors/inertial.h"
#include "roar/sensors/lidar.h"
#include "roar/sensors/occupancy_map.h"
#include "roar/sensors/radar.h"
#include "roar/sensors/sensor_spec.h"

namespace roar::sensors {

class SensorSink {
 public:
  virtual ~SensorSink() = default;
  virtual void camera(const SensorSpec& spec, double stamp, const CameraFrame& frame, const CameraIntrinsics& k) = 0;
  virtual void lidar(const SensorSpec& spec, double stamp, const std::vector<LidarPoint>& points) = 0;
  virtual void imu(const SensorSpec& spec, double stamp, const ImuSample& sample) = 0;
  virtual void gnss(const SensorSpec& spec, double stamp, const GnssFix& fix) = 0;
  virtual void velocity(const SensorSpec& spec, double stamp, const Velocity& velocity) = 0;
  // Accelerometer, gyroscope, roll_pitch_yaw and location (see sampleVector).
  virtual void vector(const SensorSpec& spec, double stamp, const Eigen::Vector3d& reading) = 0;
  virtual void occupancy(const SensorSpec& spec, double stamp, const OccupancyFrame& frame) = 0;
  virtual void radar(const SensorSpec& /*spec*/, double /*stamp*/, const std::vector<RadarDetection>& /*detections*/) {}
  // An on-demand camera is rendered at its due tick only when its frames are wanted now; otherwise its
  // frame of that tick is left to renderCamera and the sink told its stamp.
  virtual bool wanted(const SensorSpec& /*spec*/) { return true; }
  virtual void deferred(const SensorSpec& /*spec*/, double /*stamp*/) {}
};

struct RigTiming {
  double control_dt = 0.05;
  double physics_dt = 0.005;
  double gravity = 9.81;
};

class SensorRig {
 public:
  // Throws SensorSpecError naming the sensor for a rate its kind cannot keep, or a taken name.
  // Mounts within `bounds` (of base_link, or of the map for a rig on no car).
  SensorRig(const std::vector<SensorSpec>& specs, const RigTiming& timing, const track::GeoOrigin& origin,
            double start_time = 0.0, const MountBounds& bounds = kOnACar);
  ~SensorRig();

  // A sensor added at `now` reports first one period later.
  void add(const SensorSpec& spec, double now);
  bool remove(const std::string& name);
  std::vector<SensorSpec> specs() const;
  const MountBounds& bounds() const { return bounds_; }
  // New control and physics steps: throws SensorSpecError naming the first sensor whose rate they cannot
  // keep, changing nothing.
  void setTiming(double control_dt, double physics_dt);
  // Throws SensorSpecError when `spec`'s rate is faster than its kind can run at these steps.
  static void checkRate(const SensorSpec& spec, double control_dt, double physics_dt);

  // After every physics substep, at simulated time `time`.
  void sampleMotion(double time, const BodyMotion& motion, SensorSink& sink);
  // After every control tick, with the scene's cars at this tick's poses (and velocities, for the radar).
  // Cameras see the car they are on; LiDAR, radar and occupancy maps do not.
  void sampleRays(double time, const RayScene& scene, const Eigen::Isometry3d& base_in_map, int own_vehicle,
                  SensorSink& sink);
  // Whether sampleRays at `time` would cast a ray (a camera due and wanted, or a LiDAR, radar or occupancy
  // map due): when none would, the scene need not be posed for the tick (sensor_rig_test
  // OnlySensorsThatAreDueAndWantedCastRays).
  bool castsRaysAt(double time, SensorSink& sink) const;
  // Camera `name`'s frame with the scene as it is and the car at base_in_map: what sampleRays renders at a
  // tick in that state, to the bit (sensor_rig_test AnOnDemandFrameIsTheFrameSampledAtItsTick). Throws
  // SensorSpecError for a name that is no camera of this rig.
  const CameraFrame& renderCamera(const std::string& name, const RayScene& scene, const Eigen::Isometry3d& base_in_map,
                                  CameraIntrinsics* intrinsics);

 private:
  struct Sensor;
  struct CameraGroup;
  void rebuildCameraGroups();
  // A camera group renders when a member is not on demand, or a reader wants its frame.
  static bool rendered(const CameraGroup& group, SensorSink& sink);

  RigTiming timing_;
  track::GeoOrigin origin_;
  MountBounds bounds_;
  std::vector<std::unique_ptr<Sensor>> sensors_;
  std::vector<std::unique_ptr<CameraGroup>> camera_groups_;
};

}  // namespace roar::sensors

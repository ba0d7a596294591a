#pragma once
// What an agent observes of its car, selectable, as a Gymnasium Dict (keys sorted):
//   speed              Box(0, inf, (1,))   m/s
//   velocity           Box(3)              m/s, base_link frame (x forward, y left, z up): ROAR_PY's velocimeter
//   angular_velocity   Box(3)              rad/s, base_link frame
//   imu                Box(6)              specific force (m/s^2, +9.81 up at rest) then angular velocity, base_link
//   waypoints_information  Dict of waypoint_<d>: Box(4) for each distance d ahead along the centre line, as
//                      ROAR_PY_RL: the waypoint's x and y in the car's frame, its yaw relative to the car's,
//                      and the lane width (m)
//   lidar              Box(0, max_range, (beams,))  ranges of a horizontal fan of beams, right to left
//   camera_rgb         Box(0, 255, (height, width, 3), uint8)
//   camera_depth       Box(0, max_depth, (height, width), float32)  metres along the optical axis
// Camera and LiDAR are cast in the sensors module's ray scene; the car carrying them is invisible to them.
#include <memory>
#include <vector>

#include "roar/rl/observation_options.h"
#include "roar/rl/space.h"
#include "roar/sensors/sensor_spec.h"
#include "roar/sim/world.h"
#include "roar/track/track.h"

namespace roar::sensors {
class RayScene;
class CameraRenderer;
}  // namespace roar::sensors

namespace roar::rl {

// The Dict these options observe (validated first).
Space observationSpace(const ObservationOptions& options);

class ObservationBuilder {
 public:
  ObservationBuilder(const track::Track& track, const ObservationOptions& options, double gravity = 9.81);
  ~ObservationBuilder();
  ObservationBuilder(ObservationBuilder&&) noexcept;

  const Space& space() const { return space_; }
  const ObservationOptions& options() const { return options_; }
  // Camera or LiDAR: observe() needs the ray scene.
  bool needsScene() const;

  // The observation of a car in `state`, `where` its projection on the track (TrackProgress). `scene` (in
  // which the car is `own_vehicle`, -1 when it is not in it) is used when needsScene().
  Value observe(const vehicle::VehicleState& state, const track::Projection& where, const sensors::RayScene* scene,
                int own_vehicle);
  // The same into `obs`, reusing its memory when it holds an earlier observation of this builder: a step
  // then allocates nothing.
  void observeInto(const vehicle::VehicleState& state, const track::Projection& where, const sensors::RayScene* scene,
                   int own_vehicle, Value* obs);

 private:
  const track::Track* track_;
  ObservationOptions options_;
  double gravity_;
  Space space_;
  std::unique_ptr<sensors::CameraRenderer> camera_;
  std::vector<Eigen::Vector3f> lidar_dirs_;  // base_link frame
  std::vector<std::string> waypoint_keys_;   // waypointKey of each distance, formatted once
};

}  // namespace roar::rl

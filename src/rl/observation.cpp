#include "roar/rl/observation.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "roar/sensors/camera.h"
#include "roar/sensors/inertial.h"
#include "roar/sensors/ray_scene.h"
#include "roar/sensors/vehicle_motion.h"

namespace roar::rl {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Space dictOf(const ObservationOptions& o) {
  std::vector<std::pair<std::string, Space>> entries;
  if (o.speed) entries.emplace_back("speed", Space::box(0.0, kInf, {1}));
  if (o.velocity) entries.emplace_back("velocity", Space::box(-kInf, kInf, {3}));
  if (o.angular_velocity) entries.emplace_back("angular_velocity", Space::box(-kInf, kInf, {3}));
  if (o.imu) entries.emplace_back("imu", Space::box(-kInf, kInf, {6}));
  if (!o.waypoint_distances.empty()) {
    std::vector<std::pair<std::string, Space>> waypoints;
    for (double d : o.waypoint_distances) {
      // x, y and lane width unbounded like ROAR_PY_RL's; the relative yaw is an angle in [-pi, pi].
      waypoints.emplace_back(waypointKey(d), Space::box({-kInf, -kInf, -M_PI, 0.0}, {kInf, kInf, M_PI, kInf}, {4}));
    }
    entries.emplace_back("waypoints_information", Space::dict(std::move(waypoints)));
  }
  if (o.lidar.beams > 0) entries.emplace_back("lidar", Space::box(0.0, o.lidar.max_range, {o.lidar.beams}));
  if (o.camera.width > 0) {
    if (o.camera.rgb)
      entries.emplace_back("camera_rgb", Space::box(0.0, 255.0, {o.camera.height, o.camera.width, 3}, DType::kUInt8));
    if (o.camera.depth)
      entries.emplace_back("camera_depth", Space::box(0.0, o.camera.max_depth, {o.camera.height, o.camera.width}));
  }
  return Space::dict(std::move(entries));
}

}  // namespace

Space observationSpace(const ObservationOptions& options) {
  validate(options);
  return dictOf(options);
}

ObservationBuilder::ObservationBuilder(const track::Track& track, const ObservationOptions& options, double gravity)
    : track_(&track), options_(options), gravity_(gravity) {
  space_ = observationSpace(options_);
  for (double d : options_.waypoint_distances) waypoint_keys_.push_back(waypointKey(d));
  if (options_.camera.width > 0) {
    sensors::CameraSpec spec;
    spec.fov_deg = options_.camera.fov_deg;
    spec.width = options_.camera.width;
    spec.height = options_.camera.height;
    camera_ = std::make_unique<sensors::CameraRenderer>(spec);
  }
  const auto& lidar = options_.lidar;
  for (int i = 0; i < lidar.beams; ++i) {
    const double fov = lidar.fov_deg * M_PI / 180.0;
    // A full circle has no edge to repeat; a partial fan spans its edges.
    const double a = lidar.fov_deg >= 360.0 ? -M_PI + 2.0 * M_PI * (i + 0.5) / lidar.beams
                                            : -0.5 * fov + (lidar.beams == 1 ? 0.5 * fov : fov * i / (lidar.beams - 1));
    lidar_dirs_.emplace_back(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 0.0f);
  }
}

ObservationBuilder::~ObservationBuilder() = default;
ObservationBuilder::ObservationBuilder(ObservationBuilder&&) noexcept = default;

bool ObservationBuilder::needsScene() const { return options_.lidar.beams > 0 || options_.camera.width > 0; }

Value ObservationBuilder::observe(const vehicle::VehicleState& state, const track::Projection& where,
                                  const sensors::RayScene* scene, int own_vehicle) {
  Value obs;
  observeInto(state, where, scene, own_vehicle, &obs);
  return obs;
}

void ObservationBuilder::observeInto(const vehicle::VehicleState& state, const track::Projection& where,
                                     const sensors::RayScene* scene, int own_vehicle, Value* out) {
  const auto& o = options_;
  Value& obs = *out;
  if (o.speed) obs.at("speed").numbers.assign({state.speed});
  const Eigen::Vector3d& v = state.body_linear_velocity;
  const Eigen::Vector3d& w = state.body_angular_velocity;
  if (o.velocity) obs.at("velocity").numbers.assign({v.x(), v.y(), v.z()});
  if (o.angular_velocity) obs.at("angular_velocity").numbers.assign({w.x(), w.y(), w.z()});
  if (o.imu) {
    const sensors::ImuSample imu =
        sensors::sampleImu(sensors::motionOf(state), sensors::Mount(), sensors::ImuSpec(), gravity_, nullptr);
    const Eigen::Vector3d& a = imu.linear_acceleration;
    const Eigen::Vector3d& g = imu.angular_velocity;
    obs.at("imu").numbers.assign({a.x(), a.y(), a.z(), g.x(), g.y(), g.z()});
  }
  if (!o.waypoint_distances.empty()) {
    const double yaw = track::yawOf(state.pose.orientation);
    const double c = std::cos(yaw), s = std::sin(yaw);
    const Eigen::Vector2d at = state.pose.position.head<2>();
    Value& waypoints = obs.at("waypoints_information");
    for (std::size_t k = 0; k < o.waypoint_distances.size(); ++k) {
      const track::TrackPose p = track_->poseAt(where.s + o.waypoint_distances[k]);
      const Eigen::Vector2d delta = p.position - at;
      waypoints.at(waypoint_keys_[k])
          .numbers.assign({c * delta.x() + s * delta.y(), -s * delta.x() + c * delta.y(),
                           track::wrapAngle(p.heading - yaw), p.width_left + p.width_right});
    }
  }
  if (needsScene()) {
    if (!scene) throw std::invalid_argument("observe: camera and LiDAR observations need the ray scene");
    const Eigen::Isometry3d base = sensors::poseOf(state);
    if (o.lidar.beams > 0) {
      std::vector<Eigen::Vector3f> dirs(lidar_dirs_.size());
      const Eigen::Matrix3f rotation = base.linear().cast<float>();
      for (std::size_t i = 0; i < dirs.size(); ++i) dirs[i] = rotation * lidar_dirs_[i];
      std::vector<sensors::RayHit> hits(dirs.size());
      const Eigen::Vector3d origin = base * Eigen::Vector3d(0.0, 0.0, o.lidar.height);
      scene->cast(origin, dirs.data(), dirs.size(), own_vehicle, static_cast<float>(o.lidar.max_range), false,
                  hits.data());
      Value& ranges = obs.at("lidar");
      ranges.numbers.clear();
      ranges.numbers.reserve(hits.size());
      for (const auto& h : hits)
        ranges.numbers.push_back(h.hit ? std::min<double>(h.distance, o.lidar.max_range) : o.lidar.max_range);
    }
    if (camera_) {
      sensors::CameraChannels channels;
      channels.rgb = o.camera.rgb;
      channels.depth = o.camera.depth;
      sensors::CameraFrame frame;
      camera_->render(*scene, base * sensors::mountTransform(o.camera.mount), own_vehicle, channels, &frame);
      if (o.camera.rgb) obs.at("camera_rgb").numbers.assign(frame.rgb.begin(), frame.rgb.end());
      if (o.camera.depth) {
        auto& depth = obs.at("camera_depth").numbers;
        depth.clear();
        depth.reserve(frame.depth.size());
        for (float d : frame.depth)
          depth.push_back(std::isfinite(d) ? std::min<double>(d, o.camera.max_depth) : o.camera.max_depth);
      }
    }
  }
}

}  // namespace roar::rl

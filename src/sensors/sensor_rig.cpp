#include "roar/sensors/sensor_rig.h"

#include <cmath>

namespace roar::sensors {

namespace {

constexpr double kTimeEpsilon = 1e-9;

bool sameMount(const Mount& a, const Mount& b) {
  return a.position == b.position && a.roll == b.roll && a.pitch == b.pitch && a.yaw == b.yaw;
}

}  // namespace

struct SensorRig::Sensor {
  Sensor(const SensorSpec& s, double now) : spec(s), rng(s.seed) {
    if (s.type == SensorType::kLidar) lidar = std::make_unique<SpinningLidar>(s.lidar, s.seed);
    markDone(now);
  }
  // Due at multiples of the period: k / rate, so the schedule never drifts.
  bool due(double time) const { return time + kTimeEpsilon >= static_cast<double>(next) / spec.rate; }
  double markDone(double time) {
    const double last = last_time;
    last_time = time;
    next = static_cast<long>(std::floor(time * spec.rate + kTimeEpsilon)) + 1;
    return last;
  }

  SensorSpec spec;
  std::mt19937 rng;
  long next = 1;
  double last_time = 0.0;
  std::unique_ptr<SpinningLidar> lidar;
  std::vector<LidarPoint> points;
};

struct SensorRig::CameraGroup {
  std::vector<Sensor*> members;
  CameraChannels channels;
  std::unique_ptr<CameraRenderer> renderer;
  CameraFrame frame;
};

SensorRig::SensorRig(const std::vector<SensorSpec>& specs, const RigTiming& timing, const track::GeoOrigin& origin,
                     double start_time)
    : timing_(timing), origin_(origin) {
  for (const auto& s : specs) add(s, start_time);
}

SensorRig::~SensorRig() = default;

void SensorRig::add(const SensorSpec& spec, double now) {
  validate(spec, "sensor set");
  for (const auto& s : sensors_) {
    if (s->spec.name == spec.name) throw SensorSpecError("sensor '" + spec.name + "': the car already has a sensor of that name");
  }
  const bool ray_sensor = isCamera(spec.type) || spec.type == SensorType::kLidar;
  const double limit = 1.0 / (ray_sensor ? timing_.control_dt : timing_.physics_dt);
  if (spec.rate > limit * (1 + 1e-9)) {
    throw SensorSpecError("sensor '" + spec.name + "': field 'rate' " + std::to_string(spec.rate) + " Hz is faster than " +
                          (ray_sensor ? "the control rate " : "the physics rate ") + std::to_string(limit) +
                          " Hz; lower the rate or " + (ray_sensor ? "control_dt" : "physics_dt"));
  }
  sensors_.push_back(std::make_unique<Sensor>(spec, now));
  rebuildCameraGroups();
}

bool SensorRig::remove(const std::string& name) {
  for (auto it = sensors_.begin(); it != sensors_.end(); ++it) {
    if ((*it)->spec.name == name) {
      sensors_.erase(it);
      rebuildCameraGroups();
      return true;
    }
  }
  return false;
}

std::vector<SensorSpec> SensorRig::specs() const {
  std::vector<SensorSpec> out;
  for (const auto& s : sensors_) out.push_back(s->spec);
  return out;
}

void SensorRig::rebuildCameraGroups() {
  camera_groups_.clear();
  for (const auto& s : sensors_) {
    if (!isCamera(s->spec.type)) continue;
    CameraGroup* group = nullptr;
    for (auto& g : camera_groups_) {
      const SensorSpec& first = g->members.front()->spec;
      if (sameMount(first.mount, s->spec.mount) && first.rate == s->spec.rate && first.camera.fov_deg == s->spec.camera.fov_deg &&
          first.camera.width == s->spec.camera.width && first.camera.height == s->spec.camera.height) {
        group = g.get();
      }
    }
    if (!group) {
      camera_groups_.push_back(std::make_unique<CameraGroup>());
      group = camera_groups_.back().get();
      group->renderer = std::make_unique<CameraRenderer>(s->spec.camera);
    }
    group->members.push_back(s.get());
    switch (s->spec.type) {
      case SensorType::kCameraRgb: group->channels.rgb = true; break;
      case SensorType::kCameraGrey: group->channels.grey = true; break;
      case SensorType::kCameraDepth: group->channels.depth = true; break;
      default: group->channels.semantic = true; break;
    }
  }
}

void SensorRig::sampleMotion(double time, const BodyMotion& motion, SensorSink& sink) {
  for (auto& s : sensors_) {
    const SensorType type = s->spec.type;
    if (isCamera(type) || type == SensorType::kLidar || !s->due(time)) continue;
    s->markDone(time);
    if (type == SensorType::kImu) {
      sink.imu(s->spec, time, sampleImu(motion, s->spec.mount, s->spec.imu, timing_.gravity, &s->rng));
    } else if (type == SensorType::kGnss) {
      sink.gnss(s->spec, time, sampleGnss(motion, s->spec.mount, s->spec.gnss, origin_, &s->rng));
    } else {
      sink.velocity(s->spec, time, sampleVelocity(motion, s->spec.mount));
    }
  }
}

void SensorRig::sampleRays(double time, const RayScene& scene, const Eigen::Isometry3d& base_in_map, int own_vehicle,
                           SensorSink& sink) {
  for (auto& g : camera_groups_) {
    Sensor& lead = *g->members.front();
    if (!lead.due(time)) continue;
    for (Sensor* m : g->members) m->markDone(time);
    g->renderer->render(scene, base_in_map * mountTransform(lead.spec.mount), own_vehicle, g->channels, &g->frame);
    for (Sensor* m : g->members) sink.camera(m->spec, time, g->frame, g->renderer->intrinsics());
  }
  for (auto& s : sensors_) {
    if (s->spec.type != SensorType::kLidar || !s->due(time)) continue;
    const double last = s->markDone(time);
    s->lidar->scan(scene, base_in_map * mountTransform(s->spec.mount), own_vehicle, time - last, &s->points);
    sink.lidar(s->spec, time, s->points);
  }
}

}  // namespace roar::sensors

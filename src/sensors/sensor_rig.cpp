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
    if (s.type == SensorType::kOccupancyMap) occupancy = std::make_unique<OccupancyMapRenderer>(s.occupancy);
    if (s.type == SensorType::kRadar) radar = std::make_unique<Radar>(s.radar, s.seed);
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
  std::unique_ptr<OccupancyMapRenderer> occupancy;
  OccupancyFrame occupancy_frame;
  std::unique_ptr<Radar> radar;
  std::vector<RadarDetection> detections;
};

struct SensorRig::CameraGroup {
  std::vector<Sensor*> members;
  CameraChannels channels;
  std::unique_ptr<CameraRenderer> renderer;
  CameraFrame frame;
};

SensorRig::SensorRig(const std::vector<SensorSpec>& specs, const RigTiming& timing, const track::GeoOrigin& origin,
                     double start_time, const MountBounds& bounds)
    : timing_(timing), origin_(origin), bounds_(bounds) {
  for (const auto& s : specs) add(s, start_time);
}

SensorRig::~SensorRig() = default;

void SensorRig::add(const SensorSpec& spec, double now) {
  validate(spec, "sensor set", bounds_);
  for (const auto& s : sensors_) {
    if (s->spec.name == spec.name)
      throw SensorSpecError("sensor '" + spec.name + "': the car already has a sensor of that name");
  }
  checkRate(spec, timing_.control_dt, timing_.physics_dt);
  checkBudget(totalLoad(specs()), spec, kCarSensorBudget);
  sensors_.push_back(std::make_unique<Sensor>(spec, now));
  rebuildCameraGroups();
}

void SensorRig::checkRate(const SensorSpec& spec, double control_dt, double physics_dt) {
  const bool ray_sensor = castsRays(spec.type);
  const double limit = 1.0 / (ray_sensor ? control_dt : physics_dt);
  if (spec.rate > limit * (1 + 1e-9)) {
    throw SensorSpecError("sensor '" + spec.name + "': rate: " + std::to_string(spec.rate) + " Hz is faster than " +
                          (ray_sensor ? "the control rate " : "the physics rate ") + std::to_string(limit) +
                          " Hz; lower the rate or " + (ray_sensor ? "control_dt" : "physics_dt"));
  }
}

void SensorRig::setTiming(double control_dt, double physics_dt) {
  for (const auto& s : sensors_) checkRate(s->spec, control_dt, physics_dt);
  timing_.control_dt = control_dt;
  timing_.physics_dt = physics_dt;
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
      if (sameMount(first.mount, s->spec.mount) && first.rate == s->spec.rate &&
          first.camera.fov_deg == s->spec.camera.fov_deg && first.camera.width == s->spec.camera.width &&
          first.camera.height == s->spec.camera.height) {
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
      case SensorType::kCameraRgb:
        group->channels.rgb = true;
        break;
      case SensorType::kCameraGrey:
        group->channels.grey = true;
        break;
      case SensorType::kCameraDepth:
        group->channels.depth = true;
        break;
      default:
        group->channels.semantic = true;
        break;
    }
  }
}

void SensorRig::sampleMotion(double time, const BodyMotion& motion, SensorSink& sink) {
  for (auto& s : sensors_) {
    const SensorType type = s->spec.type;
    if (castsRays(type) || !s->due(time)) continue;
    s->markDone(time);
    if (type == SensorType::kImu) {
      sink.imu(s->spec, time, sampleImu(motion, s->spec.mount, s->spec.imu, timing_.gravity, &s->rng));
    } else if (type == SensorType::kGnss) {
      sink.gnss(s->spec, time, sampleGnss(motion, s->spec.mount, s->spec.gnss, origin_, &s->rng));
    } else if (type == SensorType::kVelocimeter) {
      sink.velocity(s->spec, time, sampleVelocity(motion, s->spec.mount));
    } else {
      sink.vector(s->spec, time, sampleVector(s->spec, motion, timing_.gravity, &s->rng));
    }
  }
}

bool SensorRig::rendered(const CameraGroup& group, SensorSink& sink) {
  for (const Sensor* m : group.members) {
    if (!m->spec.camera.on_demand || sink.wanted(m->spec)) return true;
  }
  return false;
}

bool SensorRig::castsRaysAt(double time, SensorSink& sink) const {
  for (const auto& g : camera_groups_) {
    if (g->members.front()->due(time) && rendered(*g, sink)) return true;
  }
  for (const auto& s : sensors_) {
    if (castsRays(s->spec.type) && !isCamera(s->spec.type) && s->due(time)) return true;
  }
  return false;
}

void SensorRig::sampleRays(double time, const RayScene& scene, const Eigen::Isometry3d& base_in_map, int own_vehicle,
                           SensorSink& sink) {
  for (auto& g : camera_groups_) {
    Sensor& lead = *g->members.front();
    if (!lead.due(time)) continue;
    for (Sensor* m : g->members) m->markDone(time);
    if (!rendered(*g, sink)) {
      for (Sensor* m : g->members) sink.deferred(m->spec, time);
      continue;
    }
    g->renderer->render(scene, base_in_map * mountTransform(lead.spec.mount), -1, g->channels, &g->frame);
    for (Sensor* m : g->members) sink.camera(m->spec, time, g->frame, g->renderer->intrinsics());
  }
  for (auto& s : sensors_) {
    const SensorType type = s->spec.type;
    if (!castsRays(type) || isCamera(type) || !s->due(time)) continue;
    const double last = s->markDone(time);
    const Eigen::Isometry3d sensor_in_map = base_in_map * mountTransform(s->spec.mount);
    if (type == SensorType::kLidar) {
      s->lidar->scan(scene, sensor_in_map, own_vehicle, time - last, &s->points);
      sink.lidar(s->spec, time, s->points);
    } else if (type == SensorType::kRadar) {
      const Eigen::Vector3d velocity = scene.velocityAt(own_vehicle, sensor_in_map.translation());
      s->radar->scan(scene, sensor_in_map, velocity, own_vehicle, time - last, &s->detections);
      sink.radar(s->spec, time, s->detections);
    } else {
      s->occupancy->render(scene, sensor_in_map, own_vehicle, &s->occupancy_frame);
      sink.occupancy(s->spec, time, s->occupancy_frame);
    }
  }
}

const CameraFrame& SensorRig::renderCamera(const std::string& name, const RayScene& scene,
                                           const Eigen::Isometry3d& base_in_map, CameraIntrinsics* intrinsics) {
  for (auto& g : camera_groups_) {
    for (Sensor* m : g->members) {
      if (m->spec.name != name) continue;
      g->renderer->render(scene, base_in_map * mountTransform(m->spec.mount), -1, g->channels, &g->frame);
      if (intrinsics) *intrinsics = g->renderer->intrinsics();
      return g->frame;
    }
  }
  throw SensorSpecError("sensor '" + name + "': the car has no camera of that name");
}

}  // namespace roar::sensors

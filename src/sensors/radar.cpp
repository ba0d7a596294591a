#include "roar/sensors/radar.h"

#include <cmath>

namespace roar::sensors {

Radar::Radar(const RadarSpec& spec, unsigned seed) : spec_(spec), rng_(seed) {}

void Radar::scan(const RayScene& scene, const Eigen::Isometry3d& sensor_in_map, const Eigen::Vector3d& sensor_velocity,
                 int own_vehicle, double dt, std::vector<RadarDetection>* detections) {
  detections->clear();
  const double wanted = spec_.points_per_second * dt + carry_;
  const auto count = static_cast<std::size_t>(std::floor(wanted));
  carry_ = wanted - static_cast<double>(count);
  if (count == 0) return;
  // CARLA's spread: a point of the unit disc (sqrt of a uniform radius) scaled to the cone's half-widths.
  const double half_h = std::tan(0.5 * spec_.horizontal_fov * M_PI / 180.0);
  const double half_v = std::tan(0.5 * spec_.vertical_fov * M_PI / 180.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::Matrix3d to_map = sensor_in_map.linear();
  dirs_.resize(count);
  std::vector<Eigen::Vector3d> local(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double radius = std::sqrt(unit(rng_)), angle = 2.0 * M_PI * unit(rng_);
    local[i] = Eigen::Vector3d(1.0, half_h * radius * std::cos(angle), half_v * radius * std::sin(angle)).normalized();
    dirs_[i] = (to_map * local[i]).cast<float>();
  }
  hits_.resize(count);
  const Eigen::Vector3d origin = sensor_in_map.translation();
  scene.cast(origin, dirs_.data(), count, own_vehicle, static_cast<float>(spec_.max_distance), false, hits_.data());
  for (std::size_t i = 0; i < count; ++i) {
    const RayHit& h = hits_[i];
    if (!h.hit) continue;
    const Eigen::Vector3d dir = dirs_[i].cast<double>();
    const Eigen::Vector3d point = origin + dir * h.distance;
    const double velocity = (scene.velocityAt(h.vehicle, point) - sensor_velocity).dot(dir);
    const Eigen::Vector3d& d = local[i];
    detections->push_back({static_cast<float>(velocity), static_cast<float>(-std::atan2(d.y(), d.x())),
                           static_cast<float>(std::atan2(d.z(), std::hypot(d.x(), d.y()))), h.distance});
  }
}

}  // namespace roar::sensors

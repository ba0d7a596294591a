#include "roar/sensors/lidar.h"

#include <cmath>

namespace roar::sensors {

namespace {
constexpr double kDeg = M_PI / 180.0;
constexpr double kAttenuation = 0.004;  // 1/m, CARLA's default atmospheric attenuation rate
}  // namespace

SpinningLidar::SpinningLidar(const LidarSpec& spec, unsigned seed) : spec_(spec), rng_(seed) {
  for (int i = 0; i < spec.num_lasers; ++i) {
    const double t = spec.num_lasers == 1 ? 0.5 : static_cast<double>(i) / (spec.num_lasers - 1);
    elevations_.push_back((spec.upper_fov + t * (spec.lower_fov - spec.upper_fov)) * kDeg);
  }
  // A limited horizontal field of view is centred on the sensor's x axis.
  azimuth_deg_ = spec.horizontal_fov >= 360.0 ? 0.0 : -0.5 * spec.horizontal_fov;
}

void SpinningLidar::scan(const RayScene& scene, const Eigen::Isometry3d& sensor_in_map, int own_vehicle, double dt,
                         std::vector<LidarPoint>* points) {
  points->clear();
  const double firings_exact = spec_.points_per_second * dt / spec_.num_lasers + carry_;
  const int firings = static_cast<int>(std::floor(firings_exact));
  carry_ = firings_exact - firings;
  if (firings == 0) return;
  // The head turns at rotation_frequency; firings are spread evenly over the angle swept in dt.
  const double sweep_deg = spec_.rotation_frequency * 360.0 * dt;
  const double step_deg = sweep_deg / firings;
  const std::size_t rays = static_cast<std::size_t>(firings) * elevations_.size();
  local_dirs_.resize(rays);
  dirs_.resize(rays);
  hits_.resize(rays);
  const Eigen::Matrix3f rotation = sensor_in_map.linear().cast<float>();
  std::size_t k = 0;
  for (int f = 0; f < firings; ++f) {
    double az = azimuth_deg_ + f * step_deg;
    if (spec_.horizontal_fov < 360.0) {
      // Sweep back and forth is not what CARLA does: it wraps within the field of view.
      az = -0.5 * spec_.horizontal_fov + std::fmod(az + 0.5 * spec_.horizontal_fov, spec_.horizontal_fov);
    }
    const double a = az * kDeg;
    for (double el : elevations_) {
      local_dirs_[k] =
          Eigen::Vector3f(static_cast<float>(std::cos(el) * std::cos(a)),
                          static_cast<float>(std::cos(el) * std::sin(a)), static_cast<float>(std::sin(el)));
      dirs_[k] = rotation * local_dirs_[k];
      ++k;
    }
  }
  azimuth_deg_ = std::fmod(azimuth_deg_ + sweep_deg, 360.0);
  scene.cast(sensor_in_map.translation(), dirs_.data(), rays, own_vehicle, static_cast<float>(spec_.max_distance),
             false, hits_.data());
  std::normal_distribution<float> noise(0.0f, static_cast<float>(spec_.noise_std));
  points->reserve(rays);
  for (std::size_t i = 0; i < rays; ++i) {
    const RayHit& hit = hits_[i];
    if (!hit.hit) continue;
    float range = hit.distance;
    if (spec_.noise_std > 0) range += noise(rng_);
    const float incidence = std::abs(hit.normal.dot(dirs_[i]));
    const float intensity = hit.reflectivity * (0.3f + 0.7f * incidence) * std::exp(-kAttenuation * hit.distance);
    const Eigen::Vector3f p = local_dirs_[i] * range;
    points->push_back({p.x(), p.y(), p.z(), intensity});
  }
}

}  // namespace roar::sensors

#include "roar/sensors/occupancy_map.h"

#include <cmath>

#include "roar/track/heading.h"

namespace roar::sensors {

namespace {
// Rays start this far above the sensor and reach this far: above any barrier or car, below any hill
// within the image.
constexpr double kRayHeight = 200.0;
constexpr float kRayLength = 400.0f;
}  // namespace

OccupancyMapRenderer::OccupancyMapRenderer(const OccupancyMapSpec& spec) : spec_(spec) {
  const double along = spec.height_m / spec.height, across = spec.width_m / spec.width;
  offsets_.reserve(static_cast<std::size_t>(spec.width) * spec.height);
  for (int row = 0; row < spec.height; ++row) {
    for (int col = 0; col < spec.width; ++col) {
      offsets_.emplace_back((0.5 * spec.height - row - 0.5) * along, (0.5 * spec.width - col - 0.5) * across);
    }
  }
  origins_.resize(offsets_.size());
  hits_.resize(offsets_.size());
}

void OccupancyMapRenderer::render(const RayScene& scene, const Eigen::Isometry3d& sensor_in_map, int own_vehicle,
                                  OccupancyFrame* frame) {
  const Eigen::Vector3d centre = sensor_in_map.translation();
  const Eigen::Vector3d forward_3d = sensor_in_map.linear().col(0);
  const double yaw = std::atan2(forward_3d.y(), forward_3d.x());
  const Eigen::Vector2d forward = track::forwardOf(yaw), left = track::leftOf(yaw);
  for (std::size_t k = 0; k < offsets_.size(); ++k) {
    const Eigen::Vector2d p = centre.head<2>() + offsets_[k].x() * forward + offsets_[k].y() * left;
    origins_[k] = Eigen::Vector3d(p.x(), p.y(), centre.z() + kRayHeight);
  }
  scene.castParallel(origins_.data(), Eigen::Vector3f(0, 0, -1), origins_.size(), own_vehicle, kRayLength,
                     hits_.data());
  frame->width = spec_.width;
  frame->height = spec_.height;
  frame->pixels.resize(hits_.size());
  for (std::size_t k = 0; k < hits_.size(); ++k) {
    const SemanticClass c = hits_[k].hit ? hits_[k].semantic : SemanticClass::kSky;
    frame->pixels[k] = c == SemanticClass::kVehicle ? kOccupancyVehicle
                       : c == SemanticClass::kRoad || c == SemanticClass::kLaneMarking || c == SemanticClass::kKerb
                           ? kOccupancyRoad
                           : kOccupancyElsewhere;
  }
}

}  // namespace roar::sensors

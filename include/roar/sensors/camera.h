#pragma once
// Pinhole cameras rendered by ray casting. One cast of a mount gives every channel at once: colour,
// greyscale, depth and semantic class.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "roar/sensors/ray_scene.h"
#include "roar/sensors/sensor_spec.h"

namespace roar::sensors {

// Intrinsics as in sensor_msgs/CameraInfo: square pixels, principal point at the image centre.
struct CameraIntrinsics {
  double fx, fy, cx, cy;
  int width, height;
};
CameraIntrinsics intrinsicsOf(const CameraSpec& spec);

// Linear light (0..1, clamped) to an 8-bit channel with gamma 2.2: round(255 * linear^(1/2.2)).
std::uint8_t gammaEncode(float linear);

// Body frame of a sensor (x forward, y left, z up) -> optical frame (z forward, x right, y down).
Eigen::Matrix3d opticalFromBody();

struct CameraChannels {
  bool rgb = false, grey = false, depth = false, semantic = false;
};

struct CameraFrame {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;       // rgb8, row-major
  std::vector<std::uint8_t> grey;      // mono8
  std::vector<float> depth;            // 32FC1: metres along the optical axis; +inf where nothing was hit
  std::vector<std::uint8_t> semantic;  // mono8 SemanticClass ids
};

class CameraRenderer {
 public:
  explicit CameraRenderer(const CameraSpec& spec, float max_distance = 1000.0f);
  // sensor_in_map: the camera's body frame (x forward) in the map frame.
  void render(const RayScene& scene, const Eigen::Isometry3d& sensor_in_map, int own_vehicle,
              const CameraChannels& channels, CameraFrame* frame);
  const CameraIntrinsics& intrinsics() const { return intrinsics_; }

 private:
  static constexpr std::size_t kRaysPerChunk = 1024;  // 64 packets of 16; their hits fit the L2 cache
  void shadePixel(std::size_t ray, const RayHit& hit, const Eigen::Vector3f& dir, const CameraChannels& channels,
                  CameraFrame* frame) const;
  CameraIntrinsics intrinsics_;
  float max_distance_;
  std::vector<Eigen::Vector3f> body_dirs_;  // unit ray per pixel in the camera body frame, 4x4 tiles in order
  std::vector<float> optical_z_;            // depth = distance * optical_z
  std::vector<int> pixel_of_ray_;
  // One chunk of rays at a time, cast and shaded while its hits are still in the cache.
  std::vector<Eigen::Vector3f> world_dirs_;
  std::vector<RayHit> hits_;
};

}  // namespace roar::sensors

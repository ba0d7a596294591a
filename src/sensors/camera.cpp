#include "roar/sensors/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace roar::sensors {

namespace {

// Simple daylight: a sun, sky light from above, and a sky colour that brightens towards the horizon.
const Eigen::Vector3f kSunDirection = Eigen::Vector3f(0.35f, -0.3f, 0.89f).normalized();

Eigen::Vector3f skyColour(const Eigen::Vector3f& dir) {
  const float up = std::clamp(dir.z(), 0.0f, 1.0f);
  return Eigen::Vector3f(0.70f, 0.80f, 0.95f) * (1.0f - up) + Eigen::Vector3f(0.25f, 0.45f, 0.85f) * up;
}

// Linear light to an 8-bit value with gamma 2.2, so that the image looks right on a screen: the byte of
// round(255 * linear^(1/2.2)), found from the linear thresholds between bytes instead of a pow per
// channel (which cost a third of a small frame).
class GammaEncoder {
 public:
  GammaEncoder() {
    for (int k = 0; k < 255; ++k) threshold_[k] = std::pow((k + 0.5f) / 255.0f, 2.2f);
    threshold_[255] = 2.0f;  // above any clamped value: byte 255 is never stepped past
    for (int i = 0; i <= kBuckets; ++i) {
      const float x = static_cast<float>(i) / kBuckets;
      int b = 0;
      while (b < 255 && x >= threshold_[b]) ++b;
      bucket_start_[i] = static_cast<std::uint8_t>(b);
    }
  }
  std::uint8_t operator()(float linear) const {
    const float x = std::clamp(linear, 0.0f, 1.0f);
    int b = bucket_start_[static_cast<int>(x * kBuckets)];
    // Above the darkest buckets a bucket holds at most one threshold: one step, taken without a branch
    // (the branch, taken or not at random, had cost more than the rest). Below them, a few more.
    b += x >= threshold_[b];
    while (x >= threshold_[b]) ++b;
    return static_cast<std::uint8_t>(b);
  }

 private:
  static constexpr int kBuckets = 4096;
  float threshold_[256];
  std::uint8_t bucket_start_[kBuckets + 1];
};

// One table for the process, built when the library loads: the renderer calls it three times a pixel, and
// through the exported function (a call through the PLT and a guard on a function's static each time) it
// took a fifth of an 84x84 frame.
const GammaEncoder kGamma;

}  // namespace

std::uint8_t gammaEncode(float linear) { return kGamma(linear); }

CameraIntrinsics intrinsicsOf(const CameraSpec& spec) {
  CameraIntrinsics k;
  k.width = spec.width;
  k.height = spec.height;
  k.fx = 0.5 * spec.width / std::tan(0.5 * spec.fov_deg * M_PI / 180.0);
  k.fy = k.fx;
  k.cx = 0.5 * spec.width;
  k.cy = 0.5 * spec.height;
  return k;
}

Eigen::Matrix3d opticalFromBody() {
  Eigen::Matrix3d m;
  m << 0, -1, 0,  //
      0, 0, -1,   //
      1, 0, 0;
  return m;
}

CameraRenderer::CameraRenderer(const CameraSpec& spec, float max_distance)
    : intrinsics_(intrinsicsOf(spec)), max_distance_(max_distance) {
  const int w = spec.width, h = spec.height;
  const Eigen::Matrix3d body_from_optical = opticalFromBody().transpose();
  // Rays in 4x4 tiles: neighbouring rays travel together through the scene (Embree packets of 16).
  for (int ty = 0; ty < h; ty += 4) {
    for (int tx = 0; tx < w; tx += 4) {
      for (int y = ty; y < std::min(ty + 4, h); ++y) {
        for (int x = tx; x < std::min(tx + 4, w); ++x) {
          const Eigen::Vector3d optical((x + 0.5 - intrinsics_.cx) / intrinsics_.fx,
                                        (y + 0.5 - intrinsics_.cy) / intrinsics_.fy, 1.0);
          const Eigen::Vector3d unit = optical.normalized();
          body_dirs_.push_back((body_from_optical * unit).cast<float>());
          optical_z_.push_back(static_cast<float>(unit.z()));
          pixel_of_ray_.push_back(y * w + x);
        }
      }
    }
  }
  world_dirs_.resize(std::min(kRaysPerChunk, body_dirs_.size()));
  hits_.resize(world_dirs_.size());
}

void CameraRenderer::render(const RayScene& scene, const Eigen::Isometry3d& sensor_in_map, int own_vehicle,
                            const CameraChannels& channels, CameraFrame* frame) {
  const std::size_t n = body_dirs_.size();
  const Eigen::Matrix3f rotation = sensor_in_map.linear().cast<float>();
  frame->width = intrinsics_.width;
  frame->height = intrinsics_.height;
  frame->rgb.resize(channels.rgb ? 3 * n : 0);
  frame->grey.resize(channels.grey ? n : 0);
  frame->depth.resize(channels.depth ? n : 0);
  frame->semantic.resize(channels.semantic ? n : 0);
  for (std::size_t first = 0; first < n; first += kRaysPerChunk) {
    const std::size_t count = std::min(kRaysPerChunk, n - first);
    for (std::size_t k = 0; k < count; ++k) world_dirs_[k] = rotation * body_dirs_[first + k];
    scene.cast(sensor_in_map.translation(), world_dirs_.data(), count, own_vehicle, max_distance_, true, hits_.data());
    for (std::size_t k = 0; k < count; ++k) shadePixel(first + k, hits_[k], world_dirs_[k], channels, frame);
  }
}

void CameraRenderer::shadePixel(std::size_t ray, const RayHit& hit, const Eigen::Vector3f& dir,
                                const CameraChannels& channels, CameraFrame* frame) const {
  const int p = pixel_of_ray_[ray];
  if (channels.depth) {
    frame->depth[p] = hit.hit ? hit.distance * optical_z_[ray] : std::numeric_limits<float>::infinity();
  }
  if (channels.semantic) frame->semantic[p] = static_cast<std::uint8_t>(hit.semantic);
  if (!channels.rgb && !channels.grey) return;
  Eigen::Vector3f colour;
  if (!hit.hit) {
    colour = skyColour(dir);
  } else {
    const float sun = std::max(0.0f, hit.normal.dot(kSunDirection));
    const float sky = 0.35f + 0.15f * hit.normal.z();
    colour = hit.albedo * (0.9f * sun + sky);
    // Distance haze towards the horizon colour.
    const float haze = 1.0f - std::exp(-hit.distance / 1500.0f);
    colour = colour * (1.0f - haze) + Eigen::Vector3f(0.7f, 0.8f, 0.95f) * haze;
  }
  if (channels.rgb) {
    frame->rgb[3 * p] = kGamma(colour.x());
    frame->rgb[3 * p + 1] = kGamma(colour.y());
    frame->rgb[3 * p + 2] = kGamma(colour.z());
  }
  if (channels.grey) frame->grey[p] = kGamma(0.299f * colour.x() + 0.587f * colour.y() + 0.114f * colour.z());
}

}  // namespace roar::sensors

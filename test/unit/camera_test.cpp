#include <gtest/gtest.h>

#include "roar/sensors/camera.h"
#include "sensor_test_scene.h"

using namespace roar;
using sensors::CameraChannels;
using sensors::CameraFrame;
using sensors::CameraRenderer;
using sensors::SemanticClass;

namespace {

CameraChannels all() {
  CameraChannels c;
  c.rgb = c.grey = c.depth = c.semantic = true;
  return c;
}

sensors::CameraSpec spec(int w, int h, double fov = 90) {
  sensors::CameraSpec s;
  s.width = w;
  s.height = h;
  s.fov_deg = fov;
  return s;
}

SemanticClass centreClass(const CameraFrame& f) {
  return static_cast<SemanticClass>(f.semantic[(f.height / 2) * f.width + f.width / 2]);
}

}  // namespace

TEST(Camera, GammaEncodingIsRoundedPowerOneOverTwoPointTwo) {
  int checked = 0;
  for (int i = -100; i <= 1100000; ++i) {
    const float linear = i / 1000000.0f;
    const float x = std::clamp(linear, 0.0f, 1.0f);
    const double exact = 255.0 * std::pow(static_cast<double>(x), 1.0 / 2.2);
    // Values within a hair of a rounding boundary may go either way in float arithmetic.
    if (std::abs(exact - std::floor(exact) - 0.5) < 1e-4) continue;
    ASSERT_EQ(sensors::gammaEncode(linear), static_cast<int>(std::lround(exact))) << "linear " << linear;
    ++checked;
  }
  EXPECT_GT(checked, 1000000);
  EXPECT_EQ(sensors::gammaEncode(-1.0f), 0);
  EXPECT_EQ(sensors::gammaEncode(2.0f), 255);
}

TEST(Camera, IntrinsicsFromFieldOfView) {
  const auto k = sensors::intrinsicsOf(spec(800, 600, 90));
  EXPECT_NEAR(k.fx, 400.0, 1e-9);
  EXPECT_NEAR(k.fy, 400.0, 1e-9);
  EXPECT_EQ(k.cx, 400.0);
  EXPECT_EQ(k.cy, 300.0);
}

TEST(Camera, DepthCameraReadsTheDistanceToABarrier) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  CameraRenderer camera(spec(84, 84));
  CameraFrame frame;
  // On the straight at y = 0, facing the right-hand barrier, whose face stands at y = -9.
  camera.render(scene, test::poseAt(200, 0, 0.5, -M_PI / 2), -1, all(), &frame);
  EXPECT_NEAR(frame.depth[42 * 84 + 42], 9.0, 0.01);
  EXPECT_NEAR(frame.depth[40 * 84 + 10], 9.0, 0.01) << "a flat wall facing the camera: the same depth everywhere";
  EXPECT_EQ(centreClass(frame), SemanticClass::kBarrier);
}

TEST(Camera, APointProjectsToThePixelCameraInfoPredicts) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  CameraRenderer camera(spec(160, 120));
  CameraFrame frame;
  const Eigen::Isometry3d cam = test::poseAt(200, 0, 0.8, -M_PI / 2 + 0.3);
  camera.render(scene, cam, -1, all(), &frame);
  const auto& k = camera.intrinsics();
  // A point on the barrier's face, into the optical frame and through K.
  const Eigen::Vector3d world(205.0, -9.0, 0.4);
  const Eigen::Vector3d optical = sensors::opticalFromBody() * (cam.inverse() * world);
  const double u = k.fx * optical.x() / optical.z() + k.cx, v = k.fy * optical.y() / optical.z() + k.cy;
  ASSERT_TRUE(u >= 0 && u < 160 && v >= 0 && v < 120);
  const int p = static_cast<int>(v) * 160 + static_cast<int>(u);
  EXPECT_EQ(static_cast<SemanticClass>(frame.semantic[p]), SemanticClass::kBarrier);
  EXPECT_NEAR(frame.depth[p], optical.z(), 0.05);
  // And back: every barrier pixel unprojects onto the wall's plane.
  int checked = 0;
  for (int y = 0; y < 120; y += 7) {
    for (int x = 0; x < 160; x += 7) {
      const int q = y * 160 + x;
      if (static_cast<SemanticClass>(frame.semantic[q]) != SemanticClass::kBarrier) continue;
      const double z = frame.depth[q];
      const Eigen::Vector3d o((x + 0.5 - k.cx) / k.fx * z, (y + 0.5 - k.cy) / k.fy * z, z);
      const Eigen::Vector3d w = cam * (sensors::opticalFromBody().transpose() * o);
      if (w.z() > 0.95) continue;  // the top of the wall
      EXPECT_NEAR(w.y(), -9.0, 0.01);
      ++checked;
    }
  }
  EXPECT_GT(checked, 20);
}

TEST(Camera, SemanticIdsMatchWhatIsHit) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  CameraRenderer camera(spec(32, 32, 20));
  CameraFrame f;
  camera.render(scene, test::poseAt(200, 0, 1.5, 0, M_PI / 2 - 0.2), -1, all(), &f);  // down at the road
  EXPECT_EQ(centreClass(f), SemanticClass::kRoad);
  camera.render(scene, test::poseAt(200, 5.6, 1.5, 0, M_PI / 2 - 0.01), -1, all(), &f);  // down at the left edge line
  EXPECT_EQ(centreClass(f), SemanticClass::kLaneMarking);
  camera.render(scene, test::poseAt(200, 0, 1.5, 0, -M_PI / 3), -1, all(), &f);  // up
  EXPECT_EQ(centreClass(f), SemanticClass::kSky);
  EXPECT_TRUE(std::isinf(f.depth[16 * 32 + 16]));
  camera.render(scene, test::poseAt(200, -30, 1.5, 0, M_PI / 3), -1, all(), &f);  // outside the barrier: grass
  EXPECT_EQ(centreClass(f), SemanticClass::kGround);
  camera.render(scene, test::poseAt(466.6, 60, 1.5, 0, M_PI / 2 - 0.01), -1, all(), &f);  // the hairpin's outside kerb
  EXPECT_EQ(centreClass(f), SemanticClass::kKerb);
}

TEST(Camera, ACarInFrontIsSeenButNotTheCarCarryingTheCamera) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  const int ego = scene.addVehicle(test::sedanLooks(), {0.1f, 0.2f, 0.8f});
  const int rival = scene.addVehicle(test::sedanLooks(), {0.8f, 0.1f, 0.1f});
  scene.setVehiclePose(ego, test::poseAt(200, 0, 0));
  scene.setVehiclePose(rival, test::poseAt(215, 0, 0));
  scene.commit();
  CameraRenderer camera(spec(84, 84));
  CameraFrame f;
  camera.render(scene, test::poseAt(200.6, 0, 1.0), ego, all(), &f);  // a camera inside ego's body, at bumper height
  EXPECT_EQ(centreClass(f), SemanticClass::kVehicle);
  EXPECT_NEAR(f.depth[42 * 84 + 42], 215 - 200.6 - 4.69 / 2, 0.01) << "the rival's tail";
  // The rival is red in the RGB image.
  const int p = 3 * (42 * 84 + 42);
  EXPECT_GT(f.rgb[p], 2 * f.rgb[p + 2]);
  // With the rival gone, the road ahead and the sky.
  scene.removeVehicle(rival);
  scene.commit();
  camera.render(scene, test::poseAt(200.6, 0, 1.0), ego, all(), &f);
  EXPECT_NE(centreClass(f), SemanticClass::kVehicle);
}

// Cars are seen from outside only: a camera inside a body sees out of it, as a hood camera does in CARLA.
TEST(Camera, ACameraInsideACarSeesOutOfIt) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  const int ego = scene.addVehicle(test::sedanLooks(), {0.1f, 0.2f, 0.8f});
  scene.setVehiclePose(ego, test::poseAt(200, 0, 0));
  scene.commit();
  CameraRenderer camera(spec(84, 84));
  CameraFrame f;
  camera.render(scene, test::poseAt(200.6, 0, 1.0), -1, all(), &f);  // inside ego, its own car not left out
  EXPECT_NE(centreClass(f), SemanticClass::kVehicle);
  EXPECT_GT(f.depth[42 * 84 + 42], 20.0f) << "the road far ahead, not the inside of the bonnet";
}

// ROAR's runner and examples mount their camera behind and above the car, pitched 10 degrees down: in
// CARLA that picture shows the car, and their viewers are built on it (the sensor rig renders cameras so).
TEST(Camera, AChaseCameraSeesTheCarItRidesOn) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  const int ego = scene.addVehicle(test::sedanLooks(), {0.1f, 0.2f, 0.8f});
  scene.setVehiclePose(ego, test::poseAt(200, 0, 0));
  scene.commit();
  CameraRenderer camera(spec(84, 84));
  CameraFrame f;
  const Eigen::Isometry3d chase = test::poseAt(200 - 2 * 2.35, 0, 3 * 0.7, 0, 10 * M_PI / 180);
  camera.render(scene, chase, -1, all(), &f);
  int car_pixels = 0;
  for (std::size_t i = 0; i < f.semantic.size(); ++i) car_pixels += f.semantic[i] == 6;
  // Seen from 2.35 m behind its tail and 2.1 m up: rows 48 to 63 of 84, below the middle.
  EXPECT_GT(car_pixels, 400) << "the car's tail and roof below the middle of the image";
  EXPECT_EQ(static_cast<SemanticClass>(f.semantic[55 * 84 + 42]), SemanticClass::kVehicle);
  camera.render(scene, chase, ego, all(), &f);
  EXPECT_NE(static_cast<SemanticClass>(f.semantic[55 * 84 + 42]), SemanticClass::kVehicle) << "left out on request";
}

TEST(Camera, TheImageLooksLikeATrack) {
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  CameraRenderer camera(spec(84, 84));
  CameraFrame f;
  camera.render(scene, test::poseAt(100, 0, 1.55, 0, 0.087), -1, all(), &f);
  // Top row: sky, bluish and bright; bottom row centre: asphalt, grey and dark.
  const int top = 3 * (0 * 84 + 42), bottom = 3 * (83 * 84 + 42);
  EXPECT_GT(f.rgb[top + 2], f.rgb[top]);
  EXPECT_GT(f.rgb[top + 2], 150);
  EXPECT_LT(f.rgb[bottom], 130);
  EXPECT_NEAR(f.rgb[bottom], f.rgb[bottom + 2], 10);
  int classes[8] = {};
  for (auto c : f.semantic) ++classes[c];
  for (auto c : {SemanticClass::kSky, SemanticClass::kRoad, SemanticClass::kLaneMarking, SemanticClass::kBarrier}) {
    EXPECT_GT(classes[static_cast<int>(c)], 10) << "class " << static_cast<int>(c) << " in view";
  }
}

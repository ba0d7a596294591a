#pragma once
// Shared by the unit tests: tracks made in code, the shipped data, and reading error messages.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <string>

#include "roar/track/track.h"
#include "roar/vehicle/vehicle_config.h"

namespace roar::test {

inline std::string sourceDir() { return ROAR_SOURCE_DIR; }

// A fresh folder under the system's temporary one, removed with everything in it when it goes.
class TempDir {
 public:
  TempDir()
      : path_(std::filesystem::temp_directory_path() /
              ("roar_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter_++))) {
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  // Writes `text` to the file `name` in it; returns the file's path.
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return (path_ / name).string();
  }
  std::string str() const { return path_.string(); }

 private:
  static inline int counter_ = 0;
  std::filesystem::path path_;
};

// The message of the exception f throws, or "" when it throws none.
inline std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Property tests (issue 17): for every number `number` matches in `text` (its first group the key, its
// last group the value), calls check(key, text with that value replaced, extreme) for each of 0, -1,
// 1e-30, 1e30, 1e300, .nan and .inf. Returns how many numbers it found.
template <typename Check>
int forEachNumberAtExtremes(const std::string& text, const std::regex& number, const Check& check) {
  int found = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number); it != std::sregex_iterator(); ++it, ++found) {
    const std::size_t value = it->size() - 1;
    for (const char* extreme : {"0", "-1", "1e-30", "1e30", "1e300", ".nan", ".inf"}) {
      std::string changed = text;
      changed.replace(it->position(value), it->length(value), extreme);
      check((*it)[1].str(), changed, std::string(extreme));
    }
  }
  return found;
}

// A circle of `radius` around `centre`, driven counter-clockwise, sampled every `spacing` metres.
inline track::Track circleTrack(double radius, double width = 12.0, Eigen::Vector2d centre = {0, 0},
                                double friction = 1.0, double spacing = 2.0) {
  std::vector<track::CentreLinePoint> pts;
  const int n = static_cast<int>(std::round(2 * M_PI * radius / spacing));
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    pts.push_back({centre.x() + radius * std::cos(a), centre.y() + radius * std::sin(a), width / 2, width / 2});
  }
  track::TrackInfo info;
  info.name = "circle";
  info.friction = friction;
  info.ground_friction = friction;  // uniform grip everywhere: physics tests drive on the open ground
  return track::Track(pts, info);
}

// On circleTrack(radius) (centred on the origin): the road's surface at arc length s counter-clockwise from
// angle 0, `lateral` metres to the left of the centre line, as odometry gives a car there.
inline Eigen::Vector3d onCircleTrack(double s, double radius = 100.0, double lateral = 0.0) {
  const double r = radius - lateral;
  return {r * std::cos(s / radius), r * std::sin(s / radius), 0.0};
}

// Open ground for physics tests: a small circuit far away, so the area near the origin is free plane.
inline track::Track openGround(double friction = 1.0) { return circleTrack(60.0, 12.0, {5000.0, 5000.0}, friction); }

inline vehicle::VehicleParams vehicle(const std::string& model) {
  return vehicle::loadVehicleModel(model, sourceDir() + "/urdf", sourceDir() + "/config/vehicles");
}

inline vehicle::VehicleParams sedan() { return vehicle("sedan"); }

}  // namespace roar::test

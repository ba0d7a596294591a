#pragma once
// The package's folders and the defaults a race takes when it names none: the one owner of both, for the
// nodes, the tools, the benchmarks and (through roar_core.layout) the Python side
// (test_build_hygiene test_the_package_layout_is_written_once).
#include <string>

namespace roar::config {

inline constexpr const char* kDefaultModel = "sedan";    // a car model when none is named
inline constexpr const char* kDefaultMap = "roar_ring";  // a map when none is named

// Where each kind of file is under the package's root (the source tree, or an installed share folder).
struct PackageLayout {
  std::string root;
  std::string maps() const { return root + "/maps"; }
  std::string urdf() const { return root + "/urdf"; }
  std::string vehicles() const { return root + "/config/vehicles"; }
  std::string sensors() const { return root + "/config/sensors"; }
  std::string scenarios() const { return root + "/config/scenarios"; }
  std::string rl() const { return root + "/config/rl"; }
  std::string policies() const { return root + "/config/policies"; }  // trained policies (policy.yaml)
};

}  // namespace roar::config

#pragma once
#include <cstdint>

namespace roar::sensors {

// Class ids of the semantic camera (mono8 pixel values). The table is part of the public interface.
enum class SemanticClass : std::uint8_t {
  kSky = 0,  // no hit within range
  kRoad = 1,
  kLaneMarking = 2,  // edge lines and the start/finish line
  kKerb = 3,
  kBarrier = 4,
  kGround = 5,  // grass run-off and everything outside the circuit
  kVehicle = 6,
};

}  // namespace roar::sensors

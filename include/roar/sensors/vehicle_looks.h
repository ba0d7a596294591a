#pragma once
#include <string>

#include "roar/sensors/ray_scene.h"

namespace roar::sensors {

// The visual boxes and cylinders of a URDF, at zero joint positions, as triangles in base_link.
// Links of the material named "body" take the car's paint (colour < 0 in the result). Throws
// std::runtime_error naming the file for an unreadable URDF.
VisualMesh readVehicleLooks(const std::string& urdf_path);

}  // namespace roar::sensors

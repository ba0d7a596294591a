#pragma once
#include <stdexcept>
#include <string>
#include <vector>

#include "roar/vehicle/vehicle_params.h"

namespace roar::vehicle {

class VehicleConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Mass, inertia, centre of mass, body box and wheel positions and sizes from a URDF (urdfdom).
// The wheels are the links named wheel_front_left, wheel_front_right, wheel_rear_left, wheel_rear_right.
void readVehicleUrdf(const std::string& urdf_path, VehicleParams* params);
void readVehicleUrdfString(const std::string& urdf_xml, const std::string& source, VehicleParams* params);

// Drivetrain, tyres, suspension, steering, brakes and aero from YAML; every error names the file and field.
void readVehicleYaml(const std::string& yaml_path, VehicleParams* params);

// A car model there is: `<config_dir>/<model>.yaml` with its `<urdf_dir>/<model>.urdf`.
struct VehicleModelInfo {
  std::string model;      // e.g. hatchback
  std::string blueprint;  // e.g. vehicle.audi.a2 (the yaml's `blueprint`)
  std::string description;
};
std::vector<VehicleModelInfo> listVehicleModels(const std::string& urdf_dir, const std::string& config_dir);
// The model a model name or a blueprint id names; throws VehicleConfigError listing the models and
// blueprints there are.
std::string resolveVehicleModel(const std::string& model_or_blueprint, const std::string& urdf_dir,
                                const std::string& config_dir);

// `<urdf_dir>/<model>.urdf` and `<config_dir>/<model>.yaml` of a model name or a blueprint id; an unknown
// one lists the models and blueprints there are.
VehicleParams loadVehicleModel(const std::string& model_or_blueprint, const std::string& urdf_dir,
                               const std::string& config_dir);

// Throws VehicleConfigError naming the first implausible value.
void validate(const VehicleParams& params, const std::string& source);

}  // namespace roar::vehicle

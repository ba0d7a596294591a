#include "roar/planning/field_planner_sizing.h"

#include "roar/planning/racing_line.h"
#include "roar/planning/vehicle_limits.h"

namespace roar::planning {

FieldPlanner fieldPlannerFor(const track::Track& track, const vehicle::VehicleParams& vehicle, double grip_use,
                             PlannerOptions planner, FieldOptions field) {
  const VehicleLimits limits = vehicleLimits(vehicle, track.info().friction, grip_use);
  planner.line.vehicle_width = vehicle.chassis.box_size.y();
  field.overtake.car.length = vehicle.chassis.box_size.x();
  field.overtake.car.width = vehicle.chassis.box_size.y();
  return FieldPlanner(track, planRacingTrajectory(track, limits, planner), limits, field);
}

}  // namespace roar::planning

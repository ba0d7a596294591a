#pragma once
// The field planner sized to the cars it plans for: one answer for the planner node and the in-process race.
#include "roar/planning/field_planner.h"
#include "roar/track/track.h"
#include "roar/vehicle/vehicle_params.h"

namespace roar::planning {

// The field planner for cars of one model: the racing line and its profile from the model's limits
// (`grip_use` of the road's friction), the line's margins and the overtaking geometry sized to its body.
// The planner node builds one per model in the race; the in-process race, one for its cars' model.
FieldPlanner fieldPlannerFor(const track::Track& track, const vehicle::VehicleParams& vehicle, double grip_use,
                             PlannerOptions planner, FieldOptions field);

}  // namespace roar::planning

#include "roar/planning/overtaking/option_table.h"

namespace roar::planning {

std::vector<OvertakeOptionEntry> overtakeOptionTable(OvertakeOptions* o) {
  auto& sl = o->slipstream;
  return {
      {"margins.lateral", &o->margins.lateral, 0.2, 5.0},
      {"margins.longitudinal", &o->margins.longitudinal, 0.0, 20.0},
      {"margins.edge", &o->margins.edge, 0.0, 5.0},
      {"margins.rejoin_time", &o->margins.rejoin_time, 0.0, 5.0},
      {"margins.follow_gap", &o->margins.follow_gap, 5.0, 200.0},
      {"prediction.horizon", &o->prediction.horizon, 1.0, 20.0},
      {"prediction.sample_step", &o->prediction.sample_step, 0.1, 20.0},
      {"prediction.lateral_lookahead", &o->prediction.lateral_lookahead, 0.0, 10.0},
      {"prediction.plan_trust", &o->prediction.plan_trust, 0.0, 10.0},
      {"prediction.plan_period", &o->prediction.plan_period, 0.005, 1.0},
      {"moves.shift_time", &o->moves.shift_time, 0.2, 10.0},
      {"moves.min_shift_length", &o->moves.min_shift_length, 1.0, 500.0},
      {"moves.offline_grip", &o->moves.offline_grip, 0.1, 1.0},
      {"moves.settle_grip", &o->moves.settle_grip, 0.1, 1.0},
      {"passing.min_gain", &o->passing.min_gain, 0.0, 100.0},
      {"passing.engage_time", &o->passing.engage_time, 0.1, 20.0},
      {"passing.min_speed", &o->passing.min_speed, 0.0, 100.0},
      {"passing.abort_plans", &o->passing.abort_plans, 1, 1000},
      {"passing.stall_time", &o->passing.stall_time, 0.1, 60.0},
      {"passing.retry_plans", &o->passing.retry_plans, 0, 10000},
      {"passing.abort_time", &o->passing.abort_time, 0.3, 20.0},
      {"passing.max_offset", &o->passing.max_offset, 0.5, 50.0},
      {"guard.lateral", &o->guard.lateral, 0.0, 5.0},
      {"guard.time", &o->guard.time, 0.0, 5.0},
      {"guard.predicted", &o->guard.predicted, 0, 1},
      {"blue_flags.enabled", &o->blue_flags.enabled, 0, 1},
      {"blue_flags.time", &o->blue_flags.time, 0.1, 20.0},
      {"defence.enabled", &o->defence.enabled, 0, 1},
      {"defence.time", &o->defence.time, 0.1, 20.0},
      {"defence.shift", &o->defence.shift, 0.1, 10.0},
      {"defence.hold", &o->defence.hold, 0.1, 60.0},
      {"slipstream.enabled", &sl.enabled, 0, 1},
      {"slipstream.max_reduction", &sl.max_reduction, vehicle::kMaxReductionRange.low,
       vehicle::kMaxReductionRange.high},
      {"slipstream.decay_length", &sl.decay_length, vehicle::kDecayLengthRange.low, vehicle::kDecayLengthRange.high},
      {"slipstream.spread_growth", &sl.spread_growth, vehicle::kSpreadGrowthRange.low,
       vehicle::kSpreadGrowthRange.high},
      {"slipstream.max_gap", &sl.max_gap, vehicle::kMaxGapRange.low, vehicle::kMaxGapRange.high},
      {"slipstream.min_speed", &sl.min_speed, vehicle::kMinSpeedRange.low, vehicle::kMinSpeedRange.high},
  };
}

void setOvertakeOption(OvertakeOptions* options, const std::string& name, const std::string& text,
                       const std::string& label) {
  config::setOption(overtakeOptionTable(options), name, text, label);
}

}  // namespace roar::planning

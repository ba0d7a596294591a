#pragma once
// How the simulated world ticks, apart from the world itself: RL environment files and scenarios carry
// these options where the simulator is not linked.
#include "roar/vehicle/slipstream.h"

namespace roar::sim {

struct WorldOptions {
  double control_dt = 0.05;               // s, one tick: controls are applied and states reported once per tick
  double physics_dt = 0.005;              // s, Bullet substep; control_dt must be a whole multiple of it
  double gravity = 9.81;                  // m/s^2
  double control_timeout = 0.5;           // s of simulated time without a new control before the car brakes (0: never)
  vehicle::SlipstreamOptions slipstream;  // less drag in another car's wake, from the cars' places at each tick's start
};

}  // namespace roar::sim

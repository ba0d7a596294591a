#pragma once
#include <pybind11/pybind11.h>

// Adds roar_core.run_time_trial and roar_core.run_race (race_binding.cpp): the stack's in-process time trial
// and race, no ROS, as a batch's jobs run them (python/roar_batch).
void bindRaces(pybind11::module_& m);

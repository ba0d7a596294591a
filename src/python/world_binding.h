#pragma once
#include <pybind11/pybind11.h>

// Adds roar_core.World (world_binding.cpp) to the module.
void bindWorld(pybind11::module_& m);

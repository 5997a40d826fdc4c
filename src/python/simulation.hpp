// SPDX-License-Identifier: MIT
/// @file
/// The Python module's simulator binding: `pce._pce._Simulation` (a loaded scene and its
/// `pce::sim::Run`) and the exceptions `SceneError` and `SimulationError`; python/pce/sim.py
/// wraps them.
#pragma once

#include <nanobind/nanobind.h>

namespace pce_python {

/// Adds `_Simulation`, `_load`, `keep_freed_memory`, `SceneError` and `SimulationError` to `m`.
void bind_simulation(nanobind::module_& m);

}  // namespace pce_python

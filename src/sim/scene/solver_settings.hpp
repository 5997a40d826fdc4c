// SPDX-License-Identifier: MIT
/// @file
/// The scene's settings (solver_settings.cpp): the top level's `dt`, `frames`,
/// `output_every`, `view_direction` and `allow_initial_intersections`, the `solver` object,
/// and the command line's overrides of them. Internal.
#pragma once

#include "params.hpp"

#include <pce/sim/broad_phase.hpp>
#include <pce/sim/scene.hpp>

namespace pce::sim {

/// Reads the settings of `root` into `scene` (its simulation's solver and frames, its output
/// settings), then applies `overrides` (an override of `solver.iterations` is checked
/// against the resulting mode); returns the broad phase the contact effects are to use.
BroadPhaseKind parse_settings(const Params& root, const SceneOverrides& overrides, Scene& scene);

}  // namespace pce::sim

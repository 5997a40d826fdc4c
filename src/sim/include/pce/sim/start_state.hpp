// SPDX-License-Identifier: MIT
/// @file
/// Start-state validation: the checks `pce-sim` makes before frame 1 (docs/simulation.md
/// §5.4), so that a start the solver cannot honour is refused with a reason instead of
/// freezing or exploding silently.
///
/// Refusals (a start state that contact cannot repair):
///  - triangle pairs that intersect, within one deformable mesh or between two (the exact
///    count of `pce/sim/intersections.hpp`, per mesh or pair of meshes): penalty contact
///    pushes intersecting sheets apart along the shorter way, which keeps them interlocked,
///    and the step bound keeps every candidate pair from crossing back;
///  - deformable triangles that intersect a mesh obstacle's triangles (at the obstacle's
///    pose at t = 0), when the scene declares `obstacle_contact`;
///  - vertices inside a sphere, box or capsule obstacle (signed distance < 0 at t = 0),
///    when the scene declares `obstacle_contact`: a pinned one can never leave, a free one
///    is thrown out by a penalty that is deepest where it starts.
/// Warnings (the run is well defined, but probably not what was meant):
///  - contact pairs already within their activation distance at the start, per contact
///    effect (from the effect's own activity test at the start state): their forces act
///    from the first step. Within one mesh this means the activation distance exceeds the
///    distance between the mesh's own non-adjacent primitives at rest.
#pragma once

#include <pce/sim/simulation.hpp>

#include <string>
#include <vector>

namespace pce::sim {

/// What `check_start_state` found: each entry one line, without the file name.
struct StartStateReport {
  /// Problems that make the start state unusable (see the file comment).
  std::vector<std::string> refusals;
  /// Conditions worth a warning.
  std::vector<std::string> warnings;
};

/// Checks `sim` at its current state (frame 0 after `start_at_rest()`) as the file comment
/// says. Calls every effect's `begin_step` and `evaluate` (no gradient, no Hessian) once at
/// the current state to read the contact counts, as the first step will again; `x`, `v`,
/// `frame` and `time` are not changed and the first step's results are the same as without
/// the check. Throws what `step()`'s checks throw for a simulation that cannot run.
StartStateReport check_start_state(Simulation& sim);

}  // namespace pce::sim

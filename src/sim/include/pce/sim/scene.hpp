// SPDX-License-Identifier: MIT
/// @file
/// Scene files (JSON, documented field by field in `docs/simulation.md` §2): meshes, obstacles, solver settings and,
/// explicitly, the effects. Only the listed effects are constructed; a scene without contact effects builds no broad
/// phase, a scene without bending allocates no bending data.
///
/// Every invalid input is reported by one `InputError` naming the file, the JSON path and
/// what was expected (`hammock.json: effects[3].penalty.distance: expected a number > 0,
/// got -1`). The effect entries' types, meshes and obstacles, and which meshes they cover,
/// are checked before the first effect is built; each entry's own fields by its builder
/// before that effect is built; on any error nothing is returned or written.
#pragma once

#include <pce/energy/projection.hpp>
#include <pce/sim/simulation.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pce::sim {

/// Command-line values that override the scene's.
struct SceneOverrides {
  /// Frames to simulate (`frames`).
  std::optional<int> frames;
  /// Every contact effect's Hessian strategy (`hessian`; one of `kContactHessians`).
  std::optional<Projection> hessian;
  /// Every contact effect's broad phase (`solver.broad_phase`).
  std::optional<BroadPhaseKind> broad_phase;
  /// OpenMP threads (`solver.threads`).
  std::optional<int> threads;
  /// One linearised solve per step (true: `solver.mode` single_solve; false changes nothing).
  std::optional<bool> single_solve;
  /// The solver's mode (`solver.mode`; wins over `single_solve`).
  std::optional<SolverMode> mode;
  /// Block descent's sweeps per step (`solver.iterations`, ≥ 1).
  std::optional<int> iterations;
  /// Block descent's acceleration (`solver.acceleration`).
  std::optional<Acceleration> acceleration;
  /// Time steps per frame (`solver.substeps`, 1–1000).
  std::optional<int> substeps;
  /// Newton's stopping tolerance (`solver.tolerance`).
  std::optional<double> tolerance;
};

/// A loaded scene: the simulation plus what the output side needs.
struct Scene {
  /// The scene file it was loaded from (the name used in errors for a text).
  std::filesystem::path file;
  /// The simulation the scene declares, at frame 0.
  Simulation simulation;
  int output_every = 1;  ///< write every k-th frame's mesh (the last always)
  Eigen::Vector3d view_direction = Eigen::Vector3d(-1.0, -2.0, -0.9);  ///< picture camera
  /// Scene key `allow_initial_intersections`: run a start state that `check_start_state`
  /// refuses, with a warning (`pce/sim/start_state.hpp`).
  bool allow_initial_intersections = false;
};

/// Parses, validates and builds `file`; throws `InputError` on any invalid input
/// (including a missing or malformed mesh file).
std::unique_ptr<Scene> load_scene(const std::filesystem::path& file, const SceneOverrides& overrides = {});

/// The same from a JSON text; `name` is the file name used in errors and `base` the
/// directory relative mesh paths start from.
std::unique_ptr<Scene> load_scene_text(const std::string& text, const std::string& name,
                                       const std::filesystem::path& base, const SceneOverrides& overrides = {});

}  // namespace pce::sim

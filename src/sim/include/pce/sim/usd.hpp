// SPDX-License-Identifier: MIT
/// @file
/// A USD cache of a run: the recorded frames (`pce/sim/recording.hpp`) as a plain-text USD
/// layer (`.usda`), written without a USD library. Under the default prim `/World`, each
/// scene mesh with triangles is a `Mesh` (a volume: its boundary triangles) and each mesh
/// with segments a linear `BasisCurves`, named after the scene mesh (`usd_identifier`):
/// topology once, `points` (and `extent`) time-sampled at every recorded frame, the time
/// code being the frame number. Obstacles are `Xform`s under `/World/obstacles` holding a
/// `Sphere`, `Cube`, `Capsule` or `Mesh`, their transform time-sampled when they move. The
/// stage says `upAxis` "Z", `metersPerUnit` 1 and `timeCodesPerSecond` = 1/dt.
#pragma once

#include <pce/sim/recording.hpp>
#include <pce/sim/scene.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace pce::sim {

/// The file name endings a USD cache may have: ".usda", ".usd" (both read as text by USD).
const std::vector<std::string>& usd_extensions();

/// `name` made a valid USD prim name: each character other than A–Z, a–z, 0–9 and `_`
/// becomes `_`, and a name that is empty or starts with a digit gets a leading `_`
/// ("sheet 1" → "sheet_1", "2d" → "_2d").
std::string usd_identifier(const std::string& name);

/// Writes `frames` (recorded from `scene`'s simulation, dt = `scene.simulation.solver.dt`)
/// to `path` as text USD: into a temporary file beside it, renamed over `path` once
/// complete, so `path` is either the whole cache or untouched. Positions as recorded
/// (floats, printed with 9 significant digits, so they read back exactly); the stage's
/// `startTimeCode` and `endTimeCode` are the first and last recorded frame. Creates the
/// missing parent directories. Throws `std::runtime_error` naming the file if it cannot be
/// written, or if nothing was recorded.
void write_usda(const std::filesystem::path& path, const Scene& scene, const FrameRecording& frames);

}  // namespace pce::sim

// SPDX-License-Identifier: MIT
/// @file
/// Checkpoints: everything the next step of a `Simulation` reads that is not rebuilt from
/// the scene, so that a run resumed from a checkpoint ends bit for bit where the
/// uninterrupted run ends (`pce-sim --checkpoint-every K`, `pce-sim SCENE --resume DIR`).
///
/// What is saved: the frame count and the simulated time (pin releases, pin and obstacle
/// motions and every other prescribed quantity are functions of them), positions and
/// velocities as raw doubles, and each effect's `CarriedState::save_state()` (self
/// contact: its tracked pairs with their settled sides). What is not: the linear solver's symbolic
/// analysis (a function of the sparsity pattern, which the first iteration rebuilds) and
/// per-step scratch.
///
/// File layout (native byte order, checked by a byte-order mark): the 8 bytes `PCESIMCK`,
/// the format version (u32), the byte-order mark 0x01020304 (u32), the scene fingerprint
/// (u64), the frame (i32), the time (f64), the vertex count n (i64), x and v (3n f64 each,
/// column by column), the effect count (u32) and per effect its name (u32 length + bytes)
/// and state (u64 length + bytes), and last an FNV-1a 64 checksum (u64) of everything
/// before it, so a truncated or corrupted file is refused.
#pragma once

#include <pce/sim/simulation.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace pce::sim {

/// The checkpoint format this build writes and reads.
inline constexpr std::uint32_t kCheckpointFormatVersion = 1;

/// FNV-1a 64-bit hash of `bytes`, continuing from `seed` (the offset basis by default).
std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t seed = 0xcbf29ce484222325ULL);

/// A fingerprint of what a simulation was built from: `scene` (the scene text and every
/// setting that changes the physics, as the caller spells them) together with the model
/// (rest positions, triangles, segments, tetrahedra, masses). A checkpoint is only read into a
/// simulation with the same fingerprint.
std::uint64_t simulation_fingerprint(std::string_view scene, const Model& model);

/// `dir/checkpoint_NNNN.pcecp`, the frame zero-padded to at least four digits.
std::string checkpoint_path(const std::string& dir, int frame);

/// The checkpoint file in `dir` with the highest frame (by name), or an empty path when
/// there is none.
std::filesystem::path latest_checkpoint(const std::filesystem::path& dir);

/// Writes `sim`'s state to `path`: to a temporary file beside it, renamed over `path` once
/// complete, so a run killed while writing leaves the previous file intact. Throws
/// std::runtime_error naming the file if it cannot be written.
void write_checkpoint(const std::filesystem::path& path, const Simulation& sim, std::uint64_t fingerprint);

/// Reads the checkpoint `path` into `sim`, a simulation built from the same scene. Throws
/// `InputError` naming the file, with the reason, and leaves `sim` unchanged when the file
/// is not a checkpoint, is of another format version, truncated or corrupted, was written
/// for another scene (fingerprint), model or list of effects, or an effect refuses its
/// state.
void read_checkpoint(const std::filesystem::path& path, Simulation& sim, std::uint64_t fingerprint);

}  // namespace pce::sim

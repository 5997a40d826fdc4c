// SPDX-License-Identifier: MIT
/// @file
/// The frames a run writes: one OBJ per frame, `dir/frame_0001.obj`, `dir/frame_0002.obj`, …
/// (frame 0 is the initial state), each holding every deformable vertex, triangle and
/// segment of the model (`pce/sim/obj.hpp`'s format, so a frame reads back exactly).
#pragma once

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace pce::sim {

/// `dir/frame_NNNN.obj` with the frame number zero-padded to at least four digits
/// (`frame_0042.obj`, `frame_12345.obj`). Throws `std::invalid_argument` if `frame` < 0.
std::string frame_path(const std::string& dir, int frame);

/// Writes positions `x` with `triangles` and `segments` to `frame_path(dir, frame)`.
/// Throws `InputError` naming the file if it cannot be written.
void write_frame(const std::string& dir, int frame, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles,
                 const Eigen::Matrix2Xi& segments);

/// Creates `dir` and its missing parents (nothing to do if it is a directory already).
/// Throws `std::runtime_error("<dir>: cannot create directory (<reason>)")` otherwise.
void ensure_directory(const std::string& dir);

/// Checks, before a run, that a file the run writes when it ends (a movie, a USD cache) can
/// be written at `path`: its name ends in one of `extensions` (".mp4", compared without
/// case), it is not a directory, it is writable if it exists, and its nearest existing
/// ancestor is a writable directory (the missing ones are created when the file is
/// written). Throws `std::invalid_argument("<path>: <what is wrong>")`; writes nothing.
void check_output_file(const std::filesystem::path& path, const std::vector<std::string>& extensions);

}  // namespace pce::sim

// SPDX-License-Identifier: MIT
/// @file
/// A movie of a run: every recorded frame (`pce/sim/recording.hpp`) drawn by the picture's
/// rasterizer (`pce/sim/render.hpp`) from one camera fitted to the whole run (every frame's
/// meshes and the obstacles at each frame's pose), encoded by `ffmpeg` run as a child
/// process: raw RGB frames piped to its standard input, H.264 in yuv420p, one movie frame
/// per recorded frame at a given frame rate. ffmpeg is not linked: it is found on `PATH`.
#pragma once

#include <pce/sim/recording.hpp>
#include <pce/sim/render.hpp>
#include <pce/sim/scene.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace pce::sim {

/// The file name endings a movie may have: ".mp4", ".m4v", ".mov", ".mkv" (ffmpeg picks the
/// container by it).
const std::vector<std::string>& movie_extensions();

/// The `ffmpeg` executable `PATH` names first (empty if there is none; `PATH` unset:
/// /usr/local/bin, /usr/bin, /bin).
std::filesystem::path find_ffmpeg();

/// What to say when `find_ffmpeg` finds nothing: "ffmpeg not found on PATH; install it
/// (Debian, Ubuntu: apt-get install ffmpeg)".
std::string ffmpeg_missing();

/// The colour scene mesh `k` is drawn in (six colours, in turn).
Eigen::Vector3f mesh_color(std::size_t k);

/// What `last_frame.png` and the movie draw of `scene` with its deformable vertices at `x`:
/// one mesh per scene mesh (triangles and segments) in `mesh_color`, then every obstacle's
/// surface at its pose at `time` (s), grey.
std::vector<RenderMesh> scene_picture(const Scene& scene, const Eigen::Matrix3Xd& x, double time);

/// Writes the movie of `frames` (recorded from `scene`'s simulation) to `path`: one
/// picture of `picture`'s size, view direction and style per recorded frame, all from the
/// camera a `ViewFit` fits to every frame's `scene_picture`, encoded by ffmpeg with
/// libx264 (yuv420p) at `frame_rate` frames per second into the container `path`'s
/// ending names. Creates `path`'s missing parent directories; ffmpeg's messages go to a
/// temporary file beside `path`, removed afterwards. Throws `std::runtime_error` naming
/// `path` if there is no ffmpeg (`ffmpeg_missing`), no frame, or if ffmpeg fails (with its
/// exit status and its error messages), and `std::invalid_argument` for a frame rate that
/// is not finite and > 0.
void write_movie(const std::filesystem::path& path, const Scene& scene, const FrameRecording& frames, double frame_rate,
                 const RenderOptions& picture);

}  // namespace pce::sim

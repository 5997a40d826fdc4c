// SPDX-License-Identifier: MIT
/// @file
/// A run of a loaded scene as `pce-sim` makes it: the start-state check, one record per
/// frame (the line `stats.jsonl` gets) and, when an output directory is open, every file
/// `pce-sim` writes there (`docs/simulation.md` §5): `frame_NNNN.obj`, `stats.jsonl`
/// (appended and flushed as each frame ends), `last_frame.png`, `stats.json`,
/// `summary.json`, checkpoints, and on request a movie and a USD cache of the run.
/// `pce-sim` and the Python module (`pce.sim`) both run scenes through this, so they write
/// the same files.
#pragma once

#include <pce/sim/scene.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace pce::sim {

/// The scene file's text and every override that changes the physics: what a run's
/// checkpoints are fingerprinted with (`simulation_fingerprint`, `pce/sim/checkpoint.hpp`).
std::string physics_key(const std::filesystem::path& scene_file, const SceneOverrides& overrides);

/// The same for a scene given as its JSON text (`load_scene_text`): the key of a file that
/// holds exactly `scene_text`.
std::string physics_key_of_text(const std::string& scene_text, const SceneOverrides& overrides);

/// Checks the start state (`check_start_state`) as `pce-sim` does before a run: throws an
/// `InputError` naming `scene_file` with every refusal on one line, unless the scene sets
/// `allow_initial_intersections`; returns the warnings, each one line starting with the file
/// name (refusals the scene allows come first).
std::vector<std::string> accept_start_state(Scene& scene, const std::string& scene_file);

/// Where and what a run writes.
struct RunOutput {
  std::filesystem::path dir;      ///< created with its missing parents
  bool write_frames = true;       ///< `frame_NNNN.obj` each output frame (false: `--no-frames`)
  int checkpoint_every = 0;       ///< a checkpoint every k frames (0: none; one on a stop always)
  std::uint64_t fingerprint = 0;  ///< the checkpoints' scene fingerprint
  bool resumed = false;           ///< the simulation was read from a checkpoint in `dir`
  /// The movie to write when the run ends (empty: none; `pce/sim/movie.hpp`): every
  /// recorded frame, at 1/(dt · `output_every`) frames per second.
  std::filesystem::path video;
  /// The USD cache to write when the run ends (empty: none; `pce/sim/usd.hpp`).
  std::filesystem::path usd;
};

/// The frame rate of a run's movie: 1/(dt · `output_every`), so that it plays in real time.
double movie_frame_rate(const Scene& scene);

/// What one frame gave.
struct FrameReport {
  FrameStats stats;            ///< `Simulation::step`'s statistics
  long intersections = 0;      ///< intersecting triangle pairs after the frame (exact, CGAL)
  long new_intersections = 0;  ///< how many more than before the frame
  std::string record;          ///< the frame's `stats.jsonl` record (one JSON object, no newline)
};

/// Steps a scene's simulation and records each frame; writes `pce-sim`'s files while an
/// output directory is open. Holds a reference to `scene`, which must outlive it.
class Run {
 public:
  /// Counts the intersections of the current state; writes nothing.
  Run(Scene& scene, std::string scene_file);
  ~Run();
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;

  /// Starts writing into `output.dir`: `stats.jsonl` (for a resumed run, the records up to
  /// the checkpoint's frame kept) and, unless resumed or `write_frames` is false, the current
  /// frame's OBJ. With a `video` or `usd` file, the frames are recorded for them
  /// (`pce/sim/recording.hpp`, in `dir/pce-sim-frames.tmp` until the run ends): the current
  /// frame, then those `step` records. Throws `std::invalid_argument` naming the video or
  /// USD file if it cannot be written there (`check_output_file`) and `std::runtime_error`
  /// if there is a `video` but no ffmpeg on `PATH` (both before anything is written), and
  /// `std::runtime_error` naming the file it cannot write.
  void open(const RunOutput& output);
  /// Whether an output directory is open.
  bool is_open() const;
  /// The open output directory (empty when none is open).
  const std::filesystem::path& dir() const;

  /// One frame: `Simulation::step`, then its record and, when open, its `stats.jsonl` line,
  /// its OBJ (every `output_every` frames and the last; not with `write_frames` false), the
  /// same frames for the movie and the USD cache (with `write_frames` false too) and a due
  /// checkpoint. A `SimulationError` propagates and nothing of that frame is recorded.
  FrameReport step();

  /// Ends the output (nothing to do when none is open): with `stopped_by` ("SIGINT",
  /// "SIGTERM") a checkpoint first; then the current frame's OBJ if not written yet, the
  /// picture `last_frame.png`, `stats.json` (every record since `open`, with a resumed run's
  /// earlier ones) and `summary.json` (with `failure` and `stopped_by`); then, with a `usd`
  /// file, the USD cache and, with a `video`, the movie, of the recorded frames and the
  /// current one. Throws `std::runtime_error` if a file cannot be written (the USD cache and
  /// the movie are both attempted; the message names each that failed).
  void close(const std::string& failure = {}, const char* stopped_by = nullptr);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace pce::sim

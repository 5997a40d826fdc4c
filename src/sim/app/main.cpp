// SPDX-License-Identifier: MIT
// pce-sim: run a scene (docs/simulation.md §5).
//   pce-sim SCENE.json [--out DIR] [--frames N] [--hessian S] [--broad-phase fcl|bullet|brute]
//           [--threads T] [--single-solve] [--tolerance TOL] [--no-frames]
//           [--checkpoint-every K] [--resume DIR] [--video FILE] [--usd FILE]
// Writes DIR/frame_NNNN.obj, DIR/stats.jsonl (one record per frame, appended and flushed as
// each frame ends), DIR/last_frame.png, DIR/stats.json and DIR/summary.json (at the end),
// DIR/checkpoint_NNNN.pcecp (every K frames, and when stopped by a signal), and at the end
// the movie (--video, encoded by ffmpeg) and the USD cache (--usd) of the output frames.
// Exit codes: 0 done; 2 invalid input (one line naming file and field, or the command-line
// option; nothing written); 3 the simulation failed (non-finite state or failed solve: the
// frames and stats up to the failure and the last finite frame are kept, the message names
// the frame, the effect and the vertex); 130 / 143 stopped by SIGINT / SIGTERM after the
// current frame (everything written as at the end, plus a checkpoint); 1 anything else.
#include <pce/sim/allocator.hpp>
#include <pce/sim/checkpoint.hpp>
#include <pce/sim/effects.hpp>
#include <pce/sim/frames.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/movie.hpp>
#include <pce/sim/run.hpp>
#include <pce/sim/scene.hpp>
#include <pce/sim/usd.hpp>

#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace {

using namespace pce::sim;

/// Set by SIGINT / SIGTERM: the run ends after the current frame.
volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int signal_number) {
  g_stop_signal = signal_number;
  std::signal(signal_number, SIG_DFL);  // a second signal ends the run at once
}

/// The names of `values` (enumerators), in their order: the accepted values of an option.
template <class Values> std::vector<std::string> names(const Values& values) {
  std::vector<std::string> out;
  for (const auto v : values) out.emplace_back(pce::name_of(v));
  return out;
}

/// The command line.
struct Options {
  std::string scene_file, out_dir, hessian, broad_phase, resume_dir, mode, video, usd, acceleration;
  int frames = 0, threads = -1, checkpoint_every = 0, iterations = 0, substeps = 0;
  double tolerance = 0;
  bool single_solve = false, no_frames = false;

  /// What the options override in the scene.
  SceneOverrides overrides() const {
    SceneOverrides o;
    if (frames > 0) o.frames = frames;
    if (!hessian.empty()) o.hessian = pce::parse<pce::Projection>(hessian);  // checked by IsMember
    if (!broad_phase.empty()) o.broad_phase = pce::parse<BroadPhaseKind>(broad_phase);
    if (threads >= 0) o.threads = threads;
    if (single_solve) o.single_solve = true;
    if (!mode.empty()) o.mode = pce::parse<SolverMode>(mode);  // checked by IsMember
    if (iterations > 0) o.iterations = iterations;
    if (substeps > 0) o.substeps = substeps;
    if (!acceleration.empty()) o.acceleration = pce::parse<Acceleration>(acceleration);  // checked by IsMember
    if (tolerance > 0) o.tolerance = tolerance;
    return o;
  }
};

/// Throws `CLI::ValidationError` naming `option` if `file` (unless empty) cannot be written
/// with one of `extensions` (`check_output_file`).
void check_file(const char* option, const std::string& file, const std::vector<std::string>& extensions) {
  if (file.empty()) return;
  try {
    check_output_file(file, extensions);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError(option, e.what());
  }
}

/// Parses the command line into `o`: −1 to go on, else the exit code (help: 0; an invalid
/// command line: 2, after one line on stderr).
int parse_options(int argc, char** argv, Options& o) {
  CLI::App app{"pce-sim: simulate a scene with pce's contact energies (docs/simulation.md)"};
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);  // later values win
  app.add_option("scene", o.scene_file, "scene file (JSON)")->required();
  app.add_option("--out", o.out_dir, "output directory (default: pce-sim-out/<scene name>)");
  app.add_option("--frames", o.frames, "frames to simulate (overrides the scene)")->check(CLI::Range(1, 10000000));
  app.add_option("--hessian", o.hessian, "Hessian strategy of every contact effect")
      ->check(CLI::IsMember(names(kContactHessians)));
  app.add_option("--broad-phase", o.broad_phase, "broad phase")
      ->check(CLI::IsMember(names(pce::enumerators<BroadPhaseKind>())));
  app.add_option("--threads", o.threads, "threads for pair evaluation (0: all)")->check(CLI::Range(0, 1024));
  app.add_flag("--single-solve", o.single_solve, "one linearised solve per step (the paper's mode)");
  app.add_option("--mode", o.mode, "solver mode (overrides the scene; --mode single_solve is --single-solve)")
      ->check(CLI::IsMember(names(pce::enumerators<SolverMode>())));
  app.add_option("--iterations", o.iterations, "block descent: sweeps per time step (overrides the scene)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--substeps", o.substeps, "time steps per frame, each of dt/S (overrides the scene)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--acceleration", o.acceleration, "block descent: the sweeps' acceleration (overrides the scene)")
      ->check(CLI::IsMember(names(pce::enumerators<Acceleration>())));
  app.add_option("--tolerance", o.tolerance, "Newton tolerance on max|dx|/(h*size), 1/s")->check(CLI::PositiveNumber);
  app.add_flag("--no-frames", o.no_frames, "write no per-frame meshes (stats, picture and the last frame only)");
  app.add_option("--checkpoint-every", o.checkpoint_every, "write DIR/checkpoint_NNNN.pcecp every K frames")
      ->check(CLI::Range(1, 10000000));
  app.add_option("--resume", o.resume_dir,
                 "continue the run in DIR from its latest checkpoint (DIR is the output directory)");
  app.add_option("--video", o.video,
                 "at the end, write a movie of the output frames to FILE (.mp4, .m4v, .mov, .mkv; needs ffmpeg)");
  app.add_option("--usd", o.usd, "at the end, write the output frames as a USD cache to FILE (.usda, .usd; text)");
  try {
    app.parse(argc, argv);
    if (!o.resume_dir.empty() && !o.out_dir.empty() &&
        std::filesystem::weakly_canonical(o.resume_dir) != std::filesystem::weakly_canonical(o.out_dir))
      throw CLI::ValidationError("--out", "--resume DIR writes into DIR; leave --out out or give the same folder");
    // The movie and the cache are written at the end: refused now if they cannot be.
    check_file("--video", o.video, movie_extensions());
    check_file("--usd", o.usd, usd_extensions());
    if (!o.video.empty() && find_ffmpeg().empty())
      throw CLI::ValidationError("--video", ffmpeg_missing() + ", or leave --video out");
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {  // one line, exit code 2, like every invalid input
    std::cerr << "pce-sim: command line: " << e.what() << " (see pce-sim --help)\n";
    return 2;
  }
  return -1;
}

/// The scene, ready to run: loaded with the options' overrides, resumed from the latest
/// checkpoint with --resume, otherwise its start state accepted (warnings on stderr). Throws
/// InputError (exit code 2).
struct Loaded {
  std::unique_ptr<Scene> scene;
  std::uint64_t fingerprint = 0;
  std::filesystem::path resumed_from;  ///< empty unless resumed
};
Loaded load(const Options& o) {
  Loaded l;
  const SceneOverrides overrides = o.overrides();
  l.scene = load_scene(o.scene_file, overrides);
  Simulation& sim = l.scene->simulation;
  l.fingerprint = simulation_fingerprint(physics_key(o.scene_file, overrides), sim.model);
  if (o.resume_dir.empty()) {
    // The start state, before anything is written (a resumed state was checked when its run
    // started).
    for (const auto& w : accept_start_state(*l.scene, o.scene_file)) std::cerr << "pce-sim: warning: " << w << "\n";
    return l;
  }
  l.resumed_from = latest_checkpoint(o.resume_dir);
  if (l.resumed_from.empty()) throw InputError(o.resume_dir, "", "no checkpoint to resume from (checkpoint_*.pcecp)");
  read_checkpoint(l.resumed_from, sim, l.fingerprint);
  if (sim.frame >= sim.frames)
    throw InputError(l.resumed_from.string(), "",
                     "the checkpoint is at frame " + std::to_string(sim.frame) + ", the run has " +
                         std::to_string(sim.frames) + " frames: nothing to resume (give more with --frames)");
  return l;
}

/// The frame's line on stderr, and its warnings (a first line search without decrease, new
/// intersecting triangle pairs, and once per run contact held at its minimum separation).
void report_frame(const FrameReport& r, const Simulation& sim) {
  const FrameStats& s = r.stats;
  const int f = sim.frame;
  static bool warned_floor = false;
  const bool sweeps = s.sweeps > 0;
  std::fprintf(stderr, "frame %d of %d: %.1f ms, %d %s, residual %.2e, %s%ld intersecting pairs\n", f, sim.frames,
               s.wall_ms, sweeps ? s.sweeps : s.newton_iterations,
               sweeps ? "block descent sweeps" : "Newton iterations", s.residual,
               s.hit_iteration_cap ? "iteration cap hit, " : "", r.intersections);
  if (s.line_search_failures > 0 && s.newton_iterations == 1)
    std::fprintf(stderr,
                 "pce-sim: warning: frame %d: the line search found no decrease at the first Newton iteration, so "
                 "the state did not move (in plane mode: a pair sits at the energy's jump, docs/simulation.md "
                 "section 10)\n",
                 f);
  if (!warned_floor && s.counters.has(Counter::floor_holds) && s.counters.at(Counter::floor_holds) > 0) {
    warned_floor = true;
    std::fprintf(stderr,
                 "pce-sim: warning: frame %d: %.0f contact pairs held at their minimum separation; their penalties "
                 "were stiffened (a penalty too soft for its load; floor_holds and stiffened_pairs in stats.jsonl "
                 "count them, docs/simulation.md section 4.6; warned once)\n",
                 f, s.counters.at(Counter::floor_holds));
  }
  if (r.new_intersections > 0)
    std::fprintf(stderr, "pce-sim: warning: frame %d: %ld new intersecting triangle pairs (%ld in all)%s\n", f,
                 r.new_intersections, r.intersections,
                 s.hit_iteration_cap ? "; Newton ended at the iteration cap"
                                     : (s.line_search_failures ? "; the line search found no decrease" : ""));
}

/// How a run ended.
struct Ending {
  int status = 0;                    ///< 0, 3 (failed) or 128 + the stopping signal
  std::string failure;               ///< the failure's message (status 3)
  const char* stopped_by = nullptr;  ///< "SIGINT" or "SIGTERM" when stopped
};

/// Runs the frames into `dir` until the last, a failure or a stop signal; throws what the
/// output throws (exit code 1).
Ending run_frames(const Options& o, Loaded& l, const std::filesystem::path& dir) {
  Simulation& sim = l.scene->simulation;
  Ending end;
  Run run(*l.scene, o.scene_file);
  RunOutput output;
  output.dir = dir;
  output.write_frames = !o.no_frames;
  output.checkpoint_every = o.checkpoint_every;
  output.fingerprint = l.fingerprint;
  output.resumed = !l.resumed_from.empty();
  output.video = o.video;
  output.usd = o.usd;
  run.open(output);
  std::cerr << "pce-sim: " << o.scene_file << ": " << sim.model.vertex_count() << " vertices, " << sim.effects.size()
            << " effects, " << sim.frames << " frames, dt = " << sim.solver.dt << " s";
  if (sim.solver.steps_per_frame() > 1) std::cerr << " in " << sim.solver.steps_per_frame() << " steps";
  if (!l.resumed_from.empty()) std::cerr << ", resumed at frame " << sim.frame << " from " << l.resumed_from.string();
  std::cerr << "\n";
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  while (sim.frame < sim.frames && !g_stop_signal) {
    try {
      report_frame(run.step(), sim);
    } catch (const SimulationError& e) {
      end.failure = o.scene_file + ": " + e.what();
      end.status = 3;
      break;
    }
  }
  if (g_stop_signal && end.status == 0) {
    end.stopped_by = g_stop_signal == SIGINT ? "SIGINT" : "SIGTERM";
    end.status = 128 + static_cast<int>(g_stop_signal);
  }
  if (!o.usd.empty() || !o.video.empty())
    std::cerr << "pce-sim: writing " << (o.usd.empty() ? "" : "the USD cache " + o.usd)
              << (o.usd.empty() || o.video.empty() ? "" : " and ") << (o.video.empty() ? "" : "the movie " + o.video)
              << "\n";
  run.close(end.failure, end.stopped_by);
  return end;
}

}  // namespace

int main(int argc, char** argv) {
  pce::sim::keep_freed_memory();  // CHOLMOD's factors then reuse freed memory (allocator.hpp)
  Options o;
  if (const int code = parse_options(argc, argv, o); code >= 0) return code;
  Loaded l;
  try {
    l = load(o);
  } catch (const InputError& e) {
    std::cerr << "pce-sim: " << e.what() << "\n";
    return 2;
  }
  const Simulation& sim = l.scene->simulation;
  const std::filesystem::path dir =
      !o.resume_dir.empty() ? std::filesystem::path(o.resume_dir)
      : o.out_dir.empty()   ? std::filesystem::path("pce-sim-out") / std::filesystem::path(o.scene_file).stem()
                            : std::filesystem::path(o.out_dir);
  Ending end;
  try {
    end = run_frames(o, l, dir);
  } catch (const std::exception& e) {
    std::cerr << "pce-sim: " << e.what() << "\n";
    return 1;
  }
  if (end.status == 3) {
    std::cerr << "pce-sim: " << end.failure << " (frame " << sim.frame << ", the last finite one, is in "
              << dir.string() << ")\n";
    return end.status;
  }
  if (end.stopped_by) {
    std::cerr << "pce-sim: stopped by " << end.stopped_by << " after frame " << sim.frame << "; wrote "
              << (dir / "summary.json").string() << " and " << checkpoint_path(dir.string(), sim.frame)
              << " (continue with --resume " << dir.string() << ")\n";
    return end.status;
  }
  std::cerr << "pce-sim: wrote " << (dir / "stats.json").string() << ", " << (dir / "last_frame.png").string()
            << (o.usd.empty() ? "" : ", " + o.usd) << (o.video.empty() ? "" : ", " + o.video) << " and the frames in "
            << dir.string() << "\n";
  std::cout << dir.string() << "\n";
  return 0;
}

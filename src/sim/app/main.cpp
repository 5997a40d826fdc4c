// SPDX-License-Identifier: MIT
// pce-sim: run a scene (docs/simulation.md §5).
//   pce-sim SCENE.json [--out DIR] [--frames N] [--hessian S] [--broad-phase fcl|bullet|brute]
//           [--threads T] [--single-solve] [--tolerance TOL] [--no-frames]
//           [--checkpoint-every K] [--resume DIR]
// Writes DIR/frame_NNNN.obj, DIR/stats.jsonl (one record per frame, appended and flushed as
// each frame ends), DIR/last_frame.png, DIR/stats.json and DIR/summary.json (at the end),
// and DIR/checkpoint_NNNN.pcecp (every K frames, and when stopped by a signal).
// Exit codes: 0 done; 2 invalid input (one line naming file and field, or the command-line
// option; nothing written); 3 the simulation failed (non-finite state or failed solve: the
// frames and stats up to the failure and the last finite frame are kept, the message names
// the frame, the effect and the vertex); 130 / 143 stopped by SIGINT / SIGTERM after the
// current frame (everything written as at the end, plus a checkpoint); 1 anything else.
#include <pce/sim/allocator.hpp>
#include <pce/sim/checkpoint.hpp>
#include <pce/sim/frames.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/intersections.hpp>
#include <pce/sim/render.hpp>
#include <pce/sim/scene.hpp>
#include <pce/sim/start_state.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

namespace {

using namespace pce::sim;
using nlohmann::json;

json frame_record(const FrameStats& s, long intersections) {
  json r;
  r["frame"] = s.frame;
  r["wall_ms"] = s.wall_ms;
  r["newton_iterations"] = s.newton_iterations;
  r["residual"] = s.residual;
  r["energy"] = s.energy;
  r["line_search_failures"] = s.line_search_failures;
  r["hit_iteration_cap"] = s.hit_iteration_cap;
  r["broad_phase_ms"] = s.broad_phase_ms;
  r["pair_ms"] = s.pair_ms;
  r["assembly_ms"] = s.assembly_ms;
  r["solve_ms"] = s.solve_ms;
  r["line_search_ms"] = s.line_search_ms;
  const auto counter = [&](const std::string& k, double fallback) {
    return s.counters.has(k) ? s.counters.at(k) : fallback;
  };
  json contacts = json::object();
  double min_distance = INFINITY;
  for (const char* kind : {"vertex_face", "edge_edge", "obstacle"}) {
    const std::string k = kind;
    if (s.counters.has(k + "_contacts")) contacts[k] = static_cast<long>(counter(k + "_contacts", 0));
    min_distance = std::min(min_distance, counter(k + "_min_distance", INFINITY));
  }
  r["contacts"] = contacts;
  r["min_distance"] = std::isfinite(min_distance) ? json(min_distance) : json(nullptr);
  r["intersecting_triangle_pairs"] = intersections;
  json effects = json::object();
  for (const auto& [name, ms] : s.effect_ms) effects[name] = ms;
  r["effects"] = effects;
  json counters = json::object();
  for (const auto& [k, v] : s.counters.entries()) counters[k] = std::isfinite(v) ? json(v) : json(nullptr);
  r["counters"] = counters;
  json iterations = json::array();
  for (const NewtonIteration& it : s.iterations)
    iterations.push_back(
        {{"residual", it.residual}, {"step_limit", it.step_limit}, {"limited_by", it.limited_by}, {"alpha", it.alpha}});
  r["iterations"] = iterations;
  return r;
}

void write_json(const std::filesystem::path& path, const json& j) {
  std::ofstream out(path);
  out << j.dump(1) << "\n";
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

std::vector<RenderMesh> scene_meshes(const Scene& scene) {
  const Simulation& sim = scene.simulation;
  std::vector<RenderMesh> meshes;
  const Eigen::Vector3f palette[] = {{0.85f, 0.35f, 0.25f}, {0.25f, 0.55f, 0.85f}, {0.35f, 0.70f, 0.35f},
                                     {0.90f, 0.70f, 0.20f}, {0.60f, 0.40f, 0.75f}, {0.30f, 0.70f, 0.70f}};
  int k = 0;
  for (const MeshRange& r : sim.model.meshes) {
    RenderMesh m;
    m.positions = sim.x.middleCols(r.first_vertex, r.vertex_count);
    m.triangles = sim.model.triangles.middleCols(r.first_triangle, r.triangle_count).array() - r.first_vertex;
    m.segments = sim.model.segments.middleCols(r.first_segment, r.segment_count).array() - r.first_vertex;
    m.color = palette[k++ % 6];
    meshes.push_back(std::move(m));
  }
  for (const Obstacle& o : sim.obstacles) {
    const Mesh s = surface_mesh(o, o.pose(sim.time));
    RenderMesh m;
    m.positions = s.positions;
    m.triangles = s.triangles;
    m.color = Eigen::Vector3f(0.62f, 0.62f, 0.66f);
    meshes.push_back(std::move(m));
  }
  return meshes;
}

double peak_memory_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

/// Set by SIGINT / SIGTERM: the run ends after the current frame.
volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int signal_number) {
  g_stop_signal = signal_number;
  std::signal(signal_number, SIG_DFL);  // a second signal ends the run at once
}

/// The scene as the fingerprint sees it: its text and every option that changes the physics.
std::string physics_key(const std::string& scene_file, const SceneOverrides& o) {
  std::ifstream in(scene_file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  std::string key = text.str();
  if (o.hessian) key += "\n--hessian " + *o.hessian;
  if (o.broad_phase) key += "\n--broad-phase " + std::to_string(static_cast<int>(*o.broad_phase));
  if (o.single_solve) key += "\n--single-solve";
  if (o.tolerance) key += "\n--tolerance " + json(*o.tolerance).dump();
  return key;
}

/// The records of `path` (one JSON object a line) with frame ≤ `last_frame`, in order; a
/// line that does not parse (a record cut short by a kill) ends the list.
json read_records(const std::filesystem::path& path, int last_frame) {
  json records = json::array();
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    const json r = json::parse(line, nullptr, false);
    if (r.is_discarded() || !r.is_object() || !r.contains("frame")) break;
    if (r["frame"].get<int>() > last_frame) break;
    records.push_back(r);
  }
  return records;
}

json summary_of(const Simulation& sim, const std::string& scene_file, const json& stats, double total_s,
                const std::string& failure, const char* stopped_by) {
  json summary;
  summary["scene"] = scene_file;
  summary["frames_done"] = sim.frame;
  summary["vertices"] = sim.model.vertex_count();
  summary["triangles"] = sim.model.triangles.cols();
  summary["segments"] = sim.model.segments.cols();
  summary["dt"] = sim.solver.dt;
  summary["mode"] = sim.solver.single_solve ? "single_solve" : "newton";
  summary["total_s"] = total_s;
  summary["peak_memory_mib"] = peak_memory_mib();
  summary["failure"] = failure.empty() ? json(nullptr) : json(failure);
  summary["stopped_by"] = stopped_by ? json(stopped_by) : json(nullptr);
  double ms = 0, iters = 0;
  long new_intersections = 0;
  for (const auto& r : stats) {
    ms += r["wall_ms"].get<double>();
    iters += r["newton_iterations"].get<double>();
    new_intersections += r.value("new_intersections", 0L);
  }
  summary["mean_ms_per_frame"] = stats.empty() ? 0.0 : ms / static_cast<double>(stats.size());
  summary["mean_newton_iterations"] = stats.empty() ? 0.0 : iters / static_cast<double>(stats.size());
  summary["new_intersections"] = new_intersections;
  return summary;
}

}  // namespace

int main(int argc, char** argv) {
  pce::sim::keep_freed_memory();  // CHOLMOD's factors then reuse freed memory (allocator.hpp)
  CLI::App app{"pce-sim: simulate a scene with pce's contact energies (docs/simulation.md)"};
  std::string scene_file, out_dir, hessian, broad_phase, resume_dir;
  int frames = 0, threads = -1, checkpoint_every = 0;
  double tolerance = 0;
  bool single_solve = false, no_frames = false;
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);  // later values win
  app.add_option("scene", scene_file, "scene file (JSON)")->required();
  app.add_option("--out", out_dir, "output directory (default: pce-sim-out/<scene name>)");
  app.add_option("--frames", frames, "frames to simulate (overrides the scene)")->check(CLI::Range(1, 10000000));
  app.add_option("--hessian", hessian, "Hessian strategy of every contact effect")
      ->check(CLI::IsMember({"analytic", "exact", "numerical", "gauss_newton", "abs"}));
  app.add_option("--broad-phase", broad_phase, "broad phase")->check(CLI::IsMember({"fcl", "bullet", "brute"}));
  app.add_option("--threads", threads, "threads for pair evaluation (0: all)")->check(CLI::Range(0, 1024));
  app.add_flag("--single-solve", single_solve, "one linearised solve per step (the paper's mode)");
  app.add_option("--tolerance", tolerance, "Newton tolerance on max|dx|/(h*size), 1/s")->check(CLI::PositiveNumber);
  app.add_flag("--no-frames", no_frames, "write no per-frame meshes (stats, picture and the last frame only)");
  app.add_option("--checkpoint-every", checkpoint_every, "write DIR/checkpoint_NNNN.pcecp every K frames")
      ->check(CLI::Range(1, 10000000));
  app.add_option("--resume", resume_dir,
                 "continue the run in DIR from its latest checkpoint (DIR is the output directory)");
  try {
    app.parse(argc, argv);
    if (!resume_dir.empty() && !out_dir.empty() &&
        std::filesystem::weakly_canonical(resume_dir) != std::filesystem::weakly_canonical(out_dir))
      throw CLI::ValidationError("--out", "--resume DIR writes into DIR; leave --out out or give the same folder");
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {  // one line, exit code 2, like every invalid input
    std::cerr << "pce-sim: command line: " << e.what() << " (see pce-sim --help)\n";
    return 2;
  }

  SceneOverrides o;
  if (frames > 0) o.frames = frames;
  if (!hessian.empty()) o.hessian = hessian;
  if (!broad_phase.empty()) o.broad_phase = broad_phase_kind(broad_phase);  // checked by IsMember above
  if (threads >= 0) o.threads = threads;
  if (single_solve) o.single_solve = true;
  if (tolerance > 0) o.tolerance = tolerance;

  std::unique_ptr<Scene> scene;
  std::uint64_t fingerprint = 0;
  std::filesystem::path resumed_from;
  try {
    scene = load_scene(scene_file, o);
    fingerprint = simulation_fingerprint(physics_key(scene_file, o), scene->simulation.model);
    if (!resume_dir.empty()) {
      resumed_from = latest_checkpoint(resume_dir);
      if (resumed_from.empty()) throw InputError(resume_dir, "", "no checkpoint to resume from (checkpoint_*.pcecp)");
      read_checkpoint(resumed_from, scene->simulation, fingerprint);
      if (scene->simulation.frame >= scene->simulation.frames)
        throw InputError(resumed_from.string(), "",
                         "the checkpoint is at frame " + std::to_string(scene->simulation.frame) + ", the run has " +
                             std::to_string(scene->simulation.frames) +
                             " frames: nothing to resume (give more with --frames)");
    }
  } catch (const InputError& e) {
    std::cerr << "pce-sim: " << e.what() << "\n";
    return 2;
  }
  Simulation& sim = scene->simulation;
  if (resumed_from.empty()) {
    // The start state, before anything is written (a resumed state was checked when its run
    // started).
    const StartStateReport start = check_start_state(sim);
    if (!start.refusals.empty() && !scene->allow_initial_intersections) {
      std::string line;
      for (const auto& r : start.refusals) line += (line.empty() ? "" : "; ") + r;
      std::cerr << "pce-sim: " << scene_file << ": " << line
                << " (move the meshes apart, or set \"allow_initial_intersections\": true to run it anyway)\n";
      return 2;
    }
    for (const auto& r : start.refusals)
      std::cerr << "pce-sim: warning: " << scene_file << ": " << r << " (allowed by allow_initial_intersections)\n";
    for (const auto& w : start.warnings) std::cerr << "pce-sim: warning: " << scene_file << ": " << w << "\n";
  }
  const std::filesystem::path dir =
      !resume_dir.empty() ? std::filesystem::path(resume_dir)
      : out_dir.empty()   ? std::filesystem::path("pce-sim-out") / std::filesystem::path(scene_file).stem()
                          : std::filesystem::path(out_dir);
  const auto started = std::chrono::steady_clock::now();
  int status = 0;
  std::string failure;
  const char* stopped_by = nullptr;
  try {
    ensure_directory(dir.string());
    // Records of the frames done: kept from the interrupted run up to its checkpoint, then
    // appended as each frame ends (flushed, so a killed run keeps every completed frame).
    json stats = json::array();
    if (!resumed_from.empty()) stats = read_records(dir / "stats.jsonl", sim.frame);
    std::ofstream jsonl(dir / "stats.jsonl", std::ios::trunc);
    for (const auto& r : stats) jsonl << r.dump() << "\n";
    jsonl.flush();
    if (!jsonl) throw std::runtime_error((dir / "stats.jsonl").string() + ": cannot write");
    if (!no_frames && resumed_from.empty())
      write_frame(dir.string(), 0, sim.x, sim.model.triangles, sim.model.segments);
    std::cerr << "pce-sim: " << scene_file << ": " << sim.model.vertex_count() << " vertices, " << sim.effects.size()
              << " effects, " << sim.frames << " frames, dt = " << sim.solver.dt << " s";
    if (!resumed_from.empty()) std::cerr << ", resumed at frame " << sim.frame << " from " << resumed_from.string();
    std::cerr << "\n";
    std::signal(SIGINT, on_stop_signal);
    std::signal(SIGTERM, on_stop_signal);
    const bool count_intersections = sim.model.triangles.cols() > 1;
    long intersections = count_intersections ? intersecting_triangle_pairs(sim.x, sim.model.triangles) : 0;
    int last_written = resumed_from.empty() && !no_frames ? 0 : -1;
    while (sim.frame < sim.frames && !g_stop_signal) {
      FrameStats s;
      try {
        s = sim.step();
      } catch (const SimulationError& e) {
        failure = scene_file + ": " + e.what();
        status = 3;
        break;
      }
      const int f = sim.frame;
      const long now = count_intersections ? intersecting_triangle_pairs(sim.x, sim.model.triangles) : 0;
      const long fresh = std::max(0L, now - intersections);
      intersections = now;
      json record = frame_record(s, now);
      record["new_intersections"] = fresh;
      stats.push_back(record);
      jsonl << record.dump() << "\n";
      jsonl.flush();
      if (!no_frames && (f % scene->output_every == 0 || f == sim.frames)) {
        write_frame(dir.string(), f, sim.x, sim.model.triangles, sim.model.segments);
        last_written = f;
      }
      if (checkpoint_every > 0 && f % checkpoint_every == 0)
        write_checkpoint(checkpoint_path(dir.string(), f), sim, fingerprint);
      std::fprintf(stderr, "frame %d of %d: %.1f ms, %d Newton iterations, residual %.2e, %s%ld intersecting pairs\n",
                   f, sim.frames, s.wall_ms, s.newton_iterations, s.residual,
                   s.hit_iteration_cap ? "iteration cap hit, " : "", now);
      if (s.line_search_failures > 0 && s.newton_iterations == 1)
        std::fprintf(stderr,
                     "pce-sim: warning: frame %d: the line search found no decrease at the first Newton iteration, so "
                     "the state did not move (in plane mode: a pair sits at the energy's jump, docs/simulation.md "
                     "section 10)\n",
                     f);
      if (fresh > 0)
        std::fprintf(stderr, "pce-sim: warning: frame %d: %ld new intersecting triangle pairs (%ld in all)%s\n", f,
                     fresh, now,
                     s.hit_iteration_cap ? "; Newton ended at the iteration cap"
                                         : (s.line_search_failures ? "; the line search found no decrease" : ""));
    }
    if (!jsonl) throw std::runtime_error((dir / "stats.jsonl").string() + ": cannot write");
    if (g_stop_signal && status == 0) {
      stopped_by = g_stop_signal == SIGINT ? "SIGINT" : "SIGTERM";
      status = 128 + static_cast<int>(g_stop_signal);
      write_checkpoint(checkpoint_path(dir.string(), sim.frame), sim, fingerprint);
    }
    // The last finite frame is always on disk (after a failure, a signal or --no-frames).
    if (last_written != sim.frame) write_frame(dir.string(), sim.frame, sim.x, sim.model.triangles, sim.model.segments);
    RenderOptions ro;
    ro.view_direction = scene->view_direction;
    render_png((dir / "last_frame.png").string(), scene_meshes(*scene), ro);
    write_json(dir / "stats.json", stats);
    const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    write_json(dir / "summary.json", summary_of(sim, scene_file, stats, total_s, failure, stopped_by));
  } catch (const std::exception& e) {
    std::cerr << "pce-sim: " << e.what() << "\n";
    return 1;
  }
  if (status == 3) {
    std::cerr << "pce-sim: " << failure << " (frame " << sim.frame << ", the last finite one, is in " << dir.string()
              << ")\n";
    return status;
  }
  if (stopped_by) {
    std::cerr << "pce-sim: stopped by " << stopped_by << " after frame " << sim.frame << "; wrote "
              << (dir / "summary.json").string() << " and " << checkpoint_path(dir.string(), sim.frame)
              << " (continue with --resume " << dir.string() << ")\n";
    return status;
  }
  std::cerr << "pce-sim: wrote " << (dir / "stats.json").string() << ", " << (dir / "last_frame.png").string()
            << " and the frames in " << dir.string() << "\n";
  std::cout << dir.string() << "\n";
  return 0;
}

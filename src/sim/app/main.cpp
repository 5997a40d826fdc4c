// SPDX-License-Identifier: MIT
// pce-sim: run a scene (contract §2, docs/simulation.md).
//   pce-sim SCENE.json [--out DIR] [--frames N] [--hessian S] [--broad-phase fcl|bullet|brute]
//           [--threads T] [--single-solve] [--tolerance TOL] [--no-frames]
// Writes DIR/frame_NNNN.obj, DIR/last_frame.png, DIR/stats.json (one record per frame) and
// DIR/summary.json. Exit codes: 0 done; 2 invalid input (one line naming file and field, or
// the command-line option; nothing written); 3 the simulation failed (non-finite state or failed solve: the frames
// and stats up to the failure are kept and the message names the frame); 1 anything else.
#include <pce/sim/frames.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/intersections.hpp>
#include <pce/sim/render.hpp>
#include <pce/sim/scene.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>

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
    const auto it = s.counters.find(k);
    return it == s.counters.end() ? fallback : it->second;
  };
  json contacts = json::object();
  double min_distance = INFINITY;
  for (const char* kind : {"vertex_face", "edge_edge", "obstacle"}) {
    const std::string k = kind;
    if (s.counters.count(k + "_contacts")) contacts[k] = static_cast<long>(counter(k + "_contacts", 0));
    min_distance = std::min(min_distance, counter(k + "_min_distance", INFINITY));
  }
  r["contacts"] = contacts;
  r["min_distance"] = std::isfinite(min_distance) ? json(min_distance) : json(nullptr);
  r["intersecting_triangle_pairs"] = intersections;
  json effects = json::object();
  for (const auto& [name, ms] : s.effect_ms) effects[name] = ms;
  r["effects"] = effects;
  json counters = json::object();
  for (const auto& [k, v] : s.counters) counters[k] = std::isfinite(v) ? json(v) : json(nullptr);
  r["counters"] = counters;
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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pce-sim: simulate a scene with pce's contact energies (docs/simulation.md)"};
  std::string scene_file, out_dir, hessian, broad_phase;
  int frames = 0, threads = -1;
  double tolerance = 0;
  bool single_solve = false, no_frames = false;
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);  // later values win
  app.add_option("scene", scene_file, "scene file (JSON)")->required();
  app.add_option("--out", out_dir, "output directory (default: pce-sim-out/<scene name>)");
  app.add_option("--frames", frames, "frames to simulate (overrides the scene)")->check(CLI::Range(1, 10000000));
  app.add_option("--hessian", hessian, "Hessian strategy of every contact effect")
      ->check(CLI::IsMember({"analytic", "exact", "numerical", "gauss_newton", "abs"}));
  app.add_option("--broad-phase", broad_phase, "broad phase")->check(CLI::IsMember({"fcl", "bullet", "brute"}));
  app.add_option("--threads", threads, "threads for pair evaluation (0: all)")->check(CLI::NonNegativeNumber);
  app.add_flag("--single-solve", single_solve, "one linearised solve per step (the paper's mode)");
  app.add_option("--tolerance", tolerance, "Newton tolerance on max|dx|/(h*size), 1/s")->check(CLI::PositiveNumber);
  app.add_flag("--no-frames", no_frames, "write no per-frame meshes (stats, picture and the last frame only)");
  try {
    app.parse(argc, argv);
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
  try {
    scene = load_scene(scene_file, o);
  } catch (const InputError& e) {
    std::cerr << "pce-sim: " << e.what() << "\n";
    return 2;
  }
  Simulation& sim = scene->simulation;
  const std::filesystem::path dir =
      out_dir.empty() ? std::filesystem::path("pce-sim-out") / std::filesystem::path(scene_file).stem()
                      : std::filesystem::path(out_dir);
  json stats = json::array();
  const auto started = std::chrono::steady_clock::now();
  int status = 0;
  std::string failure;
  try {
    ensure_directory(dir.string());
    if (!no_frames) write_frame(dir.string(), 0, sim.x, sim.model.triangles, sim.model.segments);
    std::cerr << "pce-sim: " << scene_file << ": " << sim.model.vertex_count() << " vertices, " << sim.effects.size()
              << " effects, " << sim.frames << " frames, dt = " << sim.solver.dt << " s\n";
    for (int f = 1; f <= sim.frames; ++f) {
      FrameStats s;
      try {
        s = sim.step();
      } catch (const std::runtime_error& e) {
        failure = scene_file + ": " + e.what();
        status = 3;
        break;
      }
      const long intersections =
          sim.model.triangles.cols() > 1 ? intersecting_triangle_pairs(sim.x, sim.model.triangles) : 0;
      stats.push_back(frame_record(s, intersections));
      if (!no_frames && (f % scene->output_every == 0 || f == sim.frames))
        write_frame(dir.string(), f, sim.x, sim.model.triangles, sim.model.segments);
      std::fprintf(stderr, "frame %d of %d: %.1f ms, %d Newton iterations, residual %.2e, %s%ld intersecting pairs\n",
                   f, sim.frames, s.wall_ms, s.newton_iterations, s.residual,
                   s.hit_iteration_cap ? "iteration cap hit, " : "", intersections);
    }
    if (no_frames) write_frame(dir.string(), sim.frame, sim.x, sim.model.triangles, sim.model.segments);
    RenderOptions ro;
    ro.view_direction = scene->view_direction;
    render_png((dir / "last_frame.png").string(), scene_meshes(*scene), ro);
    write_json(dir / "stats.json", stats);
    json summary;
    summary["scene"] = scene_file;
    summary["frames_done"] = sim.frame;
    summary["vertices"] = sim.model.vertex_count();
    summary["triangles"] = sim.model.triangles.cols();
    summary["segments"] = sim.model.segments.cols();
    summary["dt"] = sim.solver.dt;
    summary["mode"] = sim.solver.single_solve ? "single_solve" : "newton";
    summary["total_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    summary["peak_memory_mib"] = peak_memory_mib();
    summary["failure"] = failure.empty() ? json(nullptr) : json(failure);
    double ms = 0, iters = 0;
    for (const auto& r : stats) {
      ms += r["wall_ms"].get<double>();
      iters += r["newton_iterations"].get<double>();
    }
    summary["mean_ms_per_frame"] = stats.empty() ? 0.0 : ms / static_cast<double>(stats.size());
    summary["mean_newton_iterations"] = stats.empty() ? 0.0 : iters / static_cast<double>(stats.size());
    write_json(dir / "summary.json", summary);
  } catch (const std::exception& e) {
    std::cerr << "pce-sim: " << e.what() << "\n";
    return 1;
  }
  if (status != 0) {
    std::cerr << "pce-sim: " << failure << "\n";
    return status;
  }
  std::cerr << "pce-sim: wrote " << (dir / "stats.json").string() << ", " << (dir / "last_frame.png").string()
            << " and the frames in " << dir.string() << "\n";
  std::cout << dir.string() << "\n";
  return 0;
}

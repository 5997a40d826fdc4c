// SPDX-License-Identifier: MIT
#include <pce/sim/checkpoint.hpp>
#include <pce/sim/frames.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/intersections.hpp>
#include <pce/sim/movie.hpp>
#include <pce/sim/recording.hpp>
#include <pce/sim/render.hpp>
#include <pce/sim/run.hpp>
#include <pce/sim/start_state.hpp>
#include <pce/sim/usd.hpp>

#include "../scene/scene_names.hpp"

#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

namespace pce::sim {

namespace {

using nlohmann::json;

json frame_record(const FrameStats& s, long intersections) {
  json r;
  r["frame"] = s.frame;
  r["wall_ms"] = s.wall_ms;
  if (s.substeps > 1) r["substeps"] = s.substeps;
  r["newton_iterations"] = s.newton_iterations;
  if (s.sweeps > 0) r["sweeps"] = s.sweeps;
  r["residual"] = s.residual;
  r["friction_residual"] = s.friction_residual;
  r["friction_load"] = s.friction_load;
  r["stop"] = std::string(name_of(s.stop));
  r["energy"] = s.energy;
  r["kinetic_energy"] = s.kinetic_energy;
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
  for (const auto& [name, ms] : s.effect_ms)
    effects[name] = effects.value(name, 0.0) + ms;  // entries of one type: summed
  r["effects"] = effects;
  json counters = json::object();
  for (const auto& [k, v] : s.counters.entries()) counters[k] = std::isfinite(v) ? json(v) : json(nullptr);
  r["counters"] = counters;
  json iterations = json::array();
  for (const NewtonIteration& it : s.iterations) {
    iterations.push_back({{"residual", it.residual},
                          {"friction_residual", it.friction_residual},
                          {"friction_load", it.friction_load},
                          {"step_limit", it.step_limit},
                          {"limited_by", it.limited_by},
                          {"alpha", it.alpha}});
    if (s.substeps > 1) iterations.back()["substep"] = it.substep;
  }
  r["iterations"] = iterations;
  if (s.sweeps > 0) {
    json sweeps = json::array();
    for (const SweepRecord& k : s.sweep_records) {
      sweeps.push_back({{"residual", k.residual}, {"bound_clamps", k.bound_clamps}});
      if (s.substeps > 1) sweeps.back()["substep"] = k.substep;
      if (std::isfinite(k.energy)) {
        sweeps.back()["energy"] = k.energy;
        sweeps.back()["accelerated"] = k.accelerated;
      }
    }
    r["sweep_records"] = sweeps;
  }
  return r;
}

void write_json(const std::filesystem::path& path, const json& j) {
  std::ofstream out(path);
  out << j.dump(1) << "\n";
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

double peak_memory_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
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
  summary["substeps"] = sim.solver.steps_per_frame();
  summary["mode"] = std::string(name_of(sim.solver.mode));
  if (sim.solver.mode == SolverMode::block_descent) {
    summary["iterations"] = sim.solver.iterations;
    summary["acceleration"] = std::string(name_of(sim.solver.acceleration));
  }
  summary["total_s"] = total_s;
  summary["peak_memory_mib"] = peak_memory_mib();
  summary["failure"] = failure.empty() ? json(nullptr) : json(failure);
  summary["stopped_by"] = stopped_by ? json(stopped_by) : json(nullptr);
  double ms = 0, iters = 0, sweeps = 0;
  long new_intersections = 0;
  for (const auto& r : stats) {
    ms += r["wall_ms"].get<double>();
    iters += r["newton_iterations"].get<double>();
    sweeps += r.value("sweeps", 0.0);
    new_intersections += r.value("new_intersections", 0L);
  }
  summary["mean_ms_per_frame"] = stats.empty() ? 0.0 : ms / static_cast<double>(stats.size());
  summary["mean_newton_iterations"] = stats.empty() ? 0.0 : iters / static_cast<double>(stats.size());
  if (sim.solver.mode == SolverMode::block_descent)
    summary["mean_sweeps"] = stats.empty() ? 0.0 : sweeps / static_cast<double>(stats.size());
  summary["new_intersections"] = new_intersections;
  return summary;
}

}  // namespace

std::string physics_key(const std::filesystem::path& scene_file, const SceneOverrides& o) {
  std::ifstream in(scene_file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return physics_key_of_text(text.str(), o);
}

std::string physics_key_of_text(const std::string& scene_text, const SceneOverrides& o) {
  std::string key = scene_text;
  if (o.hessian) key += "\n--hessian " + std::string(name_of(*o.hessian));
  if (o.broad_phase) key += "\n--broad-phase " + std::to_string(static_cast<int>(*o.broad_phase));
  if (o.single_solve && *o.single_solve) key += "\n--single-solve";
  if (o.mode) key += "\n--mode " + std::string(name_of(*o.mode));
  if (o.iterations) key += "\n--iterations " + std::to_string(*o.iterations);
  if (o.substeps) key += "\n--substeps " + std::to_string(*o.substeps);
  if (o.acceleration) key += "\n--acceleration " + std::string(name_of(*o.acceleration));
  if (o.tolerance) key += "\n--tolerance " + json(*o.tolerance).dump();
  return key;
}

double movie_frame_rate(const Scene& scene) { return 1.0 / (scene.simulation.solver.dt * scene.output_every); }

std::vector<std::string> accept_start_state(Scene& scene, const std::string& scene_file) {
  const StartStateReport start = check_start_state(scene.simulation);
  if (!start.refusals.empty() && !scene.allow_initial_intersections) {
    std::string line;
    for (const auto& r : start.refusals) line += (line.empty() ? "" : "; ") + r;
    throw InputError(scene_file, "",
                     line + " (move the meshes apart, or set \"allow_initial_intersections\": true to run it anyway)");
  }
  std::vector<std::string> warnings;
  for (const auto& r : start.refusals)
    warnings.push_back(scene_file + ": " + r + " (allowed by allow_initial_intersections)");
  for (const auto& w : start.warnings) warnings.push_back(scene_file + ": " + w);
  return warnings;
}

struct Run::State {
  Scene& scene;
  std::string scene_file;
  long intersections = 0;
  bool count_intersections = false;
  // The open output (dir empty: none).
  RunOutput output;
  std::ofstream jsonl;
  json records = json::array();
  int last_written = -1;
  std::chrono::steady_clock::time_point started;
  // The frames of the movie and the USD cache (null: neither asked for).
  std::unique_ptr<FrameRecording> recording;

  State(Scene& s, std::string file) : scene(s), scene_file(std::move(file)) {}
};

Run::Run(Scene& scene, std::string scene_file) : state_(std::make_unique<State>(scene, std::move(scene_file))) {
  const Simulation& sim = scene.simulation;
  state_->count_intersections = sim.model.triangles.cols() > 1;
  state_->intersections = state_->count_intersections ? intersecting_triangle_pairs(sim.x, sim.model.triangles) : 0;
}

Run::~Run() = default;

bool Run::is_open() const { return !state_->output.dir.empty(); }

const std::filesystem::path& Run::dir() const { return state_->output.dir; }

void Run::open(const RunOutput& output) {
  State& st = *state_;
  if (is_open()) throw std::logic_error("pce::sim::Run::open: an output directory is open already");
  if (output.dir.empty()) throw std::invalid_argument("pce::sim::Run::open: no output directory");
  const Simulation& sim = st.scene.simulation;
  // The movie and the cache are written when the run ends: refused now if they cannot be.
  if (!output.video.empty()) check_output_file(output.video, movie_extensions());
  if (!output.usd.empty()) check_output_file(output.usd, usd_extensions());
  if (!output.video.empty() && find_ffmpeg().empty())
    throw std::runtime_error(output.video.string() + ": " + ffmpeg_missing());
  st.started = std::chrono::steady_clock::now();
  ensure_directory(output.dir.string());
  // Records of the frames done: kept from the interrupted run up to its checkpoint, then
  // appended as each frame ends (flushed, so a killed run keeps every completed frame).
  st.records = output.resumed ? read_records(output.dir / "stats.jsonl", sim.frame) : json::array();
  st.jsonl.open(output.dir / "stats.jsonl", std::ios::trunc);
  for (const auto& r : st.records) st.jsonl << r.dump() << "\n";
  st.jsonl.flush();
  if (!st.jsonl) throw std::runtime_error((output.dir / "stats.jsonl").string() + ": cannot write");
  st.last_written = -1;
  if (output.write_frames && !output.resumed) {
    write_frame(output.dir.string(), sim.frame, sim.x, sim.model.triangles, sim.model.segments);
    st.last_written = sim.frame;
  }
  st.recording.reset();
  if (!output.video.empty() || !output.usd.empty()) {
    st.recording = std::make_unique<FrameRecording>(output.dir / "pce-sim-frames.tmp", sim.model.vertex_count());
    st.recording->append(sim.frame, sim.time, sim.x);
  }
  st.output = output;
}

FrameReport Run::step() {
  State& st = *state_;
  Simulation& sim = st.scene.simulation;
  FrameReport report;
  report.stats = sim.step();
  const int f = sim.frame;
  report.intersections = st.count_intersections ? intersecting_triangle_pairs(sim.x, sim.model.triangles) : 0;
  report.new_intersections = std::max(0L, report.intersections - st.intersections);
  st.intersections = report.intersections;
  json record = frame_record(report.stats, report.intersections);
  record["new_intersections"] = report.new_intersections;
  report.record = record.dump();
  if (!is_open()) return report;
  st.records.push_back(record);
  st.jsonl << report.record << "\n";
  st.jsonl.flush();
  const RunOutput& out = st.output;
  const bool output_frame = f % st.scene.output_every == 0 || f == sim.frames;
  if (out.write_frames && output_frame) {
    write_frame(out.dir.string(), f, sim.x, sim.model.triangles, sim.model.segments);
    st.last_written = f;
  }
  if (st.recording && output_frame) st.recording->append(f, sim.time, sim.x);
  if (out.checkpoint_every > 0 && f % out.checkpoint_every == 0)
    write_checkpoint(checkpoint_path(out.dir.string(), f), sim, out.fingerprint);
  return report;
}

void Run::close(const std::string& failure, const char* stopped_by) {
  State& st = *state_;
  if (!is_open()) return;
  const RunOutput out = st.output;
  st.output = RunOutput{};  // closed, whatever happens below
  const Simulation& sim = st.scene.simulation;
  if (!st.jsonl) throw std::runtime_error((out.dir / "stats.jsonl").string() + ": cannot write");
  st.jsonl.close();
  if (stopped_by) write_checkpoint(checkpoint_path(out.dir.string(), sim.frame), sim, out.fingerprint);
  // The last finite frame is always on disk (after a failure, a stop or without frames).
  if (st.last_written != sim.frame)
    write_frame(out.dir.string(), sim.frame, sim.x, sim.model.triangles, sim.model.segments);
  RenderOptions ro;
  ro.view_direction = st.scene.view_direction;
  const std::unique_ptr<FrameRecording> recording = std::move(st.recording);  // removed at the end, whatever happens
  render_png((out.dir / "last_frame.png").string(), scene_picture(st.scene, sim.x, sim.time), ro);
  write_json(out.dir / "stats.json", st.records);
  const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - st.started).count();
  write_json(out.dir / "summary.json", summary_of(sim, st.scene_file, st.records, total_s, failure, stopped_by));
  if (!recording) return;
  // The frame the run ends at (stopped, failed or not a multiple of output_every) is the last one.
  if (recording->frames().back() != sim.frame) recording->append(sim.frame, sim.time, sim.x);
  std::string errors;
  const auto attempt = [&](auto&& write) {
    try {
      write();
    } catch (const std::exception& e) {
      errors += (errors.empty() ? "" : "; ") + std::string(e.what());
    }
  };
  if (!out.usd.empty()) attempt([&] { write_usda(out.usd, st.scene, *recording); });
  if (!out.video.empty())
    attempt([&] { write_movie(out.video, st.scene, *recording, movie_frame_rate(st.scene), ro); });
  if (!errors.empty()) throw std::runtime_error(errors);
}

}  // namespace pce::sim

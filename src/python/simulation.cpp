// SPDX-License-Identifier: MIT
#include "simulation.hpp"

#include <pce/sim/allocator.hpp>
#include <pce/sim/checkpoint.hpp>
#include <pce/sim/effects.hpp>
#include <pce/sim/frames.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/movie.hpp>
#include <pce/sim/run.hpp>
#include <pce/sim/scene.hpp>
#include <pce/sim/usd.hpp>

#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/unique_ptr.h>
#include <nanobind/stl/vector.h>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace nb = nanobind;

namespace pce_python {
namespace {

using namespace pce::sim;

/// A frame that failed: `pce-sim`'s message, `<scene file>: <what failed>`.
class StepFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A loaded scene, its run and what checkpoints need.
class LoadedScene {
 public:
  LoadedScene(const std::string& file, const SceneOverrides& o) : file_(file) {
    scene_ = load_scene(file, o);
    fingerprint_ = simulation_fingerprint(physics_key(file, o), scene_->simulation.model);
    warnings_ = accept_start_state(*scene_, file);
    run_ = std::make_unique<Run>(*scene_, file);
  }

  /// One frame; its stats.jsonl record is kept as `last_record` (read after the call, so a
  /// KeyboardInterrupt raised as the call returns loses nothing).
  void step() {
    try {
      nb::gil_scoped_release release;
      last_record_ = run_->step().record;
    } catch (const SimulationError& e) {
      throw StepFailure(file_ + ": " + e.what());
    }
  }

  void open(const std::string& dir, bool write_frames, int checkpoint_every, const std::string& video,
            const std::string& usd) {
    RunOutput o;
    o.dir = dir;
    o.write_frames = write_frames;
    o.checkpoint_every = checkpoint_every;
    o.video = video;
    o.usd = usd;
    o.fingerprint = fingerprint_;
    run_->open(o);
  }

  void close(const std::string& failure, const std::optional<std::string>& stopped_by) {
    nb::gil_scoped_release release;
    run_->close(failure, stopped_by ? stopped_by->c_str() : nullptr);
  }

  /// A (V, 3) float64 copy of `m` (Eigen's 3 × V column-major is V × 3 row-major).
  static nb::ndarray<nb::numpy, double, nb::shape<-1, 3>> copy(const Eigen::Matrix3Xd& m) {
    const auto n = static_cast<std::size_t>(m.cols());
    auto* data = new double[3 * n];
    std::copy(m.data(), m.data() + 3 * n, data);
    nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<double*>(p); });
    return nb::ndarray<nb::numpy, double, nb::shape<-1, 3>>(data, {n, 3}, owner);
  }

  const Simulation& simulation() const { return scene_->simulation; }
  const std::string& file() const { return file_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  const std::string& last_record() const { return last_record_; }
  bool is_open() const { return run_->is_open(); }
  std::string dir() const { return run_->dir().string(); }

 private:
  std::string file_;
  std::unique_ptr<Scene> scene_;
  std::unique_ptr<Run> run_;
  std::uint64_t fingerprint_ = 0;
  std::vector<std::string> warnings_;
  std::string last_record_;
};

/// Checks the file `run(video=...)` or `run(usd=...)` names (`what`: "video" or "usd")
/// before anything is written: ValueError "<what>: <path>: <what is wrong>" if it cannot be
/// written there, RuntimeError for a video without ffmpeg on PATH.
void check_output(const std::string& what, const std::string& path) {
  try {
    check_output_file(path, what == "video" ? movie_extensions() : usd_extensions());
  } catch (const std::invalid_argument& e) {
    throw nb::value_error((what + ": " + e.what()).c_str());
  }
  if (what == "video" && find_ffmpeg().empty()) throw std::runtime_error("video: " + ffmpeg_missing());
}

/// The names of `values` (enumerators), separated by ", ".
template <class Values> std::string plain_names(const Values& values) {
  std::string list;
  for (const auto v : values) list += (list.empty() ? "" : ", ") + std::string(pce::name_of(v));
  return list;
}

/// The names of `values` (enumerators), in their order.
template <class Values> std::vector<std::string> names(const Values& values) {
  std::vector<std::string> out;
  for (const auto v : values) out.emplace_back(pce::name_of(v));
  return out;
}

/// The strategy of `kContactHessians` named `name`; ValueError for any other name.
pce::Projection contact_hessian(const std::string& name) {
  const std::optional<pce::Projection> p = pce::parse<pce::Projection>(name);
  for (const pce::Projection allowed : kContactHessians)
    if (p == allowed) return allowed;
  throw nb::value_error(("hessian: expected one of " + plain_names(kContactHessians) + ", got '" + name + "'").c_str());
}

std::unique_ptr<LoadedScene> load(const std::string& file, std::optional<int> frames,
                                  std::optional<std::string> hessian, std::optional<std::string> broad_phase,
                                  std::optional<int> threads, std::optional<bool> single_solve,
                                  std::optional<double> tolerance, std::optional<std::string> mode,
                                  std::optional<int> iterations) {
  SceneOverrides o;
  o.frames = frames;
  if (hessian) o.hessian = contact_hessian(*hessian);
  if (broad_phase) {
    o.broad_phase = pce::parse<BroadPhaseKind>(*broad_phase);
    if (!o.broad_phase)
      throw nb::value_error(("broad_phase: expected one of " + plain_names(pce::enumerators<BroadPhaseKind>()) +
                             ", got '" + *broad_phase + "'")
                                .c_str());
  }
  o.threads = threads;
  o.single_solve = single_solve;
  o.tolerance = tolerance;
  if (mode) {
    o.mode = pce::parse<SolverMode>(*mode);
    if (!o.mode)
      throw nb::value_error(
          ("mode: expected one of " + plain_names(pce::enumerators<SolverMode>()) + ", got '" + *mode + "'").c_str());
  }
  o.iterations = iterations;
  return std::make_unique<LoadedScene>(file, o);
}

}  // namespace

void bind_simulation(nb::module_& m) {
  nb::exception<InputError>(m, "SceneError", PyExc_ValueError);
  nb::exception<StepFailure>(m, "SimulationError", PyExc_RuntimeError);
  m.def("keep_freed_memory", &keep_freed_memory,
        "glibc keeps freed memory for reuse (process-wide; what pce-sim does first): returns whether it took");
  nb::class_<LoadedScene>(m, "_Simulation")
      .def("step", &LoadedScene::step)
      .def("open", &LoadedScene::open, nb::arg("dir"), nb::arg("write_frames"), nb::arg("checkpoint_every"),
           nb::arg("video"), nb::arg("usd"))
      .def("close", &LoadedScene::close, nb::arg("failure"), nb::arg("stopped_by").none())
      .def_prop_ro("is_open", &LoadedScene::is_open)
      .def_prop_ro("dir", &LoadedScene::dir)
      .def("positions", [](const LoadedScene& s) { return LoadedScene::copy(s.simulation().x); })
      .def("velocities", [](const LoadedScene& s) { return LoadedScene::copy(s.simulation().v); })
      .def_prop_ro("frame", [](const LoadedScene& s) { return s.simulation().frame; })
      .def_prop_ro("frames", [](const LoadedScene& s) { return s.simulation().frames; })
      .def_prop_ro("time", [](const LoadedScene& s) { return s.simulation().time; })
      .def_prop_ro("dt", [](const LoadedScene& s) { return s.simulation().solver.dt; })
      .def_prop_ro("file", &LoadedScene::file)
      .def_prop_ro("warnings", &LoadedScene::warnings)
      .def_prop_ro("last_record", &LoadedScene::last_record);
  m.def(
      "_contact_hessians", [] { return names(kContactHessians); },
      "The strategies a contact effect's hessian accepts, in pce::sim::kContactHessians' order.");
  m.def(
      "_broad_phases", [] { return names(pce::enumerators<BroadPhaseKind>()); },
      "The broad phases' names, in pce::sim::kBroadPhaseNames' order.");
  m.def("_load", &load, nb::arg("file"), nb::arg("frames").none(), nb::arg("hessian").none(),
        nb::arg("broad_phase").none(), nb::arg("threads").none(), nb::arg("single_solve").none(),
        nb::arg("tolerance").none(), nb::arg("mode").none(), nb::arg("iterations").none());
  m.def("_check_output", &check_output, nb::arg("what"), nb::arg("path"),
        "Checks run()'s video= or usd= file: ValueError if it cannot be written, RuntimeError without ffmpeg.");
  m.def(
      "_solver_modes", [] { return names(pce::enumerators<SolverMode>()); },
      "The solver modes' names, in pce::sim::kSolverModeNames' order.");
}

}  // namespace pce_python

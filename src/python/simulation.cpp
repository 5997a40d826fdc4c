// SPDX-License-Identifier: MIT
#include "simulation.hpp"

#include <pce/sim/allocator.hpp>
#include <pce/sim/checkpoint.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/run.hpp>
#include <pce/sim/scene.hpp>

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

  void open(const std::string& dir, bool write_frames, int checkpoint_every) {
    RunOutput o;
    o.dir = dir;
    o.write_frames = write_frames;
    o.checkpoint_every = checkpoint_every;
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

std::unique_ptr<LoadedScene> load(const std::string& file, std::optional<int> frames,
                                  std::optional<std::string> hessian, std::optional<std::string> broad_phase,
                                  std::optional<int> threads, std::optional<bool> single_solve,
                                  std::optional<double> tolerance) {
  SceneOverrides o;
  o.frames = frames;
  o.hessian = hessian;
  if (broad_phase) o.broad_phase = broad_phase_kind(*broad_phase);
  o.threads = threads;
  o.single_solve = single_solve;
  o.tolerance = tolerance;
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
      .def("open", &LoadedScene::open, nb::arg("dir"), nb::arg("write_frames"), nb::arg("checkpoint_every"))
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
  m.def("_load", &load, nb::arg("file"), nb::arg("frames").none(), nb::arg("hessian").none(),
        nb::arg("broad_phase").none(), nb::arg("threads").none(), nb::arg("single_solve").none(),
        nb::arg("tolerance").none());
}

}  // namespace pce_python

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

#include "util/names.hpp"  // src/sim's

#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/unique_ptr.h>
#include <nanobind/stl/vector.h>

#include <cmath>
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
    start(physics_key(file, o));
  }
  /// From the JSON text of a scene: `name` stands for its file in errors, `base` is the
  /// directory relative mesh files start from.
  LoadedScene(const std::string& text, const std::string& name, const std::string& base, const SceneOverrides& o)
      : file_(name) {
    scene_ = load_scene_text(text, name, base, o);
    start(physics_key_of_text(text, o));
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

  /// The `entry`-th pins entry of the scene (in scene order); ValueError when there is none.
  PinsEffect& pins(int entry) const {
    std::vector<PinsEffect*> all;
    for (const auto& e : scene_->simulation.effects)
      if (auto* p = dynamic_cast<PinsEffect*>(e.get())) all.push_back(p);
    if (entry < 0 || entry >= static_cast<int>(all.size()))
      throw nb::value_error(("entry: expected the index of one of the scene's " + std::to_string(all.size()) +
                             " pins entries, got " + std::to_string(entry))
                                .c_str());
    return *all[static_cast<std::size_t>(entry)];
  }

  /// The obstacle named `name`; ValueError when there is none.
  const Obstacle& obstacle(const std::string& name) const {
    if (const Obstacle* o = find_named(scene_->simulation.obstacles, name)) return *o;
    const std::string names = names_of(scene_->simulation.obstacles, "'");
    throw nb::value_error(("name: no obstacle named '" + name +
                           "' (the obstacles: " + (names.empty() ? std::string("none") : names) + ")")
                              .c_str());
  }

  Simulation& simulation() { return scene_->simulation; }
  const Simulation& simulation() const { return scene_->simulation; }
  const std::string& file() const { return file_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  const std::string& last_record() const { return last_record_; }
  bool is_open() const { return run_->is_open(); }
  std::string dir() const { return run_->dir().string(); }

 private:
  void start(const std::string& key) {
    fingerprint_ = simulation_fingerprint(key, scene_->simulation.model);
    warnings_ = accept_start_state(*scene_, file_);
    run_ = std::make_unique<Run>(*scene_, file_);
  }

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
  return join_names(values, "", [](const auto v) { return pce::name_of(v); });
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

/// The enumerator of `Enum` named `value` (a `load` keyword `key`), none when absent;
/// ValueError naming the key and the accepted names for an unknown name.
template <class Enum> std::optional<Enum> enumerator(const char* key, const std::optional<std::string>& value) {
  if (!value) return std::nullopt;
  const std::optional<Enum> e = pce::parse<Enum>(*value);
  if (!e)
    throw nb::value_error(
        (std::string(key) + ": expected one of " + plain_names(pce::enumerators<Enum>()) + ", got '" + *value + "'")
            .c_str());
  return e;
}

/// `load`'s keyword overrides as SceneOverrides; ValueError for an unknown name.
SceneOverrides overrides(std::optional<int> frames, std::optional<std::string> hessian,
                         std::optional<std::string> broad_phase, std::optional<int> threads,
                         std::optional<bool> single_solve, std::optional<double> tolerance,
                         std::optional<std::string> mode, std::optional<int> iterations, std::optional<int> substeps,
                         std::optional<std::string> acceleration) {
  SceneOverrides o;
  o.frames = frames;
  if (hessian) o.hessian = contact_hessian(*hessian);
  o.broad_phase = enumerator<BroadPhaseKind>("broad_phase", broad_phase);
  o.threads = threads;
  o.single_solve = single_solve;
  o.tolerance = tolerance;
  o.mode = enumerator<SolverMode>("mode", mode);
  o.iterations = iterations;
  o.substeps = substeps;
  o.acceleration = enumerator<Acceleration>("acceleration", acceleration);
  return o;
}

/// A (k, 3) C-contiguous float64 array as 3 × k columns.
using Points = nb::ndarray<const double, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;

Eigen::Matrix3Xd columns(const Points& a) {
  Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(a.shape(0)));
  std::copy(a.data(), a.data() + 3 * a.shape(0), m.data());
  return m;
}

/// Puts obstacle `name` at a pose from the next step on: the given parts of it, the rest
/// as the obstacle is now. `rotation` (row-major 3 × 3) or `axis` and `degrees` (as a scene's
/// rotation) give the rotation.
void set_obstacle_pose(LoadedScene& s, const std::string& name, std::optional<std::vector<double>> translation,
                       std::optional<std::vector<double>> rotation, std::optional<std::vector<double>> axis,
                       std::optional<double> degrees) {
  Simulation& sim = s.simulation();
  Eigen::Isometry3d pose = s.obstacle(name).pose(sim.time);
  if ((translation && translation->size() != 3) || (rotation && rotation->size() != 9) || (axis && axis->size() != 3) ||
      (axis.has_value() != degrees.has_value()) || (axis && rotation))
    throw nb::value_error(
        "set_obstacle_pose: expected a translation of 3 numbers, and a rotation of 9 or an axis of 3 "
        "with degrees");
  if (translation) pose.translation() = Eigen::Vector3d::Map(translation->data());
  if (rotation) pose.linear() = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>::Map(rotation->data());
  if (axis) {
    const Eigen::Vector3d a = Eigen::Vector3d::Map(axis->data());
    if (!std::isfinite(*degrees)) throw nb::value_error("rotation: expected a finite number of degrees");
    if (!(a.allFinite() && a.cwiseAbs().maxCoeff() > 0))
      throw nb::value_error("rotation: expected a finite, non-zero axis");
    pose.linear() = axis_rotation(a, *degrees);
  }
  sim.set_obstacle_pose(name, pose);
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
      .def_prop_ro("last_record", &LoadedScene::last_record)
      .def("pins_entries",
           [](const LoadedScene& s) {
             int count = 0;
             for (const auto& e : s.simulation().effects) count += dynamic_cast<PinsEffect*>(e.get()) != nullptr;
             return count;
           })
      .def(
          "pin_group_count", [](const LoadedScene& s, int entry) { return s.pins(entry).group_count(); },
          nb::arg("entry"))
      .def(
          "pin_vertices",
          [](const LoadedScene& s, int entry, int group) { return s.pins(entry).group_vertices(group); },
          nb::arg("entry"), nb::arg("group"))
      .def(
          "pin_targets",
          [](const LoadedScene& s, int entry, int group) {
            return LoadedScene::copy(s.pins(entry).group_targets(group));
          },
          nb::arg("entry"), nb::arg("group"))
      .def(
          "set_pin_targets",
          [](LoadedScene& s, int entry, int group, std::optional<Points> targets) {
            PinsEffect& pins = s.pins(entry);
            if (targets)
              pins.set_targets(group, columns(*targets));
            else
              pins.clear_targets(group);
          },
          nb::arg("entry"), nb::arg("group"), nb::arg("targets").none())
      .def("obstacle_names",
           [](const LoadedScene& s) {
             std::vector<std::string> names;
             for (const Obstacle& o : s.simulation().obstacles) names.push_back(o.name);
             return names;
           })
      .def(
          "obstacle_pose",
          [](const LoadedScene& s, const std::string& name) {
            const Eigen::Isometry3d pose = s.obstacle(name).pose(s.simulation().time);
            const Eigen::Vector3d t = pose.translation();
            const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> r = pose.linear();
            return std::make_pair(std::vector<double>(t.data(), t.data() + 3),
                                  std::vector<double>(r.data(), r.data() + 9));
          },
          nb::arg("name"))
      .def("set_obstacle_pose", &set_obstacle_pose, nb::arg("name"), nb::arg("translation").none(),
           nb::arg("rotation").none(), nb::arg("axis").none(), nb::arg("degrees").none());
  m.def(
      "_contact_hessians", [] { return names(kContactHessians); },
      "The strategies a contact effect's hessian accepts, in pce::sim::kContactHessians' order.");
  m.def(
      "_broad_phases", [] { return names(pce::enumerators<BroadPhaseKind>()); },
      "The broad phases' names, in pce::sim::kBroadPhaseNames' order.");
  m.def(
      "_load",
      [](const std::string& file, std::optional<int> frames, std::optional<std::string> hessian,
         std::optional<std::string> broad_phase, std::optional<int> threads, std::optional<bool> single_solve,
         std::optional<double> tolerance, std::optional<std::string> mode, std::optional<int> iterations,
         std::optional<int> substeps, std::optional<std::string> acceleration) {
        return std::make_unique<LoadedScene>(file, overrides(frames, hessian, broad_phase, threads, single_solve,
                                                             tolerance, mode, iterations, substeps, acceleration));
      },
      nb::arg("file"), nb::arg("frames").none(), nb::arg("hessian").none(), nb::arg("broad_phase").none(),
      nb::arg("threads").none(), nb::arg("single_solve").none(), nb::arg("tolerance").none(), nb::arg("mode").none(),
      nb::arg("iterations").none(), nb::arg("substeps").none(), nb::arg("acceleration").none());
  m.def(
      "_load_text",
      [](const std::string& text, const std::string& name, const std::string& base, std::optional<int> frames,
         std::optional<std::string> hessian, std::optional<std::string> broad_phase, std::optional<int> threads,
         std::optional<bool> single_solve, std::optional<double> tolerance, std::optional<std::string> mode,
         std::optional<int> iterations, std::optional<int> substeps, std::optional<std::string> acceleration) {
        return std::make_unique<LoadedScene>(text, name, base,
                                             overrides(frames, hessian, broad_phase, threads, single_solve, tolerance,
                                                       mode, iterations, substeps, acceleration));
      },
      nb::arg("text"), nb::arg("name"), nb::arg("base"), nb::arg("frames").none(), nb::arg("hessian").none(),
      nb::arg("broad_phase").none(), nb::arg("threads").none(), nb::arg("single_solve").none(),
      nb::arg("tolerance").none(), nb::arg("mode").none(), nb::arg("iterations").none(), nb::arg("substeps").none(),
      nb::arg("acceleration").none(),
      "Loads a scene from its JSON text: name stands for the file in errors, base is where relative mesh files are.");
  m.def("_check_output", &check_output, nb::arg("what"), nb::arg("path"),
        "Checks run()'s video= or usd= file: ValueError if it cannot be written, RuntimeError without ffmpeg.");
  m.def(
      "_solver_modes", [] { return names(pce::enumerators<SolverMode>()); },
      "The solver modes' names, in pce::sim::kSolverModeNames' order.");
  m.def(
      "_accelerations", [] { return names(pce::enumerators<Acceleration>()); },
      "Block descent's accelerations' names, in pce::sim::kAccelerationNames' order.");
}

}  // namespace pce_python

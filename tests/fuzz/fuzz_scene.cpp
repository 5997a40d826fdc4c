// SPDX-License-Identifier: MIT
/// @file
/// `pce-scene-fuzz`: a structure-aware fuzzer of the scene loader and one simulation frame
/// (docs/fuzzing.md, "Fuzzing scenes"). Built, with the simulator's sources, under
/// AddressSanitizer and UndefinedBehaviorSanitizer when PCE_FUZZ_SANITIZE is on.
///
///     pce-scene-fuzz [--seed S] [--count N] [--seconds T] [--out-dir D] [--timeout T]
///                    [--max-vertices V] [--index I]
///
/// Input I of seed S is generated from std::mt19937_64 seeded with a mix of S and I alone,
/// so `--seed S --index I` regenerates and runs that one input. Each input starts from a
/// shipped scene (examples/scenes/*.json, its generators shrunk so that a frame is fast) or
/// a scene of small OBJ files the fuzzer writes itself, and applies 1–4 mutations: deleted
/// keys, wrong types, extreme numbers, NaN-like strings, huge integers and arrays, extra
/// effects, meshes moved on top of each other, OBJ files truncated or with garbage, bad or
/// negative indices, degenerate, duplicate and non-manifold triangles; or truncates or
/// corrupts the JSON text. The scene is written to `<out-dir>/work/scene.json` (its OBJ
/// files beside it), loaded with `pce::sim::load_scene` (frames 1, threads 1, at most 10
/// Newton iterations) and stepped once. Every input must end in
///   (a) an InputError whose what() is one line "<scene file>: <JSON path>: …" (the path
///       empty only for text that is not valid JSON),
///   (b) a std::runtime_error from step() naming the frame ("frame 1: …" or "frame 1, …"), or
///   (c) a clean frame whose x and v are finite.
/// Anything else — a crash, a sanitizer report, another exception type, a message without
/// the file, a hang (`--timeout`, default 60 s per input, by SIGALRM) or an accepted
/// non-finite state — is a failure: the input is copied to `<out-dir>/failure-seed<S>-input<I>/`
/// (printed), and the run exits non-zero. Inputs whose generators would make more than
/// `--max-vertices` (default 2000) vertices are skipped before loading and counted.
/// Prints one summary line:
///
///     scene-fuzz: N inputs, C clean, E input errors, R runtime errors, S skipped (too large), F failures
#include <pce/sim/input_error.hpp>
#include <pce/sim/scene.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <typeinfo>
#include <unistd.h>
#include <vector>

#if defined(PCE_FUZZ_SANITIZED) && PCE_FUZZ_SANITIZED
#include <sanitizer/common_interface_defs.h>
#endif

namespace fs = std::filesystem;
using nlohmann::json;
using Rng = std::mt19937_64;

namespace {

// ---- failure reporting (also from a signal handler or a sanitizer's death callback) ----

char g_banner[1024] = "";  ///< "pce-scene-fuzz: input I of seed S: files in <work>; replay: ..."

void print_banner() {
  const ssize_t n = ::write(2, g_banner, std::strlen(g_banner));
  (void)n;
}

extern "C" void on_alarm(int) {
  static const char msg[] = "\npce-scene-fuzz: HANG: the input exceeded the per-input time limit\n";
  const ssize_t n = ::write(2, msg, sizeof msg - 1);
  (void)n;
  print_banner();
  std::abort();
}

extern "C" void on_fatal_signal(int sig) {
  static const char msg[] = "\npce-scene-fuzz: CRASH (fatal signal)\n";
  const ssize_t n = ::write(2, msg, sizeof msg - 1);
  (void)n;
  print_banner();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

#if defined(PCE_FUZZ_SANITIZED) && PCE_FUZZ_SANITIZED
void on_sanitizer_death() { print_banner(); }
#endif

// ---- random helpers ----

template <class T> const T& pick(Rng& rng, const std::vector<T>& v) {
  return v[std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng)];
}
int uniform(Rng& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
bool chance(Rng& rng, double p) { return std::uniform_real_distribution<double>(0, 1)(rng) < p; }

// ---- the seeds: shipped scenes (shrunk) and OBJ files ----

/// Shrinks a shipped scene's generators so that one frame takes milliseconds.
void shrink(json& scene) {
  for (json& m : scene["meshes"]) {
    if (!m.contains("generator")) continue;
    json& g = m["generator"];
    if (g["type"] == "grid") {
      g["nx"] = std::min(g["nx"].get<int>(), 6);
      g["ny"] = std::min(g["ny"].get<int>(), 6);
    } else if (g["type"] == "tet_box") {
      for (json& n : g["n"]) n = std::min(n.get<int>(), 2);
    } else if (g["type"] == "tet_ball") {
      g["n"] = 1;
    } else {
      g["count"] = std::min(g["count"].get<int>(), 4);
      g["segments"] = std::min(g["segments"].get<int>(), 6);
    }
  }
}

struct Corpus {
  std::vector<json> scenes;            ///< shipped (shrunk) and OBJ-based scenes
  std::vector<std::string> obj_texts;  ///< small OBJ files the fuzzer writes itself
};

const char* const kObjNames[] = {"two_triangles.obj", "tetra.obj", "polyline.obj", "strip.obj"};

Corpus make_corpus() {
  Corpus c;
  const fs::path dir = fs::path(PCE_SOURCE_DIR) / "examples" / "scenes";
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());  // directory order is unspecified: inputs must replay
  for (const fs::path& f : files) {
    json j = json::parse(std::ifstream(f));
    shrink(j);
    c.scenes.push_back(j);
  }
  c.obj_texts = {
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n",
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n",
      "v 0 0 0\nv 0.1 0 -0.1\nv 0.2 0 -0.2\nv 0.3 0 -0.3\nv 0.4 0 -0.4\nl 1 2 3 4 5\n",
      "v 0 0 0.2\nv 0.3 0 0.2\nv 0 0.3 0.2\nv 0.3 0.3 0.2\nv 0 0.6 0.2\nv 0.3 0.6 0.2\n"
      "f 1 2 3\nf 2 4 3\nf 3 4 5\nf 4 6 5\n",
  };
  // Scenes of OBJ meshes: a cloth patch over a mesh obstacle, a polyline strand.
  c.scenes.push_back(json::parse(R"({
    "dt": 0.02, "frames": 3,
    "meshes": [{"name": "patch", "file": "strip.obj", "density": 0.2},
               {"name": "quad", "file": "two_triangles.obj", "transform": {"translation": [0, 0, 0.5]}}],
    "obstacles": [{"name": "tet", "shape": "mesh", "file": "tetra.obj", "position": [0, 0, -1.2]},
                  {"name": "ball", "shape": "sphere", "radius": 0.3, "position": [0.2, 0.2, -0.4]}],
    "effects": [{"type": "gravity"}, {"type": "stretching", "stiffness": 30},
                {"type": "bending", "stiffness": 1e-4}, {"type": "damping", "coefficient": 0.5},
                {"type": "obstacle_contact", "penalty": {"type": "cubic", "stiffness": 50, "distance": 0.02, "delta": 1e-6}},
                {"type": "self_vertex_face", "penalty": {"type": "quadratic", "stiffness": 20, "distance": 0.01},
                 "length": "signed"},
                {"type": "self_edge_edge", "penalty": {"type": "log_barrier", "stiffness": 5, "distance": 0.01},
                 "closest_features": true}]
  })"));
  c.scenes.push_back(json::parse(R"({
    "dt": 0.01, "frames": 2, "solver": {"mode": "single_solve", "linear_solver": "cg", "broad_phase": "bullet"},
    "meshes": [{"name": "hair", "file": "polyline.obj", "linear_density": 0.01},
               {"name": "hair2", "file": "polyline.obj", "transform": {"translation": [0.05, 0, 0],
                "rotation": {"axis": [0, 0, 1], "degrees": 30}, "scale": 1.5}}],
    "obstacles": [{"name": "bar", "shape": "capsule", "radius": 0.05, "half_length": 0.3, "position": [0, 0, -0.6],
                   "motion": {"velocity": [0, 0, 0.1], "angular_velocity": [0, 0, 1], "start": 0, "stop": 1}},
                  {"name": "floor", "shape": "box", "half_extents": [1, 1, 0.05], "position": [0, 0, -1]}],
    "effects": [{"type": "gravity", "acceleration": [0, 0, -9.81]}, {"type": "strand_stretching", "stiffness": 40},
                {"type": "strand_bending", "stiffness": 1e-4},
                {"type": "pins", "groups": [{"mesh": "hair", "vertices": [0]}, {"box": {"min": [0, -1, -0.01],
                 "max": [1, 1, 0.01]}, "motion": {"velocity": [0.1, 0, 0], "center": [0, 0, 0]}, "release_frame": 2}]},
                {"type": "obstacle_contact", "penalty": {"type": "log_barrier", "stiffness": 10, "distance": 0.02}},
                {"type": "self_edge_edge", "penalty": {"type": "quadratic", "stiffness": 5, "distance": 0.005},
                 "closest_features": true, "hessian": "exact"}]
  })"));
  return c;
}

// ---- mutations ----

/// Every value of `j` as a JSON pointer (the root excluded).
void collect(const json& j, const json::json_pointer& at, std::vector<json::json_pointer>& out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      const json::json_pointer p = at / it.key();
      out.push_back(p);
      collect(*it, p, out);
    }
  } else if (j.is_array()) {
    for (std::size_t k = 0; k < j.size(); ++k) {
      const json::json_pointer p = at / k;
      out.push_back(p);
      collect(j[k], p, out);
    }
  }
}

json extreme_number(Rng& rng, const json& current) {
  switch (uniform(rng, 0, 17)) {
    case 0:
      return 1e308;
    case 1:
      return -1e308;
    case 2:
      return 1e-320;
    case 3:
      return -1e-320;
    case 4:
      return 0;
    case 5:
      return -0.0;
    case 6:
      return -1;
    case 7:
      return 9223372036854775807LL;
    case 8:
      return 18446744073709551615ULL;
    case 9:
      return -9223372036854775807LL - 1;
    case 10:
      return 2147483648LL;
    case 11:
      return 1e15 + 1;
    case 12:
      return std::numeric_limits<double>::max();
    case 13:
      return std::numeric_limits<double>::min();
    case 14:
      return uniform(rng, -3, 5000);
    case 15:
      return std::ldexp(1.0, uniform(rng, -1074, 1023)) * (chance(rng, 0.5) ? 1 : -1);
    default: {  // the current number scaled by 10^k, or its neighbour
      const double v = current.is_number() ? current.get<double>() : 1.0;
      return v * std::pow(10.0, uniform(rng, -8, 8)) * (chance(rng, 0.2) ? -1 : 1);
    }
  }
}

json wrong_type(Rng& rng) {
  switch (uniform(rng, 0, 9)) {
    case 0:
      return nullptr;
    case 1:
      return true;
    case 2:
      return "NaN";
    case 3:
      return "Infinity";
    case 4:
      return "-inf";
    case 5:
      return json::array();
    case 6:
      return json::object();
    case 7:
      return json::array({1, 2});
    case 8:
      return "1e3";
    default:
      return json::array({"x", nullptr, 3});
  }
}

json huge_array(Rng& rng) {
  json a = json::array();
  const int n = chance(rng, 0.5) ? 100000 : uniform(rng, 3, 1000);
  const int kind = uniform(rng, 0, 2);
  for (int k = 0; k < n; ++k) a.push_back(kind == 0 ? json(k % 50) : kind == 1 ? json(-k) : json(1e300));
  return a;
}

/// An effect of a random type with plausible, sometimes absurd, parameters.
json random_effect(Rng& rng) {
  const std::vector<std::string> types = {
      "gravity", "stretching", "bending",          "strand_stretching", "strand_bending",
      "pins",    "damping",    "self_vertex_face", "self_edge_edge",    "obstacle_contact"};
  const std::string t = pick(rng, types);
  json e = {{"type", t}};
  const auto penalty = [&] {
    const std::vector<std::string> kinds = {"quadratic", "cubic", "log_barrier"};
    json p = {{"type", pick(rng, kinds)},
              {"stiffness", std::pow(10.0, uniform(rng, -3, 13))},
              {"distance", std::pow(10.0, uniform(rng, -7, 3))}};
    if (p["type"] == "cubic") p["delta"] = std::pow(10.0, uniform(rng, -12, 2));
    return p;
  };
  if (t == "gravity") e["acceleration"] = {0, 0, -std::pow(10.0, uniform(rng, -2, 7))};
  if (t == "stretching" || t == "bending" || t == "strand_stretching" || t == "strand_bending")
    e["stiffness"] = std::pow(10.0, uniform(rng, -6, 13));
  if (t == "damping") e["coefficient"] = std::pow(10.0, uniform(rng, -3, 7));
  if (t == "pins") e["groups"] = json::array({{{"vertices", json::array({0, uniform(rng, 0, 60)})}}});
  if (t == "self_vertex_face" || t == "self_edge_edge" || t == "obstacle_contact") e["penalty"] = penalty();
  if (t == "self_vertex_face" || t == "self_edge_edge") {
    if (chance(rng, 0.5)) e["closest_features"] = chance(rng, 0.5);
    if (chance(rng, 0.3)) e["length"] = chance(rng, 0.5) ? "signed" : "unsigned";
    if (chance(rng, 0.3))
      e["hessian"] = pick(rng, std::vector<std::string>{"analytic", "exact", "numerical", "gauss_newton", "abs"});
  }
  return e;
}

/// An OBJ text mutated: truncated, garbage, bad indices, degenerate, duplicate or
/// non-manifold triangles, extreme coordinates.
std::string mutate_obj(Rng& rng, std::string text) {
  const int ops = uniform(rng, 1, 3);
  for (int k = 0; k < ops; ++k) {
    switch (uniform(rng, 0, 11)) {
      case 0:  // truncated
        text.resize(std::uniform_int_distribution<std::size_t>(0, text.size())(rng));
        break;
      case 1: {  // garbage bytes
        const int n = uniform(rng, 1, 8);
        for (int i = 0; i < n && !text.empty(); ++i)
          text[std::uniform_int_distribution<std::size_t>(0, text.size() - 1)(rng)] =
              static_cast<char>(uniform(rng, 0, 255));
        break;
      }
      case 2:
        text += "f 1 2 " + std::to_string(uniform(rng, -20, 20)) + "\n";
        break;  // bad or negative index
      case 3:
        text += "f -1 -2 -3\n";
        break;  // relative indices
      case 4:
        text += "f 1 1 2\n";
        break;  // repeated vertex
      case 5:
        text += "v 0 0 0\nv 1 0 0\nv 2 0 0\nf -3 -2 -1\n";
        break;  // collinear (zero area)
      case 6:
        text += "f 1 2 3\nf 1 2 3\nf 3 2 1\n";
        break;  // duplicates
      case 7:
        text += "v 0.5 -1 1\nv 0.5 -1 -1\nf 1 2 -1\nf 2 1 -2\n";
        break;  // non-manifold edge
      case 8:
        text += "v " + std::string(chance(rng, 0.5) ? "1e308" : "4e5") + " 0 0\nf 1 2 -1\n";
        break;
      case 9:
        text += "v 1e-320 0 0\nv 0 1e-320 0\nf -1 -2 1\n";
        break;  // denormal triangle
      case 10:
        text += "l 1 2 1\nl " + std::to_string(uniform(rng, 1, 6)) + "\n";
        break;
      default:
        text += "f 99999999999999999999 1 2\nv nan 0 0\nvt 0 0\nusemtl x\n";
        break;
    }
  }
  return text;
}

/// Applies one structural mutation to `scene`; `obj` may be replaced by a mutated OBJ text
/// that some mesh or obstacle then refers to as "fuzz.obj".
void mutate(Rng& rng, json& scene, std::string& obj, const Corpus& corpus) {
  std::vector<json::json_pointer> paths;
  collect(scene, json::json_pointer(), paths);
  const int op = uniform(rng, 0, 13);
  if (paths.empty()) return;
  const json::json_pointer at = pick(rng, paths);
  json& target = scene[at];
  switch (op) {
    case 0:
    case 1: {  // delete a key or an array element
      json& parent = scene[at.parent_pointer()];
      const std::string key = at.back();
      if (parent.is_object())
        parent.erase(key);
      else if (parent.is_array() && !parent.empty())
        parent.erase(parent.begin() + static_cast<long>(std::min<std::size_t>(std::stoul(key), parent.size() - 1)));
      break;
    }
    case 2:
      target = wrong_type(rng);
      break;
    case 3:
    case 4:
    case 5: {  // an extreme number, preferably in place of a number
      std::vector<json::json_pointer> numbers;
      for (const auto& p : paths)
        if (scene[p].is_number()) numbers.push_back(p);
      const json::json_pointer n = numbers.empty() ? at : pick(rng, numbers);
      scene[n] = extreme_number(rng, scene[n]);
      break;
    }
    case 6:
      target = huge_array(rng);
      break;
    case 7: {  // duplicate an element of an array (effects, meshes, groups, ...)
      json& parent = scene[at.parent_pointer()];
      if (parent.is_array()) parent.push_back(target);
      break;
    }
    case 8:
      scene["effects"].push_back(random_effect(rng));
      break;
    case 9: {  // a mesh or obstacle made of a (mutated) OBJ file
      obj = chance(rng, 0.7) ? mutate_obj(rng, pick(rng, corpus.obj_texts)) : pick(rng, corpus.obj_texts);
      if (chance(rng, 0.5) && scene.contains("meshes") && scene["meshes"].is_array() && !scene["meshes"].empty()) {
        json& m =
            scene["meshes"][static_cast<std::size_t>(uniform(rng, 0, static_cast<int>(scene["meshes"].size()) - 1))];
        if (m.is_object()) {
          m.erase("generator");
          m["file"] = "fuzz.obj";
        }
      } else {
        scene["obstacles"].push_back({{"name", "fuzz_obstacle"}, {"shape", "mesh"}, {"file", "fuzz.obj"}});
      }
      break;
    }
    case 10: {  // every mesh moved on top of the first one
      if (!scene.contains("meshes") || !scene["meshes"].is_array()) break;
      for (json& m : scene["meshes"])
        if (m.is_object()) m["transform"] = {{"translation", {0, 0, 0.1 * uniform(rng, 0, 1)}}};
      break;
    }
    case 11:
      target = std::string(static_cast<std::size_t>(uniform(rng, 0, 3)), 'x');
      break;
    case 12:  // an unknown key, or a key of another object
      if (target.is_object()) target[chance(rng, 0.5) ? "stifness" : "type"] = extreme_number(rng, 1.0);
      break;
    default: {  // the same field of a different shipped scene: unusual combinations
      const json& other = pick(rng, corpus.scenes);
      if (other.contains(at)) target = other[at];
      break;
    }
  }
}

/// Vertices the scene's generators and OBJ files would make (an estimate before loading).
long estimated_vertices(const json& scene) {
  if (!scene.is_object() || !scene.contains("meshes") || !scene["meshes"].is_array()) return 0;
  long total = 0;
  const auto integer = [](const json& g, const char* key) -> long {
    if (!g.contains(key) || !g[key].is_number()) return 1;
    const double v = g[key].get<double>();
    return v > 1e9 ? 1000000000L : v < 1 ? 1 : static_cast<long>(v);
  };
  for (const json& m : scene["meshes"]) {
    if (!m.is_object() || !m.contains("generator") || !m["generator"].is_object()) {
      total += 16;
      continue;
    }
    const json& g = m["generator"];
    const bool strands = g.contains("type") && g["type"] == "strands";
    if (g.contains("type") && (g["type"] == "tet_box" || g["type"] == "tet_ball")) {
      // (n₀ + 1)(n₁ + 1)(n₂ + 1) vertices, or (2n + 1)³ for a ball
      const bool box = g["type"] == "tet_box";
      long count = 1;
      for (int k = 0; k < 3; ++k) {
        const json n =
            box && g.contains("n") && g["n"].is_array() && g["n"].size() == 3 ? g["n"][k] : g.value("n", json(1));
        const double v = n.is_number() ? n.get<double>() : 1.0;
        const long c = v > 1e3 ? 1000L : v < 1 ? 1 : static_cast<long>(v);
        count *= box ? c + 1 : 2 * c + 1;
      }
      total += count;
      continue;
    }
    total +=
        strands ? integer(g, "count") * (integer(g, "segments") + 1) : (integer(g, "nx") + 1) * (integer(g, "ny") + 1);
  }
  return total;
}

// ---- the run ----

struct Options {
  unsigned long long seed = 1;
  long count = -1;  ///< -1: until --seconds (or 1000 without it)
  double seconds = 0;
  fs::path out_dir = ".";
  unsigned timeout = 60;
  long max_vertices = 2000;
  long index = -1;  ///< replay one input
};

struct Counts {
  long inputs = 0, clean = 0, input_errors = 0, runtime_errors = 0, skipped = 0, failures = 0;
};

enum class Outcome { clean, input_error, runtime_error, skipped, failure };

struct Input {
  std::string scene_text;
  std::string obj_text;  ///< "fuzz.obj" (empty: not written)
  json scene;            ///< parsed form (null when the text was corrupted)
};

Input generate(const Corpus& corpus, unsigned long long seed, unsigned long long index) {
  Rng rng(seed * 0x9E3779B97F4A7C15ULL ^ (index + 0x632BE59BD9B4E019ULL));
  Input in;
  in.scene = pick(rng, corpus.scenes);
  const int n = chance(rng, 0.5) ? 1 : uniform(rng, 2, 4);
  for (int k = 0; k < n; ++k) {
    try {  // a mutation that does not apply to what earlier ones left (push_back on a number, ...) is dropped
      mutate(rng, in.scene, in.obj_text, corpus);
    } catch (const json::exception&) {
    }
  }
  in.scene_text = in.scene.dump(chance(rng, 0.5) ? -1 : 1);
  if (chance(rng, 0.06)) {  // text-level: truncated or corrupted JSON
    if (chance(rng, 0.5))
      in.scene_text.resize(std::uniform_int_distribution<std::size_t>(0, in.scene_text.size())(rng));
    else if (!in.scene_text.empty())
      in.scene_text[std::uniform_int_distribution<std::size_t>(0, in.scene_text.size() - 1)(rng)] =
          static_cast<char>(uniform(rng, 0, 255));
    in.scene = nullptr;
  }
  return in;
}

bool fail(const std::string& why) {
  std::fprintf(stderr, "\npce-scene-fuzz: FAILURE: %s\n", why.c_str());
  print_banner();
  return false;
}

/// Runs one input; returns the outcome (failures are printed).
Outcome run(const Input& in, const fs::path& work, const Options& opt) {
  if (!in.scene.is_null() && estimated_vertices(in.scene) > opt.max_vertices) return Outcome::skipped;
  const fs::path file = work / "scene.json";
  std::ofstream(file, std::ios::binary) << in.scene_text;
  if (!in.obj_text.empty()) std::ofstream(work / "fuzz.obj", std::ios::binary) << in.obj_text;
  const std::string name = file.string();
  std::unique_ptr<pce::sim::Scene> scene;
  pce::sim::SceneOverrides o;
  o.frames = 1;
  o.threads = 1;
  try {
    scene = pce::sim::load_scene(file, o);
  } catch (const pce::sim::InputError& e) {
    const std::string what = e.what();
    if (e.file() != name)
      return fail("InputError names the file \"" + e.file() + "\", not " + name + ": " + what), Outcome::failure;
    if (what.find('\n') != std::string::npos)
      return fail("InputError message has a newline: " + what), Outcome::failure;
    const std::string head = name + ": " + (e.where().empty() ? "" : e.where() + ": ");
    if (what.rfind(head, 0) != 0)
      return fail("InputError message does not start with \"" + head + "\": " + what), Outcome::failure;
    if (e.where().empty() && what.rfind(name + ": not valid JSON", 0) != 0)
      return fail("InputError without a JSON path: " + what), Outcome::failure;
    return Outcome::input_error;
  } catch (const std::exception& e) {
    return fail(std::string("load_scene threw a non-InputError (") + typeid(e).name() + "): " + e.what()),
           Outcome::failure;
  }
  pce::sim::Simulation& sim = scene->simulation;
  sim.solver.max_iterations = std::min(sim.solver.max_iterations, 10);
  try {
    sim.step();
  } catch (const pce::sim::ArgumentError& e) {
    return fail(std::string("step() refused a loaded scene (ArgumentError): ") + e.what()), Outcome::failure;
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    const bool names_frame = what.rfind("frame 1", 0) == 0 && what.size() > 7 && (what[7] == ':' || what[7] == ',');
    if (!names_frame || what.find('\n') != std::string::npos)
      return fail("runtime_error from step() does not name the frame: " + what), Outcome::failure;
    return Outcome::runtime_error;
  } catch (const std::exception& e) {
    return fail(std::string("step() threw ") + typeid(e).name() + ": " + e.what()), Outcome::failure;
  }
  if (!sim.x.allFinite() || !sim.v.allFinite()) return fail("a clean frame with a non-finite state"), Outcome::failure;
  return Outcome::clean;
}

void save_failure(const fs::path& work, const Options& opt, unsigned long long index) {
  const fs::path dir = opt.out_dir / ("failure-seed" + std::to_string(opt.seed) + "-input" + std::to_string(index));
  fs::create_directories(dir);
  for (const auto& e : fs::directory_iterator(work))
    fs::copy_file(e.path(), dir / e.path().filename(), fs::copy_options::overwrite_existing);
  std::fprintf(stderr, "pce-scene-fuzz: failing input saved in %s\n", dir.string().c_str());
}

int usage() {
  std::fprintf(stderr,
               "usage: pce-scene-fuzz [--seed S] [--count N] [--seconds T] [--out-dir D] [--timeout T] "
               "[--max-vertices V] [--index I]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return usage();
    const char* v = argv[++i];
    if (a == "--seed")
      opt.seed = std::strtoull(v, nullptr, 10);
    else if (a == "--count")
      opt.count = std::strtol(v, nullptr, 10);
    else if (a == "--seconds")
      opt.seconds = std::strtod(v, nullptr);
    else if (a == "--out-dir")
      opt.out_dir = v;
    else if (a == "--timeout")
      opt.timeout = static_cast<unsigned>(std::strtoul(v, nullptr, 10));
    else if (a == "--max-vertices")
      opt.max_vertices = std::strtol(v, nullptr, 10);
    else if (a == "--index")
      opt.index = std::strtol(v, nullptr, 10);
    else
      return usage();
  }
  if (opt.count < 0) opt.count = opt.seconds > 0 ? std::numeric_limits<long>::max() : 1000;
  const fs::path work = fs::absolute(opt.out_dir) / "work";
  fs::create_directories(work);
  const Corpus corpus = make_corpus();
  for (std::size_t k = 0; k < corpus.obj_texts.size(); ++k) std::ofstream(work / kObjNames[k]) << corpus.obj_texts[k];
  std::signal(SIGALRM, on_alarm);
  std::signal(SIGSEGV, on_fatal_signal);
  std::signal(SIGBUS, on_fatal_signal);
  std::signal(SIGFPE, on_fatal_signal);
#if defined(PCE_FUZZ_SANITIZED) && PCE_FUZZ_SANITIZED
  __sanitizer_set_death_callback(on_sanitizer_death);
#endif
  Counts c;
  const auto t0 = std::chrono::steady_clock::now();
  const long first = opt.index >= 0 ? opt.index : 0;
  const long last = opt.index >= 0 ? opt.index + 1 : opt.count;
  for (long index = first; index < last; ++index) {
    if (opt.seconds > 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > opt.seconds)
      break;
    std::snprintf(g_banner, sizeof g_banner,
                  "pce-scene-fuzz: input %ld of seed %llu: scene %s/scene.json (OBJ files beside it); replay: "
                  "pce-scene-fuzz --seed %llu --index %ld\n",
                  index, opt.seed, work.string().c_str(), opt.seed, index);
    std::error_code ec;
    fs::remove(work / "fuzz.obj", ec);
    const Input in = generate(corpus, opt.seed, static_cast<unsigned long long>(index));
    alarm(opt.timeout);
    const Outcome r = run(in, work, opt);
    alarm(0);
    ++c.inputs;
    switch (r) {
      case Outcome::clean:
        ++c.clean;
        break;
      case Outcome::input_error:
        ++c.input_errors;
        break;
      case Outcome::runtime_error:
        ++c.runtime_errors;
        break;
      case Outcome::skipped:
        ++c.skipped;
        break;
      case Outcome::failure:
        ++c.failures;
        save_failure(work, opt, static_cast<unsigned long long>(index));
        break;
    }
    if (opt.index < 0 && c.inputs % 1000 == 0)
      std::fprintf(stderr,
                   "scene-fuzz: %ld inputs, %ld clean, %ld input errors, %ld runtime errors, %ld skipped, %ld failures "
                   "(%.0f s)\n",
                   c.inputs, c.clean, c.input_errors, c.runtime_errors, c.skipped, c.failures,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::printf(
      "scene-fuzz: %ld inputs, %ld clean, %ld input errors, %ld runtime errors, %ld skipped (too large), "
      "%ld failures, %.1f s\n",
      c.inputs, c.clean, c.input_errors, c.runtime_errors, c.skipped, c.failures,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return c.failures == 0 ? 0 : 1;
}

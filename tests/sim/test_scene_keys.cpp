// SPDX-License-Identifier: MIT
// The scene format's key tables in docs/simulation.md §2 list exactly the keys the loader
// accepts. For every JSON object the loader reads (every `Params::only` list in
// src/sim/scene/), an unknown key "zz_not_a_key" is put into that object of a scene that
// otherwise loads; the loader's error "unknown field (expected one of: a, b, c)" lists the
// keys it accepts, and they are compared, as sets, with the keys of the object's table in
// §2. A key the loader accepts that the table lacks fails, and so does a key the table
// documents that the loader refuses. The mapping from JSON object to table is `kObjects`
// below; a test also checks that the objects reached cover every `only({...})` list in the
// loader's sources, so a new object (or a new key) cannot escape the comparison. The effect
// names of §2.5 and of §6.3's unknown-effect example are the registry's, in its order.
#include "scene/registry.hpp"

#include <pce/sim/input_error.hpp>
#include <pce/sim/scene.hpp>

#include <gtest/gtest.h>

#include <unistd.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Keys = std::set<std::string>;

const char* const kProbe = "zz_not_a_key";

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string join(const Keys& keys) {
  std::string out;
  for (const auto& k : keys) out += (out.empty() ? "" : ", ") + k;
  return out;
}

// ---------------------------------------------------------------------------------------
// The scene: one that loads and holds every object the loader reads.

/// The directory of the scene (and of the mesh obstacle's OBJ file), one per process: ctest
/// runs this file's tests as processes side by side, and rewriting one shared OBJ file while
/// another process reads it gave that one an empty mesh.
fs::path scene_dir() {
  const fs::path dir = fs::path(PCE_TEST_TMP) / ("scene_keys_" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "plate.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  return dir;
}

/// Every object the loader reads, once (effects of each type, every generator and shape).
json full_scene() {
  return json::parse(R"({
    "description": "every object the scene loader reads",
    "dt": 0.01, "frames": 1, "output_every": 1, "view_direction": [0, -1, 0],
    "allow_initial_intersections": false,
    "solver": {"mode": "newton", "tolerance": 0.01, "max_iterations": 5, "linear_solver": "direct",
               "threads": 1, "broad_phase": "brute"},
    "meshes": [
      {"name": "cloth", "generator": {"type": "grid", "width": 1, "height": 1, "nx": 2, "ny": 2},
       "transform": {"translation": [0, 0, 1], "rotation": {"axis": [0, 0, 1], "degrees": 10}, "scale": 1},
       "density": 0.1},
      {"name": "hair", "generator": {"type": "strands", "count": 1, "segments": 2, "length": 0.5, "spacing": 0.1,
                                     "curl": 0}, "linear_density": 0.005},
      {"name": "block", "generator": {"type": "tet_box", "size": [0.2, 0.2, 0.2], "n": [1, 1, 1]},
       "transform": {"translation": [3, 0, 1]}, "density": 100},
      {"name": "ball", "generator": {"type": "tet_ball", "radius": 0.1, "n": 1},
       "transform": {"translation": [6, 0, 1]}}
    ],
    "obstacles": [
      {"name": "sphere", "shape": "sphere", "radius": 0.2, "position": [0, 0, -1],
       "rotation": {"axis": [1, 0, 0], "degrees": 5},
       "motion": {"velocity": [0, 0, 0.1], "angular_velocity": [0, 0, 0], "start": 0, "stop": 1}},
      {"name": "floor", "shape": "box", "half_extents": [1, 1, 0.1], "position": [0, 0, -3],
       "motion": {"interpolation": "smooth", "keyframes": [{"time": 0},
         {"time": 1, "translation": [0, 0, 0.1], "rotation": {"axis": [0, 0, 1], "degrees": 10}}]}},
      {"name": "rod", "shape": "capsule", "radius": 0.05, "half_length": 0.5, "position": [0, 0, -4]},
      {"name": "plate", "shape": "mesh", "file": "plate.obj", "transform": {"translation": [0, 0, -5]}}
    ],
    "effects": [
      {"type": "gravity", "acceleration": [0, 0, -9.81]},
      {"type": "stretching", "model": "arap", "stiffness": 10},
      {"type": "bending", "stiffness": 1e-4},
      {"type": "strand_stretching", "stiffness": 10},
      {"type": "strand_bending", "stiffness": 1e-4},
      {"type": "pins", "stiffness": 1e4, "groups": [
        {"mesh": "cloth", "vertices": [0], "release_frame": 5,
         "motion": {"velocity": [0, 0, 0], "angular_velocity": [0, 0, 1], "center": [0, 0, 1], "start": 0, "stop": 1}},
        {"mesh": "cloth", "box": {"min": [0.4, 0.4, 0.9], "max": [0.6, 0.6, 1.1]}}]},
      {"type": "damping", "coefficient": 0.1},
      {"type": "self_vertex_face", "penalty": {"type": "quadratic", "stiffness": 10, "distance": 0.01},
       "length": "signed", "hessian": "analytic", "closest_features": false, "ccd": true, "area_weighted": false,
       "min_separation": 0.01, "friction": {"coefficient": 0.5, "slip_velocity": 0.001, "lagged_iterations": 1}},
      {"type": "self_edge_edge", "penalty": {"type": "cubic", "stiffness": 10, "distance": 0.01, "delta": 0},
       "closest_features": true},
      {"type": "obstacle_contact", "penalty": {"type": "log_barrier", "stiffness": 10, "distance": 0.01},
       "obstacles": ["sphere", "floor", "rod", "plate"], "area_weighted": false, "min_separation": 0.01,
       "friction": {"coefficient": 0.5}},
      {"type": "volume_elasticity", "model": "stable_neo_hookean", "young_modulus": 1e4, "poisson_ratio": 0.3,
       "hessian": "analytic"}
    ]
  })");
}

/// `path` ("/effects/{pins}/groups/0") as a JSON pointer into `j` ("" is the whole scene):
/// a `{name}` component is the index of the array element whose "type" or "name" is `name`.
/// Empty when there is no such element.
std::optional<std::string> resolve(const json& j, const std::string& path) {
  std::string pointer;
  const json* at = &j;
  std::stringstream parts(path.empty() ? "" : path.substr(1));
  std::string part;
  while (std::getline(parts, part, '/')) {
    if (part.size() > 2 && part.front() == '{' && part.back() == '}') {
      const std::string name = part.substr(1, part.size() - 2);
      std::size_t i = 0;
      while (i < at->size() && at->at(i).value("type", "") != name && at->at(i).value("name", "") != name) ++i;
      if (i == at->size()) return std::nullopt;
      part = std::to_string(i);
    }
    at = &(*at)[json::json_pointer("/" + part)];
    pointer += "/" + part;
  }
  return pointer;
}

/// The loader's JSON path of `pointer` ("/effects/5/groups/0" → "effects[5].groups[0]").
std::string loader_path(const std::string& pointer) {
  std::string path;
  std::stringstream parts(pointer.empty() ? "" : pointer.substr(1));
  std::string part;
  while (std::getline(parts, part, '/'))
    path += !part.empty() && part.find_first_not_of("0123456789") == std::string::npos
                ? "[" + part + "]"
                : (path.empty() ? "" : ".") + part;
  return path;
}

/// The message of loading `j`, "" when it loads.
std::string load_error(const json& j) {
  try {
    pce::sim::load_scene_text(j.dump(), "scene.json", scene_dir());
  } catch (const pce::sim::InputError& e) {
    return e.what();
  }
  return "";
}

/// The keys the loader accepts in `j`'s object at `pointer`, from the error an unknown key
/// there gives; `error` gets a reason when there is none.
Keys loader_keys(json j, const std::string& pointer, std::string* error) {
  j[json::json_pointer(pointer)][kProbe] = 1;
  const std::string message = load_error(j);
  const std::string expected_start =
      "scene.json: " + loader_path(pointer + "/" + kProbe) + ": unknown field (expected one of: ";
  if (message.rfind(expected_start, 0) != 0 || message.back() != ')') {  // also when it loads
    *error =
        "the unknown key at " + loader_path(pointer) + " gave \"" + message + "\", not \"" + expected_start + "…)\"";
    return {};
  }
  Keys keys;
  std::stringstream list(message.substr(expected_start.size(), message.size() - expected_start.size() - 1));
  std::string key;
  while (std::getline(list, key, ',')) keys.insert(key.substr(key.find_first_not_of(' ')));
  return keys;
}

// ---------------------------------------------------------------------------------------
// The documentation: docs/simulation.md §2's tables.

const std::string& docs() {
  static const std::string text = read_text(fs::path(PCE_SOURCE_DIR) / "docs" / "simulation.md");
  return text;
}

/// The cells of a table row ("| `a` | b |"), split at the `|`s outside code spans.
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string cell;
  bool code = false;
  for (std::size_t i = 1; i < row.size(); ++i) {  // after the leading '|'
    const char c = row[i];
    if (c == '`') code = !code;
    if (c == '|' && !code) {
      const std::size_t b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
      out.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
      cell.clear();
    } else {
      cell += c;
    }
  }
  return out;
}

/// The body rows (after the header and the `|---|` line) of the first table after `anchor`
/// in the section that starts at the heading `section`; empty if there is none.
std::vector<std::vector<std::string>> table_after(const std::string& section, const std::string& anchor) {
  const std::string& doc = docs();
  const std::size_t begin = doc.find("\n" + section + "\n");
  if (begin == std::string::npos) return {};
  const std::size_t end = std::min(doc.find("\n## ", begin + 1), doc.find("\n### ", begin + 1));
  const std::size_t from = doc.find(anchor, begin);
  if (from == std::string::npos || from > end) return {};
  std::size_t line = doc.find("\n|", from);
  if (line == std::string::npos || line > end) return {};
  std::vector<std::vector<std::string>> rows;
  for (int k = 0; line != std::string::npos && line < end && doc.compare(line, 2, "\n|") == 0; ++k) {
    const std::size_t next = doc.find('\n', line + 1);
    if (k >= 2) rows.push_back(cells(doc.substr(line + 1, next - line - 1)));
    line = next;
  }
  return rows;
}

/// The key names in a cell: its code spans that are identifiers (`stiffness` μ → stiffness;
/// "`young_modulus` E, `poisson_ratio` ν" → both).
Keys code_names(const std::string& cell) {
  static const std::regex name("`([a-z_][a-z0-9_]*)`");
  Keys out;
  for (std::sregex_iterator it(cell.begin(), cell.end(), name), e; it != e; ++it) out.insert((*it)[1]);
  return out;
}

/// What a table of docs/simulation.md §2 documents for one JSON object.
struct DocTable {
  const char* section;  ///< the heading of its section ("### 2.2 Meshes")
  const char* anchor;   ///< text in the section after which it is the first table ("" for the first)
  /// Tables that list several objects: the first column's entry whose rows are meant
  /// ("`grid`"; rows with an empty first column continue the entry above). The keys are then
  /// in the second column, else in the first.
  const char* group = nullptr;
  /// An object written inline: the row (first column's key) whose type cell spells it as
  /// `{"a": …, "b": …}`; its keys are the quoted names there.
  const char* inline_row = nullptr;
  /// An obstacle shape: rows restricted to shapes by a note "(sphere, capsule)" or
  /// "(mesh only)" count only for the shapes they name.
  const char* shape = nullptr;
  /// Keys documented outside the table, each with the text of the docs that documents it.
  std::vector<std::pair<std::string, std::string>> elsewhere{};
  /// Keys of the table that this object refuses, each with the text its row says so by.
  std::vector<std::pair<std::string, std::string>> refused{};
};

/// The shapes a row is restricted to by a parenthesised list of shape names, empty if none.
Keys row_shapes(const std::vector<std::string>& row) {
  static const std::regex note(R"(\(((?:sphere|box|capsule|mesh)(?:, (?:sphere|box|capsule|mesh))*)(?: only)?\))");
  Keys shapes;
  for (const std::string& cell : row) {
    std::smatch m;
    if (!std::regex_search(cell, m, note)) continue;
    std::stringstream list(m[1]);
    std::string s;
    while (std::getline(list, s, ',')) shapes.insert(s.substr(s.find_first_not_of(' ')));
  }
  return shapes;
}

/// The keys `t` documents; `error` gets a reason when the table or a cited text is missing.
Keys doc_keys(const DocTable& t, std::string* error) {
  const auto rows = table_after(t.section, t.anchor);
  if (rows.empty()) {
    *error = std::string("docs/simulation.md has no table after \"") + t.anchor + "\" in \"" + t.section + "\"";
    return {};
  }
  Keys keys;
  bool in_group = false;
  for (const auto& row : rows) {
    if (row.size() < 2) continue;
    if (t.inline_row) {
      if (code_names(row[0]) != Keys{t.inline_row}) continue;
      static const std::regex quoted("\"([a-z_][a-z0-9_]*)\"");
      for (std::sregex_iterator it(row[1].begin(), row[1].end(), quoted), e; it != e; ++it) keys.insert((*it)[1]);
      continue;
    }
    if (t.group) {
      if (!row[0].empty()) in_group = row[0].find(t.group) != std::string::npos;
      if (in_group) keys.merge(code_names(row[1]));
      continue;
    }
    const Keys shapes = row_shapes(row);
    if (t.shape && !shapes.empty() && !shapes.count(t.shape)) continue;
    keys.merge(code_names(row[0]));
  }
  if (keys.empty()) *error = std::string("docs/simulation.md: the table after \"") + t.anchor + "\" lists no keys";
  for (const auto& [key, text] : t.elsewhere) {
    if (docs().find(text) == std::string::npos)
      *error = "docs/simulation.md no longer documents `" + key + "` by \"" + text + "\"";
    keys.insert(key);
  }
  for (const auto& [key, text] : t.refused) {
    bool said = false;
    for (const auto& row : rows)
      said = said || (!row.empty() && code_names(row[0]).count(key) && row.back().find(text) != std::string::npos);
    if (!said) *error = "docs/simulation.md's row of `" + key + "` no longer says \"" + text + "\"";
    keys.erase(key);
  }
  return keys;
}

// ---------------------------------------------------------------------------------------
// The mapping: each object the loader reads → its table.

struct SceneObject {
  const char* name;  ///< for messages
  std::string path;  ///< where the unknown key goes in `full_scene()` ({name}: see `resolve`)
  DocTable doc;
};

const char* const kTop = "### 2.1 Top level";
const char* const kMeshes = "### 2.2 Meshes";
const char* const kObstacles = "### 2.3 Obstacles";
const char* const kSolver = "### 2.4 Solver";
const char* const kEffects = "### 2.5 Effects";
const char* const kPenalties = "### 2.6 Penalties";

/// The effects' table: one effect's rows, and `type` and `meshes`, documented in the prose
/// above it.
DocTable effect_rows(const char* name, bool meshes = true) {
  DocTable t{kEffects, "", name, nullptr, nullptr, {{"type", "Each entry is `{\"type\": NAME, …}`"}}};
  if (meshes) t.elsewhere.emplace_back("meshes", "Every entry may name the meshes it");
  return t;
}

/// A generator's rows of the generator table, and its `type` (the table's first column).
DocTable generator_rows(const char* name) {
  return {kMeshes, "`generator`:", name, nullptr, nullptr, {{"type", "| `type` | field | type | default | meaning |"}}};
}

/// An obstacle shape's rows of the obstacle table.
DocTable shape_rows(const char* shape) { return {kObstacles, "", nullptr, nullptr, shape}; }

const std::vector<SceneObject>& objects() {
  static const std::vector<SceneObject> list = {
      {"top level", "", {kTop, ""}},
      {"solver", "/solver", {kSolver, ""}},
      {"mesh", "/meshes/{cloth}", {kMeshes, ""}},
      {"mesh transform", "/meshes/{cloth}/transform", {kMeshes, "`transform`:"}},
      {"mesh transform rotation", "/meshes/{cloth}/transform/rotation", {kMeshes, "`transform`:", nullptr, "rotation"}},
      {"grid generator", "/meshes/{cloth}/generator", generator_rows("`grid`")},
      {"strands generator", "/meshes/{hair}/generator", generator_rows("`strands`")},
      {"tet_box generator", "/meshes/{block}/generator", generator_rows("`tet_box`")},
      {"tet_ball generator", "/meshes/{ball}/generator", generator_rows("`tet_ball`")},
      {"sphere obstacle", "/obstacles/{sphere}", shape_rows("sphere")},
      {"box obstacle", "/obstacles/{floor}", shape_rows("box")},
      {"capsule obstacle", "/obstacles/{rod}", shape_rows("capsule")},
      {"mesh obstacle", "/obstacles/{plate}", shape_rows("mesh")},
      {"mesh obstacle transform", "/obstacles/{plate}/transform", {kMeshes, "`transform`:"}},
      {"obstacle rotation", "/obstacles/{sphere}/rotation", {kObstacles, "", nullptr, "rotation"}},
      {"obstacle motion", "/obstacles/{sphere}/motion", {kObstacles, "`motion`: between"}},
      {"keyframed obstacle motion", "/obstacles/{floor}/motion", {kObstacles, "`motion`: between"}},
      {"keyframe", "/obstacles/{floor}/motion/keyframes/1", {kObstacles, "A keyframe is"}},
      {"keyframe rotation",
       "/obstacles/{floor}/motion/keyframes/1/rotation",
       {kObstacles, "A keyframe is", nullptr, "rotation"}},
      {"gravity", "/effects/{gravity}", effect_rows("`gravity`")},
      {"stretching", "/effects/{stretching}", effect_rows("`stretching`")},
      {"bending", "/effects/{bending}", effect_rows("`bending`")},
      {"strand_stretching", "/effects/{strand_stretching}", effect_rows("`strand_stretching`")},
      {"strand_bending", "/effects/{strand_bending}", effect_rows("`strand_bending`")},
      {"pins", "/effects/{pins}", effect_rows("`pins`")},
      {"damping", "/effects/{damping}", effect_rows("`damping`")},
      {"self_vertex_face", "/effects/{self_vertex_face}", effect_rows("`self_vertex_face`")},
      {"self_edge_edge", "/effects/{self_edge_edge}", effect_rows("`self_edge_edge`")},
      {"obstacle_contact", "/effects/{obstacle_contact}", effect_rows("`obstacle_contact`")},
      {"volume_elasticity", "/effects/{volume_elasticity}", effect_rows("`volume_elasticity`")},
      {"pin group", "/effects/{pins}/groups/0", {kEffects, "A pin group is one of"}},
      {"pin group box", "/effects/{pins}/groups/1/box", {kEffects, "A pin group is one of", nullptr, "box"}},
      {"pin group motion", "/effects/{pins}/groups/0/motion", {kEffects, "A pin group's `motion`"}},
      {"quadratic penalty",
       "/effects/{self_vertex_face}/penalty",
       {kPenalties, "", nullptr, nullptr, nullptr, {}, {{"delta", "cubic only"}}}},
      {"cubic penalty", "/effects/{self_edge_edge}/penalty", {kPenalties, ""}},
      {"log_barrier penalty",
       "/effects/{obstacle_contact}/penalty",
       {kPenalties, "", nullptr, nullptr, nullptr, {}, {{"delta", "cubic only"}}}},
      {"self-contact friction", "/effects/{self_vertex_face}/friction", {kPenalties, "`\"friction\": {"}},
      {"obstacle friction", "/effects/{obstacle_contact}/friction", {kPenalties, "`\"friction\": {"}},
  };
  return list;
}

/// The keys of every `only({...})` list in the loader's sources (every .cpp of
/// src/sim/scene), one set per call.
std::vector<Keys> source_only_lists() {
  std::vector<Keys> lists;
  for (const fs::directory_entry& file : fs::directory_iterator(fs::path(PCE_SOURCE_DIR) / "src" / "sim" / "scene")) {
    if (file.path().extension() != ".cpp") continue;
    const std::string text = read_text(file.path());
    for (std::size_t at = text.find("only({"); at != std::string::npos; at = text.find("only({", at + 1)) {
      const std::string list = text.substr(at, text.find("})", at) - at);
      static const std::regex quoted("\"([^\"]*)\"");
      Keys keys;
      for (std::sregex_iterator it(list.begin(), list.end(), quoted), e; it != e; ++it) keys.insert((*it)[1]);
      lists.push_back(keys);
    }
  }
  return lists;
}

TEST(SceneKeys, TheProbedSceneLoads) {
  EXPECT_EQ(load_error(full_scene()), "");
  for (const SceneObject& o : objects()) EXPECT_TRUE(resolve(full_scene(), o.path)) << o.name << ": " << o.path;
}

TEST(SceneKeys, EveryLoaderObjectIsProbed) {
  // Each `only({...})` list of the loader is reached by some object of `objects()`: an
  // object added to the loader without a row in the mapping fails here.
  std::set<Keys> probed;
  const json j = full_scene();
  for (const SceneObject& o : objects()) {
    std::string error;
    probed.insert(loader_keys(j, resolve(j, o.path).value_or(""), &error));
  }
  const std::vector<Keys> lists = source_only_lists();
  EXPECT_GE(lists.size(), 25u) << "src/sim/scene: fewer only({...}) calls than expected; is the parse right?";
  for (const Keys& list : lists)
    EXPECT_TRUE(probed.count(list))
        << "src/sim/scene reads an object with the keys {" << join(list)
        << "} that no entry of test_scene_keys.cpp's objects() reaches: add the object and its docs table";
}

TEST(SceneKeys, TheRegistryEffectsAreEachProbed) {
  std::set<std::string> names;
  for (const SceneObject& o : objects()) names.insert(o.name);
  for (const auto& r : pce::sim::effect_registry())
    EXPECT_TRUE(names.count(r.name)) << "effect \"" << r.name << "\" has no entry in objects()";
}

TEST(SceneKeys, TheDocsListTheRegistrysEffectsInItsOrder) {
  // §2.5's list of effect names and §6.3's example of an unknown effect's error, against the
  // registry the loader looks names up in (white space collapsed: the docs wrap lines).
  std::string doc;
  for (const char c : docs())
    if (!(c == ' ' || c == '\n') || doc.empty() || doc.back() != ' ') doc += c == '\n' ? ' ' : c;
  std::string prose, message;
  for (const auto& r : pce::sim::effect_registry()) {
    prose += (prose.empty() ? "`" : ", `") + std::string(r.name) + "`";
    message += (message.empty() ? "" : ", ") + std::string(r.name);
  }
  EXPECT_NE(doc.find("The names, in the registry's order (`scene/registry.cpp`): " + prose + "."), std::string::npos)
      << "docs/simulation.md §2.5 should list the effects as the registry does: " << prose;
  EXPECT_NE(doc.find("unknown effect \"stretchin\" (expected one of: " + message + ")"), std::string::npos)
      << "docs/simulation.md §6.3's unknown-effect example should list the registry's effects: " << message;
}

TEST(SceneKeys, DocsTablesListExactlyTheKeysTheLoaderAccepts) {
  for (const SceneObject& o : objects()) {
    SCOPED_TRACE(o.name);
    const json j = full_scene();
    const std::string pointer = resolve(j, o.path).value_or("");
    std::string error;
    const Keys loader = loader_keys(j, pointer, &error);
    ASSERT_EQ(error, "") << o.name;
    std::string doc_error;
    const Keys documented = doc_keys(o.doc, &doc_error);
    EXPECT_EQ(doc_error, "") << o.name;
    const std::string where = std::string("docs/simulation.md \"") + o.doc.section + "\"" +
                              (*o.doc.anchor ? std::string(", the table after \"") + o.doc.anchor + "\"" : "") +
                              (o.doc.group ? std::string(", rows of ") + o.doc.group : "") +
                              (o.doc.inline_row ? std::string(", the row `") + o.doc.inline_row + "`" : "") +
                              (o.doc.shape ? std::string(", rows for shape ") + o.doc.shape : "");
    for (const std::string& k : loader)
      EXPECT_TRUE(documented.count(k)) << "the loader accepts `" << k << "` in the " << o.name << " ("
                                       << loader_path(pointer) << "), but " << where
                                       << " does not document it (documented: " << join(documented) << ")";
    for (const std::string& k : documented)
      EXPECT_TRUE(loader.count(k)) << where << " documents `" << k << "`, but the loader refuses it in the " << o.name
                                   << " (" << loader_path(pointer) << "; it accepts: " << join(loader) << ")";
  }
}

}  // namespace

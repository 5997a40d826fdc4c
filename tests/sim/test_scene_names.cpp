// SPDX-License-Identifier: MIT
// The name tables of the scene format's choices (scene/scene_names.hpp and the tables next to
// the public enumerations): every enumerator has one name, names are unique and parse back to
// their enumerator, the older `to_string` functions agree with the tables, the loader's error
// lists a table's names, and docs/simulation.md lists every name where it documents the key.
#include "scene/scene_names.hpp"

#include <pce/energy/projection.hpp>
#include <pce/sim/broad_phase.hpp>
#include <pce/sim/effects.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/obstacle.hpp>
#include <pce/sim/scene.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace {

using namespace pce::sim;

/// Every enumerator of E's table names itself: unique, non-empty names that parse back.
template <class E> void expect_round_trip() {
  std::set<std::string> names;
  std::set<int> values;
  for (const auto& [value, name] : pce::names_of<E>()) {
    EXPECT_FALSE(name.empty());
    EXPECT_TRUE(names.insert(std::string(name)).second) << name << " twice";
    EXPECT_TRUE(values.insert(static_cast<int>(value)).second) << name << ": enumerator listed twice";
    EXPECT_EQ(pce::name_of(value), name);
    EXPECT_EQ(pce::parse<E>(name), value) << name;
    EXPECT_EQ(name.data()[name.size()], '\0') << name;  // a C string too
  }
  EXPECT_FALSE(pce::parse<E>("no_such_name").has_value());
  EXPECT_FALSE(pce::parse<E>("").has_value());
}

TEST(SceneNames, EveryTableRoundTrips) {
  expect_round_trip<pce::Projection>();
  expect_round_trip<pce::VolumeProjection>();
  expect_round_trip<ContactPenalty::Kind>();
  expect_round_trip<ShapeKind>();
  expect_round_trip<BroadPhaseKind>();
  expect_round_trip<LinearSolver>();
  expect_round_trip<StopReason>();
  expect_round_trip<GeneratorKind>();
  expect_round_trip<SolverMode>();
  expect_round_trip<LengthKind>();
  expect_round_trip<StretchingModel>();
  expect_round_trip<VolumeModel>();
}

TEST(SceneNames, TablesListEveryEnumerator) {
  // The enumerations are dense from 0: a table as long as the enumeration lists each once
  // (EveryTableRoundTrips checks there are no repeats).
  EXPECT_EQ(pce::kProjectionNames.size(), static_cast<std::size_t>(pce::Projection::exact) + 1);
  EXPECT_EQ(pce::kVolumeProjectionNames.size(), static_cast<std::size_t>(pce::VolumeProjection::numerical) + 1);
  EXPECT_EQ(kPenaltyNames.size(), static_cast<std::size_t>(ContactPenalty::Kind::log_barrier) + 1);
  EXPECT_EQ(kShapeNames.size(), static_cast<std::size_t>(ShapeKind::mesh) + 1);
  EXPECT_EQ(kBroadPhaseNames.size(), static_cast<std::size_t>(BroadPhaseKind::brute) + 1);
  EXPECT_EQ(kLinearSolverNames.size(), static_cast<std::size_t>(LinearSolver::amg) + 1);
  EXPECT_EQ(kStopReasonNames.size(), static_cast<std::size_t>(StopReason::sweeps) + 1);
  EXPECT_EQ(kGeneratorNames.size(), static_cast<std::size_t>(GeneratorKind::tet_ball) + 1);
}

TEST(SceneNames, ToStringAgreesWithTheTables) {
  for (const auto& [p, name] : pce::kProjectionNames) EXPECT_EQ(pce::to_string(p), name);
  for (const auto& [b, name] : kBroadPhaseNames) {
    EXPECT_EQ(to_string(b), name);
    EXPECT_EQ(broad_phase_kind(std::string(name)), b);
  }
  for (const auto& [s, name] : kStopReasonNames) EXPECT_EQ(to_string(s), name);
  EXPECT_STREQ(pce::to_string(static_cast<pce::Projection>(99)), "unknown");
}

TEST(SceneNames, QuotedNamesListTheTableInOrder) {
  EXPECT_EQ(pce::quoted_names<LinearSolver>(), R"("direct", "factor_reuse", "ldlt", "cg", "pcg", "amg")");
  EXPECT_EQ(pce::quoted_names(kContactHessians), R"("analytic", "exact", "numerical", "gauss_newton", "abs")");
  for (const pce::Projection p : kContactHessians) EXPECT_NE(p, pce::Projection::none);
}

/// The message of loading `text`, or "" when it loads.
std::string load_error(const std::string& text) {
  try {
    load_scene_text(text, "scene.json", ".");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneNames, TheLoaderListsATablesNames) {
  const std::string mesh = R"("meshes": [{"name": "a", "generator": {"type": "grid", "width": 1, "height": 1,
                              "nx": 2, "ny": 2}}])";
  const std::string effects = R"("effects": [{"type": "gravity"}])";
  EXPECT_NE(load_error(R"({"dt": 0.01, "frames": 1, "solver": {"broad_phase": "bvh"}, )" + mesh + ", " + effects + "}")
                .find(R"(solver.broad_phase: expected one of "fcl", "bullet", "brute", got "bvh")"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"dt": 0.01, "frames": 1, "solver": {"mode": "fast"}, )" + mesh + ", " + effects + "}")
                .find(R"(solver.mode: expected one of "newton", "single_solve", "block_descent", got "fast")"),
            std::string::npos);
  EXPECT_NE(
      load_error(R"({"dt": 0.01, "frames": 1, "meshes": [{"name": "a", "generator": {"type": "cube"}}], )" + effects +
                 "}")
          .find(R"(meshes[0].generator.type: expected one of "grid", "strands", "tet_box", "tet_ball", got "cube")"),
      std::string::npos);
  EXPECT_NE(load_error(R"({"dt": 0.01, "frames": 1, )" + mesh + R"(, "obstacles": [{"name": "b", "shape": "cone"}], )" +
                       effects + "}")
                .find(R"(obstacles[0].shape: expected one of "sphere", "box", "capsule", "mesh", got "cone")"),
            std::string::npos);
  EXPECT_NE(
      load_error(R"({"dt": 0.01, "frames": 1, )" + mesh +
                 R"(, "effects": [{"type": "self_vertex_face", "hessian": "none",
                           "penalty": {"type": "quadratic", "stiffness": 1, "distance": 0.01}}]})")
          .find(
              R"(effects[0].hessian: expected one of "analytic", "exact", "numerical", "gauss_newton", "abs", got "none")"),
      std::string::npos);
  EXPECT_NE(load_error(R"({"dt": 0.01, "frames": 1, )" + mesh +
                       R"(, "effects": [{"type": "self_vertex_face",
                           "penalty": {"type": "barrier", "stiffness": 1, "distance": 0.01}}]})")
                .find(R"(effects[0].penalty.type: expected one of "quadratic", "cubic", "log_barrier", got "barrier")"),
            std::string::npos);
}

/// docs/simulation.md from `begin` (a heading) to `end` (the next heading to stop at).
std::string doc_section(const std::string& begin, const std::string& end) {
  std::ifstream in(std::string(PCE_SOURCE_DIR) + "/docs/simulation.md");
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  const std::size_t b = doc.find(begin), e = doc.find(end, b);
  if (b == std::string::npos || e == std::string::npos) return "";
  return doc.substr(b, e - b);
}

/// The names of `values` as the scene format's tables write a field's choices:
/// `"a"`, `"b"` (each quoted and in backticks, in the table's order).
template <class Values> std::string doc_choices(const Values& values) {
  std::string list;
  for (const auto v : values) list += (list.empty() ? "`\"" : ", `\"") + std::string(pce::name_of(v)) + "\"`";
  return list;
}

TEST(SceneNames, TheSceneFormatDocumentsEveryName) {
  const std::string format = doc_section("## 2. The scene format", "## 3. The effects");
  ASSERT_FALSE(format.empty()) << "docs/simulation.md section 2";
  // The row of each key lists exactly the table's names, in its order.
  for (const std::string& row : {
           "| `mode` | " + doc_choices(pce::enumerators<SolverMode>()) + " |",
           "| `linear_solver` | " + doc_choices(pce::enumerators<LinearSolver>()) + " |",
           "| `broad_phase` | " + doc_choices(pce::enumerators<BroadPhaseKind>()) + " |",
           "| `shape` | " + doc_choices(pce::enumerators<ShapeKind>()) + " |",
           "| `length` | " + doc_choices(pce::enumerators<LengthKind>()) + " |",
           "| `hessian` | " + doc_choices(kContactHessians) + " |",
           "| `hessian` | " + doc_choices(kVolumeHessians) + " |",
           "| `type` | " + doc_choices(pce::enumerators<ContactPenalty::Kind>()) + " |",
           "| `model` | " + doc_choices(pce::enumerators<StretchingModel>()) + " |",
           "| `model` | " + doc_choices(pce::enumerators<VolumeModel>()) + " |",
       })
    EXPECT_NE(format.find(row), std::string::npos) << "docs/simulation.md section 2 has no row " << row;
  // The generators: one row each in the generator table.
  for (const auto& [kind, name] : kGeneratorNames)
    EXPECT_NE(format.find("| `" + std::string(name) + "` |"), std::string::npos) << name;

  const std::string stats = doc_section("### 6.1 ", "### 6.2 ");
  ASSERT_FALSE(stats.empty()) << "docs/simulation.md section 6.1";
  for (const auto& [reason, name] : kStopReasonNames)
    EXPECT_NE(stats.find("`\"" + std::string(name) + "\"`"), std::string::npos) << name;
}

}  // namespace

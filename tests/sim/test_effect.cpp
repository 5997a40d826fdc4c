// SPDX-License-Identifier: MIT
// The effect interface (pce/sim/effect.hpp, pce/sim/contact_effect.hpp): every effect's
// per-vertex local terms are the columns of its gradient and the diagonal blocks of its
// Hessian (also for vertices sharing elements or listed twice, and whatever the thread
// count), the gradient columns are the energy's derivatives, and only contact effects are
// ContactEffects.
#include <pce/sim/contact_effect.hpp>
#include <pce/sim/effects.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/scene.hpp>

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

using namespace pce::sim;

namespace {

std::unique_ptr<Scene> shipped(const std::string& name) {
  return load_scene(std::filesystem::path(PCE_SOURCE_DIR) / "examples" / "scenes" / (name + ".json"));
}

/// A shipped scene after a few frames (contacts active, pins and damping at work) and a
/// state off its last solve (a Newton iterate, not a minimum): x plus a small twist.
Eigen::Matrix3Xd stepped_state(Simulation& sim) {
  for (int f = 0; f < 4; ++f) sim.step();
  Eigen::Matrix3Xd x = sim.x;
  for (Eigen::Index i = 0; i < x.cols(); ++i) x(2, i) += 1e-4 * std::sin(0.37 * static_cast<double>(i));
  return x;
}

/// The whole gradient and Hessian of `e` at x, as the solver assembles them.
void evaluate_whole(Effect& e, const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& g, BlockHessian& H) {
  if (ContactEffect* c = as_contact(&e)) c->begin_iteration(x);
  Pattern pattern;
  e.declare(pattern);
  H.set_pattern(static_cast<int>(x.cols()), pattern);
  H.set_zero();
  g = Eigen::Matrix3Xd::Zero(3, x.cols());
  e.evaluate(x, &g, &H);
}

/// `e`'s local terms of `vertices` at x.
LocalTerms local_terms(Effect& e, const Eigen::Matrix3Xd& x, const std::vector<int>& vertices) {
  LocalTerms local;
  local.reset(vertices.size());
  e.evaluate_local(x, vertices, local);
  return local;
}

/// evaluate_local of `vertices` against the whole evaluation: entry j is the gradient
/// column and the diagonal Hessian block of vertex vertices[j], to 1e-12 relative.
void expect_local_is_whole(Effect& e, const Eigen::Matrix3Xd& x, const std::vector<int>& vertices) {
  Eigen::Matrix3Xd g;
  BlockHessian H;
  evaluate_whole(e, x, g, H);
  const LocalTerms local = local_terms(e, x, vertices);
  const double g_scale = std::max(g.cwiseAbs().maxCoeff(), 1e-300);
  for (std::size_t j = 0; j < vertices.size(); ++j) {
    const int i = vertices[j];
    ASSERT_LE((local.gradient.col(static_cast<Eigen::Index>(j)) - g.col(i)).cwiseAbs().maxCoeff(), 1e-12 * g_scale)
        << "vertex " << i << " (entry " << j << ")";
    const Eigen::Matrix3d B = H.diagonal_block(i);
    ASSERT_LE((local.hessian[j] - B).cwiseAbs().maxCoeff(), 1e-12 * std::max(B.cwiseAbs().maxCoeff(), 1.0))
        << "vertex " << i << " (entry " << j << ")";
  }
}

/// The vertices of the first `count` triangles, segments and tetrahedra of the model, in
/// element order: neighbouring elements share vertices, so the list holds vertices that
/// share elements and vertices listed more than once.
std::vector<int> element_vertices(const Model& model, Eigen::Index count) {
  std::vector<int> vertices;
  for (Eigen::Index k = 0; k < std::min(count, model.triangles.cols()); ++k)
    for (int a = 0; a < 3; ++a) vertices.push_back(model.triangles(a, k));
  for (Eigen::Index k = 0; k < std::min(count, model.segments.cols()); ++k)
    for (int a = 0; a < 2; ++a) vertices.push_back(model.segments(a, k));
  for (Eigen::Index k = 0; k < std::min(count, model.tetrahedra.cols()); ++k)
    for (int a = 0; a < 4; ++a) vertices.push_back(model.tetrahedra(a, k));
  return vertices;
}

}  // namespace

TEST(Effect, LocalTermsAreTheGradientColumnsAndDiagonalHessianBlocks) {
  // Shipped scenes after a few frames: for every effect and every third vertex,
  // evaluate_local against the whole evaluation.
  int checked = 0;
  for (const char* name : {"crumple", "ball_drop", "strands", "pile", "twist", "drape"}) {
    SCOPED_TRACE(name);
    auto s = shipped(name);
    Simulation& sim = s->simulation;
    const Eigen::Matrix3Xd x = stepped_state(sim);
    std::vector<int> vertices;
    for (int i = 0; i < sim.model.vertex_count(); i += 3) vertices.push_back(i);
    for (auto& e : sim.effects) {
      SCOPED_TRACE(e->name());
      expect_local_is_whole(*e, x, vertices);
      ++checked;
    }
  }
  EXPECT_GE(checked, 20);
}

TEST(Effect, LocalTermsOfVerticesSharingElementsAndListedTwice) {
  // Lists of the vertices of neighbouring elements (each vertex of an element together with
  // its neighbours in it, interior vertices several times), long and short: every entry
  // gets its vertex's full terms.
  int checked = 0;
  for (const char* name : {"crumple", "ball_drop", "strands", "pile"}) {
    SCOPED_TRACE(name);
    auto s = shipped(name);
    Simulation& sim = s->simulation;
    const Eigen::Matrix3Xd x = stepped_state(sim);
    for (const Eigen::Index count : {Eigen::Index{60}, Eigen::Index{4}}) {
      SCOPED_TRACE(count);
      std::vector<int> vertices = element_vertices(sim.model, count);
      vertices.push_back(vertices.front());  // listed at both ends, whatever the model
      ASSERT_LT(std::set<int>(vertices.begin(), vertices.end()).size(), vertices.size());
      for (auto& e : sim.effects) {
        SCOPED_TRACE(e->name());
        expect_local_is_whole(*e, x, vertices);
        ++checked;
      }
    }
  }
  EXPECT_GE(checked, 30);
}

TEST(Effect, StretchingsLocalTermsInEveryRegimeOfItsSingularValues) {
  // A 5 × 5 sheet mapped by x = M X (each triangle's F is M in its rest frame, turned), with
  // a ripple: both singular values above 1, one, neither, near 1, nearly collapsed (the
  // closed form's fallback to the frame) and mirrored. Every vertex's local terms against the
  // whole evaluation, whose Hessian comes from the frame and the modes (arap_triangle).
  Model model = build_model({{"sheet", grid(0.4, 0.4, 4, 4)}});
  auto e = make_stretching(model, 50);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  std::vector<int> vertices(static_cast<std::size_t>(model.vertex_count()));
  for (std::size_t i = 0; i < vertices.size(); ++i) vertices[i] = static_cast<int>(i);
  const std::vector<std::pair<std::string, Eigen::Vector3d>> stretches = {
      {"both above 1", {1.4, 1.2, 1}},     {"one above 1", {1.3, 0.8, 1}}, {"neither", {0.7, 0.9, 1}},
      {"near 1", {1 + 1e-9, 1 - 1e-9, 1}}, {"collapsed", {1.1, 3e-3, 1}},  {"mirrored", {-1.2, 0.9, 1}}};
  for (const auto& [what, stretch] : stretches) {
    SCOPED_TRACE(what);
    Eigen::Matrix3Xd x = turn * stretch.asDiagonal() * model.rest;
    for (Eigen::Index i = 0; i < x.cols(); ++i) x(2, i) += 2e-3 * std::sin(1.3 * static_cast<double>(i));
    expect_local_is_whole(*e, x, vertices);
  }
}

TEST(Effect, LocalGradientIsTheEnergysDerivative) {
  // Central differences of each non-contact effect's energy against its local gradient
  // column, for 20 vertices spread over the model. Step h = 1e-7 ℓ, ℓ the mean rest edge
  // length (the elements' curvature scale: the truncation error O(h²) stays below 1e-6 of
  // the column). The tolerance is 1e-6 of the column plus the rounding error of the whole
  // energy's difference, 1000 ε|E|/h (up to 50 ε|E|/h seen: the volumes' terms cancel).
  int checked = 0;
  for (const char* name : {"crumple", "ball_drop", "strands", "pile"}) {
    SCOPED_TRACE(name);
    auto s = shipped(name);
    Simulation& sim = s->simulation;
    Eigen::Matrix3Xd x = stepped_state(sim);
    const Eigen::Matrix2Xi& edges = sim.model.edges;
    double length = 0;
    for (Eigen::Index k = 0; k < edges.cols(); ++k)
      length += (sim.model.rest.col(edges(1, k)) - sim.model.rest.col(edges(0, k))).norm();
    const double h = 1e-7 * length / static_cast<double>(edges.cols());
    const int n = sim.model.vertex_count();
    std::vector<int> vertices;
    for (int k = 0; k < 20; ++k) vertices.push_back(static_cast<int>((static_cast<long>(k) * n) / 20 + k % 3));
    for (auto& e : sim.effects) {
      if (as_contact(e.get())) continue;
      SCOPED_TRACE(e->name());
      const LocalTerms local = local_terms(*e, x, vertices);
      const double energy = std::abs(e->evaluate(x, nullptr, nullptr));
      ASSERT_TRUE(std::isfinite(energy));
      const double rounding = 1e3 * std::numeric_limits<double>::epsilon() * energy / h;
      for (std::size_t j = 0; j < vertices.size(); ++j) {
        const int i = vertices[j];
        const Eigen::Vector3d g = local.gradient.col(static_cast<Eigen::Index>(j));
        for (int d = 0; d < 3; ++d) {
          const double xi = x(d, i);
          x(d, i) = xi + h;
          const double plus = e->evaluate(x, nullptr, nullptr);
          x(d, i) = xi - h;
          const double minus = e->evaluate(x, nullptr, nullptr);
          x(d, i) = xi;
          const double fd = (plus - minus) / (2 * h);
          EXPECT_NEAR(fd, g[d], 1e-6 * g.cwiseAbs().maxCoeff() + rounding) << "vertex " << i << ", coordinate " << d;
        }
      }
      ++checked;
    }
  }
  EXPECT_GE(checked, 12);
}

TEST(Effect, LocalTermsDoNotDependOnTheThreadCount) {
  // Every vertex of the scenes with one and with two threads: the same bits.
  const int threads = omp_get_max_threads();
  for (const char* name : {"crumple", "ball_drop", "strands", "pile"}) {
    SCOPED_TRACE(name);
    auto s = shipped(name);
    Simulation& sim = s->simulation;
    const Eigen::Matrix3Xd x = stepped_state(sim);
    std::vector<int> vertices(static_cast<std::size_t>(sim.model.vertex_count()));
    for (std::size_t i = 0; i < vertices.size(); ++i) vertices[i] = static_cast<int>(i);
    for (auto& e : sim.effects) {
      SCOPED_TRACE(e->name());
      omp_set_num_threads(1);
      const LocalTerms one = local_terms(*e, x, vertices);
      omp_set_num_threads(2);
      const LocalTerms two = local_terms(*e, x, vertices);
      EXPECT_EQ(std::memcmp(one.gradient.data(), two.gradient.data(), sizeof(double) * one.gradient.size()), 0);
      for (std::size_t j = 0; j < vertices.size(); ++j)
        ASSERT_EQ(std::memcmp(one.hessian[j].data(), two.hessian[j].data(), sizeof(double) * 9), 0) << "vertex " << j;
    }
  }
  omp_set_num_threads(threads);
}

TEST(Effect, OnlyContactEffectsAreContactEffects) {
  for (const char* name : {"ball_drop", "crumple", "strands"}) {
    auto s = shipped(name);
    for (auto& e : s->simulation.effects) {
      const std::string n = e->name();
      const bool contact = n == "self_vertex_face" || n == "self_edge_edge" || n == "obstacle_contact";
      EXPECT_EQ(as_contact(e.get()) != nullptr, contact) << name << ": " << n;
    }
  }
}

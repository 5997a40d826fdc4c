// SPDX-License-Identifier: MIT
// The effect interface (pce/sim/effect.hpp, pce/sim/contact_effect.hpp): every effect's
// per-vertex local terms are the columns of its gradient and the diagonal blocks of its
// Hessian, and only contact effects are ContactEffects.
#include <pce/sim/contact_effect.hpp>
#include <pce/sim/scene.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

using namespace pce::sim;

namespace {

std::unique_ptr<Scene> shipped(const std::string& name) {
  return load_scene(std::filesystem::path(PCE_SOURCE_DIR) / "examples" / "scenes" / (name + ".json"));
}

/// The whole gradient and Hessian of `e` at x, as the solver assembles them.
void evaluate_whole(Effect& e, const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& g, BlockHessian& H) {
  if (ContactEffect* c = as_contact(&e)) c->update_pattern(x);
  Pattern pattern;
  e.declare(pattern);
  H.set_pattern(static_cast<int>(x.cols()), pattern);
  H.set_zero();
  g = Eigen::Matrix3Xd::Zero(3, x.cols());
  e.evaluate(x, &g, &H);
}

}  // namespace

TEST(Effect, LocalTermsAreTheGradientColumnsAndDiagonalHessianBlocks) {
  // Shipped scenes after a few frames (contacts active, pins and damping at work): for every
  // effect and every third vertex, evaluate_local against the whole evaluation.
  int checked = 0;
  for (const char* name : {"crumple", "ball_drop", "strands", "pile", "twist", "drape"}) {
    SCOPED_TRACE(name);
    auto s = shipped(name);
    Simulation& sim = s->simulation;
    for (int f = 0; f < 4; ++f) sim.step();
    // A state off the last solve (a Newton iterate, not a minimum): x plus a small twist.
    Eigen::Matrix3Xd x = sim.x;
    for (Eigen::Index i = 0; i < x.cols(); ++i) x(2, i) += 1e-4 * std::sin(0.37 * static_cast<double>(i));
    std::vector<int> vertices;
    for (int i = 0; i < sim.model.vertex_count(); i += 3) vertices.push_back(i);
    for (auto& e : sim.effects) {
      SCOPED_TRACE(e->name());
      Eigen::Matrix3Xd g;
      BlockHessian H;
      evaluate_whole(*e, x, g, H);
      LocalTerms local;
      local.reset(vertices.size());
      e->evaluate_local(x, vertices, local);
      const double g_scale = std::max(g.cwiseAbs().maxCoeff(), 1e-300);
      for (std::size_t j = 0; j < vertices.size(); ++j) {
        const int i = vertices[j];
        ASSERT_LE((local.gradient.col(static_cast<Eigen::Index>(j)) - g.col(i)).cwiseAbs().maxCoeff(), 1e-12 * g_scale)
            << "vertex " << i;
        const Eigen::Matrix3d B = H.diagonal_block(i);
        ASSERT_LE((local.hessian[j] - B).cwiseAbs().maxCoeff(), 1e-12 * std::max(B.cwiseAbs().maxCoeff(), 1.0))
            << "vertex " << i;
      }
      ++checked;
    }
  }
  EXPECT_GE(checked, 20);
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

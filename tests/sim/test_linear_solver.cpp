// SPDX-License-Identifier: MIT
// The factor_reuse linear solver (CG preconditioned by a kept Cholesky factor): it reaches
// the state the reference `direct` solver reaches, in contact; it factorises less often than
// Newton iterates; a CG that never converges falls back to direct's solve exactly; a loose
// CG tolerance still converges; and the scene key accepts it (the default stays `direct`)
// and names a wrong value's file and JSON path.
#include "drop_scene.hpp"

#include <pce/sim/input_error.hpp>
#include <pce/sim/scene.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

using namespace pce::sim;
using nlohmann::json;
using pce::sim::fixtures::drop;

namespace {

std::unique_ptr<Scene> load(const json& j) { return load_scene_text(j.dump(), "scene.json", PCE_TEST_TMP); }

/// What a run of `steps` steps did, summed over its steps.
struct Totals {
  Eigen::Matrix3Xd x;
  int newton_iterations = 0;
  double factorizations = 0, cg_iterations = 0, contacts = 0;
  bool hit_cap = false;
};

Totals run(Simulation& sim, int steps) {
  Totals r;
  for (int f = 0; f < steps; ++f) {
    const FrameStats st = sim.step();
    r.newton_iterations += st.newton_iterations;
    r.factorizations += st.counters.at("factorizations");
    r.cg_iterations += st.counters.at("cg_iterations");
    r.contacts += st.counters.at("vertex_face_contacts") + st.counters.at("edge_edge_contacts") +
                  st.counters.at("obstacle_contacts");
    r.hit_cap = r.hit_cap || st.hit_iteration_cap;
  }
  r.x = sim.x;
  return r;
}

}  // namespace

TEST(LinearSolver, FactorReuseReachesTheDirectStateInContact) {
  // Newton stops when its last direction moves no vertex by more than tolerance·h·ℓ
  // (1e-6 · 0.02 · ~0.7 ≈ 1.4e-8 here) and the error left after that step is smaller
  // still (quadratic convergence for direct; for factor_reuse, linear at a rate about the
  // CG tolerance η = 1e-2), so each step of both runs ends within about 1.4e-8 of the exact
  // minimiser whatever the directions were. 1e-7 allows the 12 steps to carry those
  // differences a little through the contact forces (measured: a few 1e-9).
  auto direct = load(drop("direct", 1e-6));
  auto reuse = load(drop("factor_reuse", 1e-6));
  const Totals d = run(direct->simulation, 12), r = run(reuse->simulation, 12);
  EXPECT_GT(d.contacts, 50);  // the comparison is made in contact
  EXPECT_FALSE(d.hit_cap);
  EXPECT_FALSE(r.hit_cap);
  EXPECT_LT((r.x - d.x).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_GT((r.x - d.x).cwiseAbs().maxCoeff(), 0.0);  // inexact directions: not the same run
}

TEST(LinearSolver, FactorReuseFactorisesLessOftenThanNewtonIterates) {
  auto reuse = load(drop("factor_reuse", 1e-2));
  const Totals r = run(reuse->simulation, 6);
  EXPECT_LT(r.factorizations, r.newton_iterations);
  EXPECT_GE(r.factorizations, 1);
  EXPECT_GT(r.cg_iterations, 0);
  // direct: one factorisation per Newton iteration and no CG
  auto direct = load(drop("direct", 1e-2));
  const Totals d = run(direct->simulation, 6);
  EXPECT_EQ(d.factorizations, d.newton_iterations);
  EXPECT_EQ(d.cg_iterations, 0);
}

TEST(LinearSolver, CgThatNeverConvergesFallsBackToDirectsSolveExactly) {
  // One CG iteration can never reach a relative residual of 1e-14: every direction is the
  // refactored one (after a failed CG, or without trying CG during the back-off), so the
  // run is direct's bit for bit.
  auto direct = load(drop("direct", 1e-3));
  auto reuse = load(drop("factor_reuse", 1e-3));
  reuse->simulation.solver.reuse_tolerance = 1e-14;
  reuse->simulation.solver.reuse_max_cg_iterations = 1;
  double cg_iterations = 0;
  for (int f = 1; f <= 8; ++f) {
    const FrameStats sd = direct->simulation.step(), sr = reuse->simulation.step();
    ASSERT_EQ(direct->simulation.x, reuse->simulation.x) << "frame " << f;
    EXPECT_EQ(sr.newton_iterations, sd.newton_iterations);
    EXPECT_EQ(sr.counters.at("factorizations"), sr.newton_iterations);
    cg_iterations += sr.counters.at("cg_iterations");
  }
  EXPECT_GT(cg_iterations, 0);  // CG was tried (between back-offs)
}

TEST(LinearSolver, LooseCgToleranceStillConverges) {
  // η = 0.5: the first CG iterate or two; the directions are poor but still descent
  // directions (CG from zero lowers the quadratic model at every iterate), so Newton with
  // its line search gets to the same state, in more iterations. Its convergence is linear
  // at a rate up to η, so what is left after the last step is up to about that step
  // (< 1.4e-8, as above) again: 1e-6 is a margin, measured ~2e-8.
  auto direct = load(drop("direct", 1e-6));
  auto reuse = load(drop("factor_reuse", 1e-6));
  reuse->simulation.solver.reuse_tolerance = 0.5;
  reuse->simulation.solver.max_iterations = 500;
  const Totals d = run(direct->simulation, 6), r = run(reuse->simulation, 6);
  EXPECT_FALSE(r.hit_cap);
  EXPECT_GT(r.newton_iterations, d.newton_iterations);
  EXPECT_LT((r.x - d.x).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(LinearSolver, SceneKeyAcceptsFactorReuseDefaultsToDirectAndNamesAWrongValue) {
  json j = drop("factor_reuse", 1e-2);
  EXPECT_EQ(load(j)->simulation.solver.linear, LinearSolver::factor_reuse);
  j["solver"].erase("linear_solver");
  EXPECT_EQ(load(j)->simulation.solver.linear, LinearSolver::direct);
  j.erase("solver");
  EXPECT_EQ(load(j)->simulation.solver.linear, LinearSolver::direct);
  EXPECT_EQ(SolverSettings{}.linear, LinearSolver::direct);
  j = drop("direct", 1e-2);
  EXPECT_EQ(load(j)->simulation.solver.linear, LinearSolver::direct);
  j["solver"]["linear_solver"] = "factor-reuse";
  try {
    load(j);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "scene.json");
    EXPECT_EQ(e.where(), "solver.linear_solver");
    EXPECT_NE(std::string(e.what()).find(
                  R"(expected one of "direct", "factor_reuse", "ldlt", "cg", "pcg", "amg", got "factor-reuse")"),
              std::string::npos)
        << e.what();
  }
}

TEST(LinearSolver, ReuseSettingsAreChecked) {
  auto s = load(drop("factor_reuse", 1e-2));
  s->simulation.solver.reuse_tolerance = 0;
  EXPECT_THROW(s->simulation.step(), ArgumentError);
  s->simulation.solver.reuse_tolerance = 1e-4;
  s->simulation.solver.reuse_max_cg_iterations = -1;
  EXPECT_THROW(s->simulation.step(), ArgumentError);
  EXPECT_EQ(s->simulation.frame, 0);
}

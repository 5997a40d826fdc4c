// SPDX-License-Identifier: MIT
// The solver and the "only what a scene declares" claims: backward Euler reproduced
// exactly for a free fall, the linear solvers agree, single-solve takes one iteration, and a
// scene without contact (or without bending) builds no broad phase (no bending data).
#include <pce/sim/instrumentation.hpp>
#include <pce/sim/scene.hpp>

#include <gtest/gtest.h>
#include <algorithm>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

using namespace pce::sim;
using nlohmann::json;

namespace {

json cloth(const json& effects) {
  json j = json::parse(R"({
    "dt": 0.02, "frames": 3,
    "meshes": [{"name": "cloth", "generator": {"type": "grid", "width": 0.5, "height": 0.5, "nx": 6, "ny": 6}}]
  })");
  j["effects"] = effects;
  return j;
}

std::unique_ptr<Scene> load(const json& j) { return load_scene_text(j.dump(), "sim.json", PCE_TEST_TMP); }

}  // namespace

TEST(Simulation, FreeFallIsBackwardEulerExactly) {
  auto s = load(cloth(json::parse(R"([{"type": "gravity", "acceleration": [0, 0, -9.81]}])")));
  Simulation& sim = s->simulation;
  const Eigen::Matrix3Xd x0 = sim.x;
  double v = 0, z = 0;
  for (int f = 1; f <= 3; ++f) {
    const FrameStats st = sim.step();
    v += -9.81 * 0.02;  // v₁ = v₀ + h g, x₁ = x₀ + h v₁
    z += 0.02 * v;
    EXPECT_LE(st.newton_iterations, 2);  // quadratic potential: one step, then the check
    EXPECT_NEAR((sim.x.row(2) - x0.row(2)).maxCoeff(), z, 1e-12);
    EXPECT_NEAR((sim.x.row(2) - x0.row(2)).minCoeff(), z, 1e-12);
    EXPECT_NEAR(sim.v.row(2).mean(), v, 1e-10);
  }
}

/// An energy term whose gradient is `m_i k` at every vertex but whose energy is 0: from a
/// cloth at rest without gravity (the inertia's minimum), Newton's direction is
/// Δx_i = −h² k and every trial along it raises the energy by ½ Σ m_i h² |k|², so the
/// Armijo test rejects it. The direction's residual is h|k|/ℓ, chosen by k.
class RejectedDirection final : public Effect {
 public:
  RejectedDirection(const Model& model, const Eigen::Vector3d& k)
      : Effect("rejected_direction"), mass_(model.mass), k_(k) {}
  void declare(Pattern&) const override {}
  double evaluate(const Eigen::Matrix3Xd&, Eigen::Matrix3Xd* gradient, BlockHessian*) override {
    if (gradient)
      for (Eigen::Index i = 0; i < gradient->cols(); ++i) gradient->col(i) += mass_[i] * k_;
    return 0;
  }

 private:
  Eigen::VectorXd mass_;
  Eigen::Vector3d k_;
};

TEST(Simulation, ARejectedTrialAtAConvergedDirectionIsNoLineSearchFailure) {
  // A direction below the tolerance whose trial fails Armijo (in a real scene: rounding, as
  // in a free fall's second Newton direction) has converged: no line-search failure. The same
  // rejection at a direction above the tolerance is one.
  for (const double ratio : {1e-3, 10.0}) {  // the direction's residual over the tolerance
    SCOPED_TRACE(ratio);
    auto s = load(cloth(json::parse(R"([{"type": "gravity", "acceleration": [0, 0, 0]}])")));
    Simulation& sim = s->simulation;
    const Eigen::Matrix3Xd& rest = sim.model.rest;
    const double scale = (rest.rowwise().maxCoeff() - rest.rowwise().minCoeff()).norm();
    const double residual = ratio * sim.solver.tolerance;
    sim.effects.push_back(
        std::make_unique<RejectedDirection>(sim.model, Eigen::Vector3d(residual * scale / sim.solver.dt, 0, 0)));
    const FrameStats st = sim.step();
    ASSERT_EQ(st.iterations.size(), 1u);
    EXPECT_EQ(st.iterations[0].alpha, 0.0) << "the trial was accepted: the case this test is about did not occur";
    EXPECT_NEAR(st.iterations[0].residual, residual, 1e-9 * residual);
    EXPECT_EQ(st.line_search_failures, ratio < 1 ? 0 : 1);
    EXPECT_EQ(st.stop, ratio < 1 ? StopReason::rounding : StopReason::line_search);
    EXPECT_EQ(sim.x, rest);  // nothing accepted: the cloth stays where it was
  }
}

TEST(Simulation, LinearSolversAgreeAndSingleSolveTakesOneIteration) {
  const json effects = json::parse(R"([{"type": "gravity"}, {"type": "stretching", "stiffness": 20},
      {"type": "bending", "stiffness": 1e-4}, {"type": "pins", "groups": [{"vertices": [0, 6]}]}])");
  Eigen::Matrix3Xd reference;
  for (const char* solver : {"direct", "ldlt", "cg"}) {
    SCOPED_TRACE(solver);
    json j = cloth(effects);
    j["solver"] = {{"linear_solver", solver}, {"tolerance", 1e-6}};
    auto s = load(j);
    for (int f = 0; f < 3; ++f) s->simulation.step();
    if (reference.size() == 0) reference = s->simulation.x;
    EXPECT_LT((s->simulation.x - reference).cwiseAbs().maxCoeff(), 1e-6);
  }
  json j = cloth(effects);
  j["solver"] = {{"mode", "single_solve"}};
  auto s = load(j);
  EXPECT_EQ(s->simulation.step().newton_iterations, 1);
}

TEST(Simulation, WithoutContactNoBroadPhaseIsBuiltOrQueried) {
  const long built = instrumentation().broad_phases_built;
  const long vf = instrumentation().vertex_face_pairs_evaluated, ee = instrumentation().edge_edge_pairs_evaluated;
  auto s = load(cloth(json::parse(R"([{"type": "gravity"}, {"type": "stretching", "stiffness": 20}])")));
  for (int f = 0; f < 3; ++f) {
    const FrameStats st = s->simulation.step();
    EXPECT_EQ(st.broad_phase_ms, 0.0);
    EXPECT_EQ(st.effect_ms.size(), 2u);
    EXPECT_FALSE(st.counters.has(Counter::broad_phase_queries));
  }
  EXPECT_EQ(instrumentation().broad_phases_built, built);
  EXPECT_EQ(instrumentation().vertex_face_pairs_evaluated, vf);
  EXPECT_EQ(instrumentation().edge_edge_pairs_evaluated, ee);
  // and with a contact effect the same counters move (so the check above can fail)
  json with = cloth(json::parse(R"([{"type": "gravity"}, {"type": "self_edge_edge",
      "penalty": {"type": "quadratic", "stiffness": 10, "distance": 0.01}}])"));
  auto c = load(with);
  const FrameStats first = c->simulation.step();
  EXPECT_EQ(instrumentation().broad_phases_built, built + 1);
  EXPECT_GT(first.counters.at(Counter::broad_phase_queries), 0);
  EXPECT_EQ(instrumentation().vertex_face_pairs_evaluated, vf);  // edge-edge only: no vertex-face pair
}

TEST(Simulation, WithoutBendingNoBendingDataIsAllocated) {
  const long hinges = instrumentation().bending_hinges_allocated;
  load(cloth(json::parse(R"([{"type": "gravity"}, {"type": "stretching", "stiffness": 20}])")))->simulation.step();
  EXPECT_EQ(instrumentation().bending_hinges_allocated, hinges);
  load(cloth(json::parse(R"([{"type": "gravity"}, {"type": "bending", "stiffness": 1e-4}])")));
  EXPECT_EQ(instrumentation().bending_hinges_allocated, hinges + 6 * 6 * 3 - 6 * 2);  // interior edges of a 6×6 grid
}

TEST(Simulation, NonFiniteStateIsAnErrorNamingTheFrameAndVertex) {
  auto s = load(cloth(json::parse(R"([{"type": "gravity"}])")));
  s->simulation.x(0, 3) = std::numeric_limits<double>::quiet_NaN();
  try {
    s->simulation.step();
    ADD_FAILURE() << "no error";
  } catch (const SimulationError& e) {
    EXPECT_EQ(e.frame(), 1);
    EXPECT_EQ(e.vertex(), 3);
    EXPECT_NE(std::string(e.what()).find("frame 1, at Newton iteration 1: the position of vertex 3"), std::string::npos)
        << e.what();
  }
}

namespace {
/// An energy that is fine until `bad_frame`, then gives a NaN gradient at `vertex`.
class BreaksAtFrame final : public Effect {
 public:
  BreaksAtFrame(int bad_frame, int vertex) : Effect("breaks_at_frame"), bad_frame_(bad_frame), vertex_(vertex) {}
  void begin_step(const StepContext& ctx) override { frame_ = ctx.frame; }
  void declare(Pattern& /*pattern*/) const override {}
  double evaluate(const Eigen::Matrix3Xd& /*x*/, Eigen::Matrix3Xd* gradient, BlockHessian* /*hessian*/) override {
    if (gradient && frame_ >= bad_frame_) (*gradient)(1, vertex_) += std::numeric_limits<double>::quiet_NaN();
    return 0.0;
  }

 private:
  int bad_frame_, vertex_, frame_ = 0;
};
}  // namespace

TEST(Simulation, NonFiniteGradientNamesTheFrameTheEffectAndTheVertexAndKeepsTheLastState) {
  auto s = load(cloth(json::parse(R"([{"type": "gravity"}, {"type": "stretching", "stiffness": 20}])")));
  Simulation& sim = s->simulation;
  sim.effects.push_back(std::make_unique<BreaksAtFrame>(3, 7));
  sim.step();
  sim.step();
  const Eigen::Matrix3Xd x = sim.x, v = sim.v;
  try {
    sim.step();
    ADD_FAILURE() << "no error";
  } catch (const SimulationError& e) {
    EXPECT_EQ(e.frame(), 3);
    EXPECT_EQ(e.effect(), "breaks_at_frame");
    EXPECT_EQ(e.vertex(), 7);
    const std::string what = e.what();
    EXPECT_NE(what.find("frame 3, at Newton iteration 1: effect \"breaks_at_frame\" gives a non-finite gradient at "
                        "vertex 7"),
              std::string::npos)
        << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  EXPECT_EQ(sim.frame, 2);  // the failed step changed nothing
  EXPECT_TRUE((sim.x.array() == x.array()).all());
  EXPECT_TRUE((sim.v.array() == v.array()).all());
}

TEST(Simulation, AFrameOfSubstepsIsThatManyStepsOfTheirSize) {
  // A frame of 4 substeps of dt/4 ends on the bits of 4 frames of dt/4 (dt/4 is exact, and
  // nothing here depends on the time), in Newton and in block descent; the frame's
  // statistics sum the steps' work and describe the last step's state.
  const json effects = json::parse(R"([{"type": "gravity"}, {"type": "stretching", "stiffness": 20},
      {"type": "bending", "stiffness": 1e-4}, {"type": "pins", "groups": [{"vertices": [0, 6]}]},
      {"type": "self_vertex_face", "penalty": {"type": "quadratic", "stiffness": 10, "distance": 0.01}}])");
  for (const char* mode : {"newton", "block_descent"}) {
    SCOPED_TRACE(mode);
    json whole = cloth(effects), parts = cloth(effects);
    whole["solver"] = {{"mode", mode}, {"substeps", 4}};
    parts["solver"] = {{"mode", mode}, {"substeps", 1}};
    parts["dt"] = 0.005;
    auto a = load(whole), b = load(parts);
    EXPECT_EQ(a->simulation.solver.substeps, 4);
    for (int f = 1; f <= 2; ++f) {
      const FrameStats sa = a->simulation.step();
      int iterations = 0, sweeps = 0;
      double queries = 0, residual = 0;
      FrameStats sb;
      for (int k = 0; k < 4; ++k) {
        sb = b->simulation.step();
        iterations += sb.newton_iterations;
        sweeps += sb.sweeps;
        queries += sb.counters.at(Counter::broad_phase_queries);
        residual = std::max(residual, sb.residual);
      }
      ASSERT_EQ(a->simulation.x, b->simulation.x) << "frame " << f;
      ASSERT_EQ(a->simulation.v, b->simulation.v) << "frame " << f;
      EXPECT_EQ(a->simulation.frame, f);
      EXPECT_DOUBLE_EQ(a->simulation.time, 0.02 * f);
      EXPECT_EQ(sa.frame, f);
      EXPECT_EQ(sa.substeps, 4);
      EXPECT_EQ(sa.newton_iterations, iterations);
      EXPECT_EQ(sa.sweeps, sweeps);
      EXPECT_EQ(sa.counters.at(Counter::broad_phase_queries), queries);  // work: summed
      EXPECT_EQ(sa.counters.at(Counter::vertex_face_candidates),
                sb.counters.at(Counter::vertex_face_candidates));  // state: the last
      EXPECT_EQ(sa.energy, sb.energy);
      EXPECT_EQ(sa.residual, residual);
      EXPECT_EQ(sa.iterations.size() + sa.sweep_records.size(),
                static_cast<std::size_t>(iterations) + static_cast<std::size_t>(sweeps));
      if (!sa.iterations.empty()) {
        EXPECT_EQ(sa.iterations.back().substep, 3);
      }
      if (!sa.sweep_records.empty()) {
        EXPECT_EQ(sa.sweep_records.back().substep, 3);
      }
    }
  }
}

namespace {
/// An energy that is fine for `good_steps` time steps, then gives a NaN gradient at vertex 3.
class BreaksAfterSteps final : public Effect {
 public:
  explicit BreaksAfterSteps(int good_steps) : Effect("breaks_after_steps"), good_(good_steps) {}
  void begin_step(const StepContext& /*ctx*/) override { ++steps_; }
  void declare(Pattern& /*pattern*/) const override {}
  double evaluate(const Eigen::Matrix3Xd& /*x*/, Eigen::Matrix3Xd* gradient, BlockHessian* /*hessian*/) override {
    if (gradient && steps_ > good_) (*gradient)(1, 3) += std::numeric_limits<double>::quiet_NaN();
    return 0.0;
  }

 private:
  int good_, steps_ = 0;
};
}  // namespace

TEST(Simulation, AFrameWhoseSubstepFailsLeavesTheFramesStart) {
  // 3 substeps a frame; the 5th step (frame 2's second) fails: frame, time, x and v are
  // frame 1's.
  json j = cloth(json::parse(R"([{"type": "gravity"}, {"type": "stretching", "stiffness": 20}])"));
  j["solver"] = {{"substeps", 3}};
  auto s = load(j);
  Simulation& sim = s->simulation;
  sim.effects.push_back(std::make_unique<BreaksAfterSteps>(4));
  sim.step();
  const Eigen::Matrix3Xd x = sim.x, v = sim.v;
  const double time = sim.time;
  EXPECT_THROW(sim.step(), SimulationError);
  EXPECT_EQ(sim.frame, 1);
  EXPECT_EQ(sim.time, time);
  EXPECT_EQ(sim.x, x);
  EXPECT_EQ(sim.v, v);
}

// SPDX-License-Identifier: MIT
// Vertex block descent (Chen, Macklin, Yang & Kim 2024, "Vertex block descent", ACM TOG
// 43(4)) on the incremental potential, with per-vertex conservative bounds (Chen et al.
// 2025, "Offset geometric contact"): docs/simulation.md §5.5.
//
// A step: (1) the first move from xⁿ towards x̃ + h² a (x̃ = xⁿ + h vⁿ the inertial
// prediction, a the uniform fields' acceleration, gravity: the paper's initialisation), each
// vertex as far as the obstacles let it alone (`ContactEffect::limit_moves`), then the whole
// move as far as every contact effect finds safe (`ContactEffect::safe_step`: conservative
// advancement over the candidates and the obstacles' surfaces); (2) the contact effects' per-vertex
// bounds at that state (`vertex_bounds`); (3) `iterations` sweeps: the vertices are
// coloured so that no two of one colour share an element or a contact pair the sweep can
// find active (greedy, solver/colouring.*; again whenever those pairs change), and colour by
// colour every vertex takes one Newton step on its own 3×3 problem
//     (mᵢ/h² I + Hᵢᵢ) Δxᵢ = −(mᵢ/h² (xᵢ − x̃ᵢ) + ∂E/∂xᵢ),
// with Hᵢᵢ the diagonal blocks of the effects' PSD Hessians (`Effect::evaluate_local`),
// cut to the ball of its bound about the bounds' state and to a trust region about its
// position at the sweep's start (twice its move in the sweep before, at least an eighth of
// its bound: what a contact effect's local terms of the sweep can reach is listed from
// these radii, `begin_sweep`, so they stay short). A sweep after which a vertex was
// cut, or a contact effect's candidates went stale (`still_valid`), measures the bounds
// again at its result. The vertices of a colour read the positions of the colour's start
// and are written after all have been computed, so nothing depends on the thread count.
#include "solver/colouring.hpp"
#include "solver/step_state.hpp"

#include <pce/sim/contact_effect.hpp>
#include <pce/sim/simulation.hpp>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace pce::sim {

/// What block descent keeps between steps (buffers and the colouring of the elements).
struct Simulation::BlockState {
  Colouring colouring;
  LocalTerms terms;
  Eigen::VectorXd bound;    ///< per vertex: how far it may move from `anchor`
  Eigen::VectorXd reach;    ///< per vertex: how far it can move in the current sweep
  Eigen::Matrix3Xd anchor;  ///< the state the bounds were measured at
  Eigen::Matrix3Xd next;    ///< a colour's new positions
  std::vector<char> cut, bad;
  std::vector<double> motion;
  Eigen::VectorXd moved;   ///< per vertex: its move in the last sweep
  Eigen::VectorXd limit;   ///< per vertex: the fraction of the first move the one-vertex effects allow
  Eigen::Matrix3Xd field;  ///< per vertex: the state-independent acceleration (gravity), a
};

/// A vertex's trust region in a sweep: this many times its move in the sweep before…
constexpr double kTrustGrowth = 2;
/// …and at least this share of its bound.
constexpr double kTrustShare = 0.125;

void Simulation::block_descent(StepState& s) {
  if (!block_) block_ = std::make_shared<BlockState>();
  BlockState& b = *block_;
  FrameStats& st = s.st;
  const int n = s.n;
  const double h = solver.dt;
  const double inf = std::numeric_limits<double>::infinity();

  // (1) The first move: inertia and the uniform fields (gravity), x̃ + h² a.
  b.field.setZero(3, n);
  for (const auto& e : effects) e->add_acceleration(b.field);
  s.dxm = (x_tilde_ - s.x_start) + h * h * b.field;
  // Effects of one-vertex pairs stop the vertices they must (`limit_moves`), then the move
  // they leave is cut to what every effect finds safe: a vertex landing on an obstacle does
  // not hold back the rest of its sheet.
  b.limit.setOnes(n);
  for (const auto& [k, c] : s.contacts) {
    const ScopedTimer timer(s.effect_ms[k]);
    c->limit_moves(s.y, s.dxm, b.limit);
  }
  for (int i = 0; i < n; ++i) s.dxm.col(i) *= b.limit[i];
  double t = 1;
  for (const auto& [k, c] : s.contacts) {
    const ScopedTimer timer(s.effect_ms[k]);
    t = std::min(t, c->safe_step(s.y, s.dxm));
  }
  s.y = s.x_start + t * s.dxm;
  st.counters[Counter::first_move] = t * b.limit.mean();

  // The elements' couplings (unchanged from step to step unless an effect's declaration is).
  {
    const ScopedTimer timer(st.assembly_ms);
    Pattern elements;
    for (const auto& e : effects)
      if (!as_contact(e.get())) e->declare(elements);
    b.colouring.set_static(n, elements.pairs());
    b.colouring.restart();
  }

  // (2) The bounds.
  const auto measure_bounds = [&] {
    b.bound.setConstant(n, inf);
    for (const auto& [k, c] : s.contacts) {
      const ScopedTimer timer(s.effect_ms[k]);
      c->vertex_bounds(s.y, b.bound);
    }
    b.anchor = s.y;
    st.counters[Counter::detections] += 1;
  };
  measure_bounds();

  // (3) The sweeps.
  for (int sweep = 0; sweep < solver.iterations; ++sweep) {
    if (sweep == 0) b.moved.setZero(n);
    b.reach.resize(n);
    for (int i = 0; i < n; ++i)
      b.reach[i] = std::min(b.bound[i] + (s.y.col(i) - b.anchor.col(i)).norm(),
                            std::max(kTrustGrowth * b.moved[i], kTrustShare * b.bound[i]));
    Pattern couplings;
    for (const auto& [k, c] : s.contacts) {
      const ScopedTimer timer(s.effect_ms[k]);
      c->begin_sweep(s.y, b.reach, couplings);
    }
    {
      const ScopedTimer timer(st.assembly_ms);
      if (b.colouring.colour(couplings.pairs())) st.counters[Counter::colourings] += 1;
    }
    double largest = 0;
    long cut = 0;
    for (const std::vector<int>& colour : b.colouring.colours()) {
      const auto m = static_cast<long>(colour.size());
      b.terms.reset(colour.size());
      for (std::size_t k = 0; k < effects.size(); ++k) {
        const ScopedTimer timer(s.effect_ms[k]);
        effects[k]->evaluate_local(s.y, colour, b.terms);
      }
      const ScopedTimer timer(st.solve_ms);
      b.next.resize(3, m);
      b.cut.assign(static_cast<std::size_t>(m), 0);
      b.bad.assign(static_cast<std::size_t>(m), 0);
      b.motion.assign(static_cast<std::size_t>(m), 0.0);
#pragma omp parallel for schedule(static) if (m >= 64)
      for (long j = 0; j < m; ++j) {
        const auto uj = static_cast<std::size_t>(j);
        const int i = colour[uj];
        const double mh = model.mass[i] / (h * h);
        const Eigen::Vector3d yi = s.y.col(i);
        const Eigen::Vector3d g = b.terms.gradient.col(j) + mh * (yi - x_tilde_.col(i));
        const Eigen::Matrix3d H = b.terms.hessian[uj] + mh * Eigen::Matrix3d::Identity();
        const Eigen::LLT<Eigen::Matrix3d> llt(H);
        Eigen::Vector3d p = yi - llt.solve(g);
        if (llt.info() != Eigen::Success || !p.allFinite()) {
          b.bad[uj] = 1;
          p = yi;
        }
        const Eigen::Vector3d r = p - b.anchor.col(i);
        const double rn = r.norm();
        if (rn > b.bound[i]) p = b.anchor.col(i) + (b.bound[i] / rn) * r;
        // then the trust region (p and yᵢ both lie in the bound's ball, so their chord does)
        const double step = (p - yi).norm();
        if (step > b.reach[i]) p = yi + (b.reach[i] / step) * (p - yi);
        // the vertex used its bound: it ends on the ball's surface
        b.cut[uj] = rn > b.bound[i] && (p - b.anchor.col(i)).norm() >= b.bound[i] * (1 - 1e-9);
        b.motion[uj] = (p - yi).norm();
        b.next.col(j) = p;
      }
      for (long j = 0; j < m; ++j) {
        const auto uj = static_cast<std::size_t>(j);
        if (b.bad[uj]) fail_non_finite(s.y, st.frame, "at block descent sweep " + std::to_string(sweep + 1));
        s.y.col(colour[uj]) = b.next.col(j);
        b.moved[colour[uj]] = b.motion[uj];
        cut += b.cut[uj];
        largest = std::max(largest, b.motion[uj]);
      }
    }
    ++st.newton_iterations;
    st.residual = largest / (h * scale_);
    NewtonIteration record;
    record.residual = st.residual;
    record.alpha = 1;
    st.iterations.push_back(record);
    st.counters[Counter::bound_clamps] += static_cast<double>(cut);
    bool stale = cut > 0;
    for (const auto& [k, c] : s.contacts) stale = !c->still_valid(s.y) || stale;
    if (stale && sweep + 1 < solver.iterations) measure_bounds();
  }
  // The accepted state's energy and counters are to see every pair within reach there.
  for (const auto& [k, c] : s.contacts)
    if (!c->still_valid(s.y)) {
      const ScopedTimer timer(s.effect_ms[k]);
      c->refresh(s.y);
    }
  st.counters[Counter::colours] = static_cast<double>(b.colouring.colours().size());
  st.stop = StopReason::block_descent;
  s.evaluated_at_y = false;
}

}  // namespace pce::sim

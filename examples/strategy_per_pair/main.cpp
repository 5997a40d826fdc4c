// SPDX-License-Identifier: MIT
// Choosing the PSD Hessian strategy per pair: `analytic` by default, `exact` near contact or
// when the caller asks, `gauss_newton` for far pairs. The frame is evaluated once
// (pce::pair_energy); any strategy is then one call to pce::projected_hessian.
#include <pce/pce.hpp>

#include <cstdio>

// pce::Projection, one line each (measured cost and accuracy: docs/benchmarks.md, and
// which strategy when: benchmarks/guidance.md):
//   none          the exact Hessian ∇²E: indefinite in general, not for a Newton solve
//   analytic      clamp the closed-form eigenvalues: PSD, near the exact Hessian's own cost
//   exact         the true nearest PSD matrix through a ≤5×5 eigenproblem: about 2× analytic
//   numerical     the same matrix by a 12×12 eigensolve: the reference, many times slower
//   gauss_newton  max(ψ″,0) ∇L∇Lᵀ: cheapest, drops the length's curvature (least faithful)
//   abs           like analytic but flips negative eigenvalues instead of clamping them
pce::Projection choose(double L, double dhat, bool caller_wants_exact) {
  if (caller_wants_exact || L < 0.1 * dhat) return pce::Projection::exact;  // near contact
  if (L > 0.5 * dhat) return pce::Projection::gauss_newton;                 // far: weak force, curvature hardly matters
  return pce::Projection::analytic;
}

const pce::LogBarrierPenalty barrier{1e3, 0.1};  // k, d̂

// Evaluates one pair, picks its strategy, checks the result is PSD; returns false if not.
template <class Pair> bool show(const char* what, const pce::Vec12<double>& x, bool caller_wants_exact) {
  pce::PairEnergy<double> e;
  if (pce::pair_energy<Pair>(x, pce::UnsignedLength{}, barrier, e) != pce::Status::ok) return false;
  const pce::Projection p = choose(e.length, barrier.dhat, caller_wants_exact);
  const pce::Mat12<double> H = pce::projected_hessian(e, p);
  const pce::Mat12<double> nearest = pce::projected_hessian(e, pce::Projection::numerical);
  const double min_eig = pce::symmetric_eigenvalues(H).minCoeff();
  const double dist = (H - nearest).norm() / nearest.norm();
  std::printf("%-26s L = %.3f  %-12s  min eig %+.2e  |H - nearest PSD| / |nearest| = %.2e\n", what, e.length,
              pce::to_string(p), min_eig, dist);
  const bool psd = min_eig >= -1e-12 * H.norm();
  return psd && (p != pce::Projection::exact || dist < 1e-10);  // exact must be the nearest PSD matrix
}

int main() {
  pce::Vec12<double> vf, ee;
  //    p                 t0         t1         t2
  vf << 0.2, 0.3, 0.005, 0, 0, 0, 1, 0, 0, 0, 1, 0;
  //    ea0          ea1        eb0             eb1
  ee << -1, 0, 0, 1, 0, 0, 0, -1, 0.03, 0, 1, 0.03;
  bool ok = show<pce::VertexFace>("vertex-face, touching", vf, false);
  vf[2] = 0.03;
  ok = show<pce::VertexFace>("vertex-face, in range", vf, false) && ok;
  vf[2] = 0.07;
  ok = show<pce::VertexFace>("vertex-face, far", vf, false) && ok;
  ok = show<pce::EdgeEdge>("edge-edge, caller asks", ee, true) && ok;
  ok = show<pce::EdgeEdge>("edge-edge, default", ee, false) && ok;
  std::printf("%s\n", ok ? "ok: every chosen Hessian is PSD, exact is the nearest PSD matrix" : "FAILED");
  return ok ? 0 : 1;
}

// SPDX-License-Identifier: MIT
// Evaluate the penalty energy of a few vertex-face and edge-edge pairs: length, energy,
// gradient norm, the closed-form eigenvalues, and how each PSD strategy compares.
// Check: every strategy but `none` gives a PSD Hessian (the exit code says so).
//
//   ./pce-example-basic_energies
#include <pce/pce.hpp>

#include <cstdio>

namespace {

bool all_psd = true;  // every strategy except `none` must give a PSD Hessian

template <class Pair, class Length, class Penalty>
void show(const char* what, const pce::Vec12<double>& x, const Length& length, const Penalty& penalty) {
  pce::PairResult<double> r;
  const pce::Status s = pce::evaluate<Pair>(x, length, penalty, pce::Projection::analytic, r);
  std::printf("%-44s ", what);
  if (s != pce::Status::ok) {
    std::printf("status %s\n", pce::to_string(s));
    return;
  }
  std::printf("L = %+.4f  E = %.6g  |grad| = %.4g\n", r.length, r.value, r.gradient.norm());
  std::printf("    frame eigenvalues:");
  for (int i = 0; i < 9; ++i) std::printf(" %.4g", r.eigen.values[i]);
  std::printf("\n    smallest eigenvalue of the 12x12 Hessian by strategy:");
  pce::PairEnergy<double> e;
  pce::pair_energy<Pair>(x, length, penalty, e);
  for (pce::Projection p : {pce::Projection::none, pce::Projection::analytic, pce::Projection::numerical,
                            pce::Projection::gauss_newton, pce::Projection::abs}) {
    const pce::Vec12<double> lam = pce::symmetric_eigenvalues(pce::projected_hessian(e, p));
    std::printf(" %s %.3g", pce::to_string(p), lam.minCoeff());
    if (p != pce::Projection::none && lam.minCoeff() < -1e-12 * lam.cwiseAbs().maxCoeff()) all_psd = false;
  }
  std::printf("\n");
}

}  // namespace

int main() {
  pce::Vec12<double> vf, ee;
  //    p                 t0         t1         t2
  vf << 0.2, 0.3, 0.05, 0, 0, 0, 1, 0, 0, 0, 1, 0;
  //    ea0          ea1        eb0             eb1
  ee << -1, 0, 0, 1, 0, 0, 0, -1, 0.02, 0, 1, 0.02;

  const pce::LogBarrierPenalty barrier{1e3, 0.1};   // k, d̂
  const pce::QuadraticPenalty quadratic{1e4, 0.1};  // k, ε
  const pce::CubicPenalty cubic{1e5, 0.1, 1e-4};    // k, ε, δ

  show<pce::VertexFace>("vertex-face, signed, log barrier", vf, pce::SignedLength{}, barrier);
  show<pce::VertexFace>("vertex-face, signed (other side), quadratic", vf, pce::SignedLength{pce::Side::negative},
                        quadratic);
  show<pce::VertexFace>("vertex-face, unsigned, cubic", vf, pce::UnsignedLength{}, cubic);
  show<pce::EdgeEdge>("edge-edge, unsigned, log barrier", ee, pce::UnsignedLength{}, barrier);
  show<pce::EdgeEdge>("edge-edge, signed (other side), log barrier", ee, pce::SignedLength{pce::Side::negative},
                      barrier);
  pce::Vec12<double> parallel = ee;
  parallel.segment<3>(9) << 2, -1, 0.02;  // eb parallel to ea
  show<pce::EdgeEdge>("edge-edge, parallel edges", parallel, pce::UnsignedLength{}, barrier);
  std::printf("%s\n", all_psd ? "ok: every projected Hessian is PSD" : "FAILED: a projected Hessian is not PSD");
  return all_psd ? 0 : 1;
}

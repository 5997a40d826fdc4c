// SPDX-License-Identifier: MIT
// The consumer tests' pce::pce user: README's "Use" example, built against an installed or
// an add_subdirectory pce. Exits non-zero unless the pair evaluates and its projected
// Hessian is PSD.
#include <pce/pce.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdio>

int main() {
  pce::Vec12<double> x;  // p, t0, t1, t2
  x << 0.2, 0.3, 0.05, 0, 0, 0, 1, 0, 0, 0, 1, 0;

  pce::PairEnergy<double> e;
  const pce::Status s =
      pce::pair_energy<pce::VertexFace>(x, pce::SignedLength{pce::Side::positive}, pce::LogBarrierPenalty{1e3, 0.1}, e);
  if (s != pce::Status::ok) {
    std::printf("pair_energy: status %d\n", static_cast<int>(s));
    return 1;
  }
  const pce::Vec12<double> g = pce::energy_gradient(e);
  const pce::Mat12<double> H = pce::projected_hessian(e, pce::Projection::analytic);
  const double min_eigenvalue = Eigen::SelfAdjointEigenSolver<pce::Mat12<double>>(H).eigenvalues().minCoeff();
  std::printf("pce %s: psi %.6g, |g| %.6g, min eigenvalue of the projected Hessian %.3g\n", PCE_CONSUMER_VERSION,
              e.psi.value, g.norm(), min_eigenvalue);
  const bool ok = std::isfinite(e.psi.value) && e.psi.value > 0 && g.allFinite() && min_eigenvalue > -1e-8 * H.norm();
  return ok ? 0 : 1;
}

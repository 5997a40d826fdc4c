// SPDX-License-Identifier: MIT
// Evaluating a broad-phase candidate by its closest features: a vertex-face or edge-edge
// pair resolves to point-plane / line-line, point-edge or point-point, and the energy is of
// the true distance between the primitives (plane mode would use the plane or line distance).
// Checks: the distance is the expected one and the gradient matches finite differences.
#include <pce/pce.hpp>

#include <cmath>
#include <cstdio>

const pce::QuadraticPenalty penalty{1e3, 2.0};  // k, ε: every pair below is active (L < ε)

template <class Pair> bool show(const char* what, const pce::Vec12<double>& x, double expected) {
  pce::ClosestFeatureEnergy<double> e;
  if (pce::closest_feature_energy<Pair>(x, pce::UnsignedLength{}, penalty, e) != pce::Status::ok) return false;
  const pce::Vec12<double> g = pce::energy_gradient(e);  // on all 12 coordinates
  const pce::Mat12<double> H = pce::projected_hessian(e, pce::Projection::analytic);
  double fd_err = 0;
  for (int k = 0; k < 12; ++k) {  // central differences of ψ(distance)
    pce::Vec12<double> xp = x, xm = x;
    xp[k] += 1e-6, xm[k] -= 1e-6;
    pce::ClosestFeatureEnergy<double> ep, em;
    pce::closest_feature_energy<Pair>(xp, pce::UnsignedLength{}, penalty, ep);
    pce::closest_feature_energy<Pair>(xm, pce::UnsignedLength{}, penalty, em);
    fd_err = std::fmax(fd_err, std::abs((ep.psi.value - em.psi.value) / 2e-6 - g[k]) / (1 + g.norm()));
  }
  pce::PairEnergy<double> plane;  // the same candidate in plane mode, for comparison
  const pce::Status ps = pce::pair_energy<Pair>(x, pce::UnsignedLength{}, penalty, plane);
  std::printf("%-22s %-11s points (%2d %2d %2d)  distance %.4f", what, pce::to_string(e.feature), e.points[0],
              e.points[1], e.points[2], e.length);
  if (ps == pce::Status::ok)
    std::printf("  plane mode %.4f", plane.length);
  else
    std::printf("  plane mode: %s", pce::to_string(ps));
  const double min_eig = pce::symmetric_eigenvalues(H).minCoeff();
  std::printf("  fd err %.1e\n", fd_err);
  return std::abs(e.length - expected) < 1e-12 && fd_err < 1e-6 && min_eig >= -1e-12 * H.norm();
}

int main() {
  pce::Vec12<double> vf, ee;
  //    p               t0         t1         t2
  vf << 0.2, 0.3, 0.1, 0, 0, 0, 1, 0, 0, 0, 1, 0;
  bool ok = show<pce::VertexFace>("p over the face", vf, 0.1);
  vf.head<3>() << 0.5, -0.2, 0.1;
  ok = show<pce::VertexFace>("p beside edge t0-t1", vf, std::sqrt(0.05)) && ok;
  vf.head<3>() << -0.3, -0.4, 0;
  ok = show<pce::VertexFace>("p beyond corner t0", vf, 0.5) && ok;
  //    ea0         ea1        eb0            eb1
  ee << -1, 0, 0, 1, 0, 0, 0, -1, 0.1, 0, 1, 0.1;
  ok = show<pce::EdgeEdge>("crossing edges", ee, 0.1) && ok;
  ee.tail<6>() << 0, 0.2, 0.1, 0, 1, 0.1;
  ok = show<pce::EdgeEdge>("T: eb0 above ea", ee, std::sqrt(0.05)) && ok;
  ee.tail<6>() << 2, 0, 0.1, 3, 0, 0.1;
  ok = show<pce::EdgeEdge>("parallel, end to end", ee, std::sqrt(1.01)) && ok;
  std::printf("%s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}

// SPDX-License-Identifier: MIT
// Adding pce contact energies to an existing Newton solver: each pair's 12-vector is
// gathered from the global DOFs, and its energy, gradient and PSD 12×12 Hessian are
// scattered back into a global gradient and an Eigen::SparseMatrix through triplets.
// Checks: gradient = central finite difference, H symmetric and PSD, Newton step descends.
#include <pce/pce.hpp>

#include <Eigen/SparseCholesky>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

struct Candidate {
  bool edge_edge;        // false: vertex-face (p, t0, t1, t2); true: edge-edge (ea0, ea1, eb0, eb1)
  std::array<int, 4> v;  // global vertex indices, in the pair's order
};

const pce::LogBarrierPenalty barrier{1e2, 0.1};  // k, d̂

// Energy of all pairs at x (3n DOFs); adds gradient and PSD Hessian triplets when asked.
double contact(const Eigen::VectorXd& x, const std::vector<Candidate>& pairs, Eigen::VectorXd* g,
               std::vector<Eigen::Triplet<double>>* H) {
  double E = 0;
  for (const Candidate& c : pairs) {
    pce::Vec12<double> xl;  // pair-local: point a of the pair is global vertex c.v[a]
    for (int a = 0; a < 4; ++a) xl.segment<3>(3 * a) = x.segment<3>(3 * c.v[a]);
    pce::PairResult<double> r;
    const pce::Status s =
        c.edge_edge ? pce::evaluate<pce::EdgeEdge>(xl, pce::UnsignedLength{}, barrier, pce::Projection::analytic, r)
                    : pce::evaluate<pce::VertexFace>(xl, pce::UnsignedLength{}, barrier, pce::Projection::analytic, r);
    if (s != pce::Status::ok) continue;  // degenerate pair: a real solver would log or mollify
    E += r.value;
    for (int a = 0; a < 4; ++a) {  // local DOF 3a+i  ->  global DOF 3 v[a] + i
      if (g) g->segment<3>(3 * c.v[a]) += r.gradient.segment<3>(3 * a);
      for (int b = 0; H && b < 4; ++b)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            H->emplace_back(3 * c.v[a] + i, 3 * c.v[b] + j, r.projected_hessian(3 * a + i, 3 * b + j));
    }
  }
  return E;
}

int main() {
  Eigen::VectorXd x(3 * 8);  // triangle 0-1-2, points 3, 4 above it, edges 5-6, 5-7 over edges 1-2, 3-4
  //   0        1        2        3               4               5               6
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.3, 0.05, 0.5, 0.2, 0.08, 0.3, 0.3, 0.13, 0.7, 0.7, 0.03, 0.4, 0.2, 0.08;  // 7
  const std::vector<Candidate> pairs = {
      {false, {3, 0, 1, 2}}, {false, {4, 0, 1, 2}}, {true, {1, 2, 5, 6}}, {true, {5, 7, 3, 4}}};
  const int n = static_cast<int>(x.size());
  const double inertia = 50.0;  // the existing solver's own term: (m/h²)/2 |x − x̃|², here x̃ = x
  Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
  std::vector<Eigen::Triplet<double>> trip;
  for (int k = 0; k < n; ++k) trip.emplace_back(k, k, inertia);  // the solver's Hessian entries
  const double E = contact(x, pairs, &g, &trip);
  Eigen::SparseMatrix<double> H(n, n);
  H.setFromTriplets(trip.begin(), trip.end());  // duplicates (shared vertices) are summed

  double fd_err = 0;  // central differences of the total contact energy, one DOF at a time
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd xp = x, xm = x;
    xp[k] += 1e-6, xm[k] -= 1e-6;
    const double fd = (contact(xp, pairs, nullptr, nullptr) - contact(xm, pairs, nullptr, nullptr)) / 2e-6;
    fd_err = std::fmax(fd_err, std::abs(fd - g[k]) / (1 + std::abs(g[k])));
  }
  const Eigen::MatrixXd Hd(H);
  const double asym = (Hd - Hd.transpose()).norm() / Hd.norm();
  const double min_eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Hd).eigenvalues().minCoeff();
  const Eigen::VectorXd dx = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>(H).solve(-g);
  std::printf("contact energy %.6g, |grad| %.4g, %d pairs, H %dx%d with %ld non-zeros\n", E, g.norm(),
              static_cast<int>(pairs.size()), n, n, static_cast<long>(H.nonZeros()));
  std::printf(
      "gradient vs finite differences: max rel. error %.1e; H asymmetry %.0e, smallest eigenvalue %.4g "
      "(>= inertia %.0f); Newton slope g.dx = %.4g\n",
      fd_err, asym, min_eig, inertia, g.dot(dx));
  const bool ok = E > 0 && fd_err < 1e-5 && asym < 1e-14 && min_eig >= inertia * (1 - 1e-9) && g.dot(dx) < 0;
  std::printf("%s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}

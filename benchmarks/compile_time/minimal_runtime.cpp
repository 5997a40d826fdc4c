// SPDX-License-Identifier: MIT
// Compile-time benchmark (benchmarks/run_all, step compile_time): the smallest user file with
// the PSD strategy chosen at run time, `projected_hessian(e, Projection::analytic)`. Header-only
// it compiles every strategy, Eigen's 12x12 eigensolver included; with -DPCE_PRECOMPILED (a
// program linking pce::precompiled) those instantiations are declared extern and not compiled.
// Compare minimal_template.cpp, which picks the strategy at compile time.
#include <pce/pce.hpp>

#include <cstdio>

int main() {
  pce::Vec12<double> x;
  //   p                t0         t1         t2
  x << 0.2, 0.3, 0.05, 0, 0, 0, 1, 0, 0, 0, 1, 0;
  pce::PairEnergy<double> e;
  const pce::Status s =
      pce::pair_energy<pce::VertexFace>(x, pce::SignedLength{pce::Side::positive}, pce::QuadraticPenalty{1e3, 0.1}, e);
  if (s != pce::Status::ok) {
    std::printf("status %s\n", pce::to_string(s));
    return 1;
  }
  const pce::Vec12<double> g = pce::energy_gradient(e);
  const pce::Mat12<double> H = pce::projected_hessian(e, pce::Projection::analytic);
  std::printf("E = %.6g  |grad| = %.6g  |H| = %.6g\n", e.psi.value, g.norm(), H.norm());
  return 0;
}

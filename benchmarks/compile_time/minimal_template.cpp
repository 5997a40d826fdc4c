// SPDX-License-Identifier: MIT
// Compile-time benchmark (benchmarks/run_all, step compile_time): minimal_runtime.cpp with the
// PSD strategy chosen at compile time, `projected_hessian<Projection::analytic>(e)`: only that
// strategy is instantiated, so the file compiles quickly header-only, without pce::precompiled.
// Use this form in a file you edit often.
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
  const pce::Mat12<double> H = pce::projected_hessian<pce::Projection::analytic>(e);
  std::printf("E = %.6g  |grad| = %.6g  |H| = %.6g\n", e.psi.value, g.norm(), H.norm());
  return 0;
}

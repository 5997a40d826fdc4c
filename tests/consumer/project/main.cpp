// SPDX-License-Identifier: MIT
// The consumer tests' pce::pce user: README's "Use" example, built against an installed or
// an add_subdirectory pce. Exits non-zero unless the pair evaluates and its projected
// Hessian is PSD (a Cholesky factorisation of H + δI). Built header-only (the strategy at
// compile time, as README shows) and, where pce::precompiled is at hand, linked to it (the
// run-time strategy from the library, which must give the same bits).
#include <pce/pce.hpp>

#include <Eigen/Cholesky>

#include <cmath>
#include <cstdio>

int main() {
#if defined(PCE_CONSUMER_EXPECT_PRECOMPILED) && !defined(PCE_PRECOMPILED)
  std::printf("linked pce::precompiled, but PCE_PRECOMPILED is not defined\n");
  return 1;
#elif !defined(PCE_CONSUMER_EXPECT_PRECOMPILED) && defined(PCE_PRECOMPILED)
  std::printf("PCE_PRECOMPILED is defined without pce::precompiled\n");
  return 1;
#endif
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
  const pce::Mat12<double> H = pce::projected_hessian<pce::Projection::analytic>(e);
#if defined(PCE_PRECOMPILED)
  if (pce::projected_hessian(e, pce::Projection::analytic) != H) {
    std::printf("pce::precompiled's projected_hessian differs from the header's\n");
    return 1;
  }
#endif
  const bool psd = (H + 1e-10 * H.norm() * pce::Mat12<double>::Identity()).llt().info() == Eigen::Success;
  std::printf("pce %s%s: psi %.6g, |g| %.6g, projected Hessian %s\n", PCE_CONSUMER_VERSION,
#if defined(PCE_PRECOMPILED)
              " (pce::precompiled)",
#else
              "",
#endif
              e.psi.value, g.norm(), psd ? "PSD" : "not PSD");
  const bool ok = std::isfinite(e.psi.value) && e.psi.value > 0 && g.allFinite() && psd;
  return ok ? 0 : 1;
}

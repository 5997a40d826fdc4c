// SPDX-License-Identifier: MIT
/// @file
/// Per-tetrahedron benchmarks of the stable Neo-Hookean energy (`volumes/`):
/// `tet_snh/<quantity>/<float|double>`, time per tetrahedron over a fixed-seed pool of 1024
/// deformed tetrahedra (well-shaped rest shapes, each vertex moved by up to 30 % of the edge
/// length; some come out inverted). Quantities: `energy_gradient` (E and ∇E), `hessian` (E, ∇E
/// and the exact 12×12 Hessian), `analytic` and `numerical` (E, ∇E and the PSD Hessian by the
/// closed-form eigensystem or by a 9×9 eigensolve, `VolumeProjection`), and `projection_analytic`
/// / `projection_numerical` (the 9×9 F-space projection alone). See docs/pce-bench.md.
#include "bench_common.hpp"

#include <pce/volumes/stable_neo_hookean.hpp>

#include <cstdio>
#include <random>
#include <vector>

namespace pce_bench {

namespace {

/// One tetrahedron of the pool: its rest shape and deformed coordinates.
template <class Scalar> struct Tet {
  pce::TetRest<Scalar> rest;
  pce::Vec12<Scalar> x;
};

/// The pool, built once per scalar; `inverted` counts det F < 0, `indefinite` the tetrahedra
/// whose 3×3 scaling block has a negative eigenvalue (the analytic projection's slower path).
template <class Scalar> struct TetPool {
  std::vector<Tet<Scalar>> tets;
  int inverted = 0, indefinite = 0;
};

pce::StableNeoHookean material() { return pce::StableNeoHookean::from_young_poisson(1e5, 0.4); }

template <class Scalar> const TetPool<Scalar>& tet_pool() {
  static const TetPool<Scalar> pool = [] {
    TetPool<Scalar> p;
    std::mt19937_64 rng(kSeed);
    std::uniform_real_distribution<double> u(-1, 1);
    // a regular tetrahedron of edge 1, positively oriented
    const double X0[12] = {0, 0, 0, 1, 0, 0, 0.5, std::sqrt(3.0) / 2, 0, 0.5, std::sqrt(3.0) / 6, std::sqrt(2.0 / 3)};
    while (p.tets.size() < kPoolSize) {
      pce::Vec12<Scalar> X, x;
      for (int i = 0; i < 12; ++i) X[i] = static_cast<Scalar>(X0[i] + 0.1 * u(rng));
      Tet<Scalar> t;
      if (pce::tet_rest(X, t.rest) != pce::Status::ok) continue;
      for (int i = 0; i < 12; ++i) x[i] = static_cast<Scalar>(X[i] + 0.3 * u(rng));
      t.x = x;
      const pce::Mat3<Scalar> F = pce::deformation_gradient(t.rest, x);
      p.inverted += F.determinant() < Scalar(0);
      const pce::detail::SnhModes<Scalar> md(material(), F);
      p.indefinite += Eigen::LLT<pce::Mat3<Scalar>>(md.A).info() != Eigen::Success;
      p.tets.push_back(t);
    }
    return p;
  }();
  return pool;
}

enum class TetQuantity { energy_gradient, hessian, analytic, numerical, projection_analytic, projection_numerical };

template <class Scalar, TetQuantity Q> void bench_tet(benchmark::State& state) {
  const TetPool<Scalar>& pool = tet_pool<Scalar>();
  const pce::StableNeoHookean m = material();
  std::size_t i = 0;
  for (auto _ : state) {
    const Tet<Scalar>& t = pool.tets[i];
    i = (i + 1) & (kPoolSize - 1);
    if constexpr (Q == TetQuantity::projection_analytic || Q == TetQuantity::projection_numerical) {
      const pce::Mat3<Scalar> F = pce::deformation_gradient(t.rest, t.x);
      const pce::Mat9<Scalar> H = pce::snh_projected_hessian(
          m, F,
          Q == TetQuantity::projection_analytic ? pce::VolumeProjection::analytic : pce::VolumeProjection::numerical);
      benchmark::DoNotOptimize(H);
    } else {
      Scalar E = 0;
      pce::Vec12<Scalar> g = pce::Vec12<Scalar>::Zero();
      pce::Mat12<Scalar> H = pce::Mat12<Scalar>::Zero();
      const pce::VolumeProjection how = Q == TetQuantity::analytic    ? pce::VolumeProjection::analytic
                                        : Q == TetQuantity::numerical ? pce::VolumeProjection::numerical
                                                                      : pce::VolumeProjection::none;
      const pce::Status s =
          pce::snh_tet_energy(m, t.rest, t.x, how, E, &g, Q == TetQuantity::energy_gradient ? nullptr : &H);
      benchmark::DoNotOptimize(s);
      benchmark::DoNotOptimize(E);
      benchmark::DoNotOptimize(g);
      if constexpr (Q != TetQuantity::energy_gradient) benchmark::DoNotOptimize(H);
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

template <class Scalar> void register_tet_scalar(const char* scalar) {
  const auto reg = [scalar](const char* q, void (*f)(benchmark::State&)) {
    benchmark::RegisterBenchmark((std::string("tet_snh/") + q + "/" + scalar).c_str(), f);
  };
  reg("energy_gradient", &bench_tet<Scalar, TetQuantity::energy_gradient>);
  reg("hessian", &bench_tet<Scalar, TetQuantity::hessian>);
  reg("analytic", &bench_tet<Scalar, TetQuantity::analytic>);
  reg("numerical", &bench_tet<Scalar, TetQuantity::numerical>);
  reg("projection_analytic", &bench_tet<Scalar, TetQuantity::projection_analytic>);
  reg("projection_numerical", &bench_tet<Scalar, TetQuantity::projection_numerical>);
}

}  // namespace

TetPoolStats register_tet_benchmarks() {
  register_tet_scalar<double>("double");
  register_tet_scalar<float>("float");
  const TetPool<double>& p = tet_pool<double>();
  return {static_cast<int>(p.tets.size()), p.inverted, p.indefinite};
}

}  // namespace pce_bench

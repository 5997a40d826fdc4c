// SPDX-License-Identifier: MIT
/// @file
/// Shared fixture of the `pce-bench` micro-benchmarks: a fixed-seed pool of random pairs
/// on which the log barrier is active, checked before anything is timed, and the
/// benchmark bodies themselves (one per measured quantity), templated on the pair kind
/// and the scalar. `bench_vertex_face.cpp` and `bench_edge_edge.cpp` register them under
/// the names `<pair>/<quantity>/<scalar>`; `bench_main.cpp` runs everything and prints
/// the ratio summary. See `docs/pce-bench.md`.
#pragma once

#include <pce/pce.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

// Eigen's dense symmetric eigensolvers (pce::project_psd behind Projection::numerical, the
// eigenvalues check_pair uses, the tetrahedra's numerical F-space projection) are not compiled
// in every benchmark file: benchmarks/CMakeLists.txt links pce::precompiled's archive, which
// holds them for float and double (compiled with the same flags), without its PCE_PRECOMPILED,
// so that the run-time dispatch projected_hessian(e, strategy) and everything else that is
// timed stays inline in the benchmark loops, as in a header-only build. Eigen's solver is
// called out of line either way (it is far too large to inline), so the timings are those of
// the header-only build.
namespace pce {
PCE_PSD_PROJECTION_INSTANCES(extern, float)
PCE_PSD_PROJECTION_INSTANCES(extern, double)
namespace detail {
PCE_SNH_INSTANCES(extern, float)
PCE_SNH_INSTANCES(extern, double)
}  // namespace detail
}  // namespace pce

namespace pce_bench {

/// Main configuration: log barrier of stiffness 1 and activation distance `kDhat` on the
/// signed length, positive side. Geometry lives in [-1, 1]^3 with edges of length ~1.
inline constexpr double kDhat = 1e-2;
/// Pairs per pool; a power of two so the loop index wraps with a mask.
inline constexpr std::size_t kPoolSize = 1024;
static_assert((kPoolSize & (kPoolSize - 1)) == 0, "kPoolSize must be a power of two");
/// Fixed seed: every run times the same pairs (with the same standard library; the
/// `uniform_real_distribution` algorithm is implementation-defined).
inline constexpr std::uint64_t kSeed = 20231121;
/// The barrier's length L = l is drawn uniformly in [kLMin, kLMax] * dhat.
inline constexpr double kLMin = 0.05, kLMax = 0.95;

inline pce::LogBarrierPenalty penalty() { return pce::LogBarrierPenalty{1.0, kDhat}; }
/// The signed length for the plane kinds; the point kinds (`PointEdge`, `PointPoint`) are
/// unsigned only.
template <class Pair> auto length() {
  if constexpr (Pair::dofs == 12)
    return pce::SignedLength{};
  else
    return pce::UnsignedLength{};
}

/// What one benchmark measures (all include the frame, L and ψ).
enum class Quantity {
  value_only,            ///< value_only: E alone, from the lean frame
  value_gradient,        ///< value_gradient: E and its gradient, from the lean frame
  exact_hessian,         ///< pair_energy + energy_gradient + energy_hessian
  eigensystem,           ///< pair_energy + energy_eigensystem (closed form, frame space)
  analytic,              ///< pair_energy + energy_gradient + projected_hessian(analytic)
  abs,                   ///< ... projected_hessian(abs)
  exact,                 ///< ... projected_hessian(exact): nearest PSD matrix via the <= 5x5 reduced problem
  gauss_newton,          ///< ... projected_hessian(gauss_newton)
  numerical,             ///< ... projected_hessian(numerical): 12x12 eigensolve + clamp (baseline)
  batch_value_gradient,  ///< evaluate_batch over the pool (1024 pairs): value and gradient; time per pair
  batch_exact_hessian,   ///< ... value, gradient and exact Hessian
  batch_analytic,        ///< ... value, gradient and projected_hessian(analytic)
};

/// Whether a quantity is timed through `evaluate_batch` (per pair, in batches of kPoolSize).
constexpr bool is_batched(Quantity q) {
  return q == Quantity::batch_value_gradient || q == Quantity::batch_exact_hessian || q == Quantity::batch_analytic;
}

inline const char* to_string(Quantity q) {
  switch (q) {
    case Quantity::value_only:
      return "value_only";
    case Quantity::value_gradient:
      return "value_gradient";
    case Quantity::exact_hessian:
      return "exact_hessian";
    case Quantity::eigensystem:
      return "eigensystem";
    case Quantity::analytic:
      return "analytic";
    case Quantity::abs:
      return "abs";
    case Quantity::exact:
      return "exact";
    case Quantity::gauss_newton:
      return "gauss_newton";
    case Quantity::numerical:
      return "numerical";
    case Quantity::batch_value_gradient:
      return "batch_value_gradient";
    case Quantity::batch_exact_hessian:
      return "batch_exact_hessian";
    case Quantity::batch_analytic:
      return "batch_analytic";
  }
  return "unknown";
}

/// Registration order within one (pair, scalar): cheap to expensive, PSD strategies last.
inline constexpr Quantity kQuantities[] = {Quantity::value_only,
                                           Quantity::value_gradient,
                                           Quantity::exact_hessian,
                                           Quantity::eigensystem,
                                           Quantity::analytic,
                                           Quantity::abs,
                                           Quantity::exact,
                                           Quantity::gauss_newton,
                                           Quantity::numerical,
                                           Quantity::batch_value_gradient,
                                           Quantity::batch_exact_hessian,
                                           Quantity::batch_analytic};

template <class Scalar> constexpr const char* scalar_name();
template <> constexpr const char* scalar_name<float>() { return "float"; }
template <> constexpr const char* scalar_name<double>() { return "double"; }

/// Benchmark name `<pair>/<quantity>/<scalar>`, e.g. `vertex_face/analytic/double`.
template <class Pair, class Scalar> std::string bench_name(Quantity q) {
  return std::string(Pair::name) + "/" + to_string(q) + "/" + scalar_name<Scalar>();
}

namespace detail {

using Vec3d = pce::Vec3<double>;
using Vec12d = pce::Vec12<double>;
template <class Pair, class Scalar> using X = pce::VecN<Scalar, Pair::dofs>;
template <class Pair, class Scalar> using H = pce::MatN<Scalar, Pair::dofs>;

inline Vec3d random_point(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vec3d p;
  for (int i = 0; i < 3; ++i) p[i] = u(rng);
  return p;
}

/// A well-shaped random pair whose signed length is exactly `L` (up to rounding) by
/// construction: the fourth point (VF) or second edge (EE) is placed at distance L along
/// the pair's normal n = e0 x e1 / |e0 x e1|. Returns false for a badly shaped draw.
inline bool make_random_pair(pce::VertexFace, std::mt19937_64& rng, double L, Vec12d& x) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3d t0 = random_point(rng), t1 = random_point(rng), t2 = random_point(rng);
  const Vec3d e0 = t1 - t0, e1 = t2 - t0;
  const Vec3d m = e0.cross(e1);
  if (e0.norm() < 0.3 || e1.norm() < 0.3 || (t2 - t1).norm() < 0.3) return false;
  if (m.norm() < 0.3 * e0.norm() * e1.norm()) return false;  // angle at t0 not too flat
  const Vec3d n = m.normalized();
  double b1 = u(rng), b2 = u(rng);
  if (b1 + b2 > 1.0) b1 = 1.0 - b1, b2 = 1.0 - b2;  // uniform in the triangle
  const Vec3d p = t0 + b1 * e0 + b2 * e1 + L * n;
  x << p, t0, t1, t2;
  return true;
}

inline bool make_random_pair(pce::EdgeEdge, std::mt19937_64& rng, double L, Vec12d& x) {
  std::uniform_real_distribution<double> u(0.2, 0.8);
  const Vec3d a0 = random_point(rng), a1 = random_point(rng), c0 = random_point(rng), c1 = random_point(rng);
  const Vec3d ea = a1 - a0, eb = c1 - c0;
  if (ea.norm() < 0.3 || eb.norm() < 0.3) return false;
  const Vec3d m = ea.cross(eb);
  if (m.norm() < 0.3 * ea.norm() * eb.norm()) return false;  // not nearly parallel
  const Vec3d n = m.normalized();
  const double sa = u(rng), sb = u(rng);
  const Vec3d b0 = a0 + sa * ea + L * n - sb * eb;  // closest points inside both edges
  x << a0, a1, b0, b0 + eb;
  return true;
}

/// A point at distance L from the line of a random edge (length >= 0.3), its foot inside.
inline bool make_random_pair(pce::PointEdge, std::mt19937_64& rng, double L, pce::Vec9<double>& x) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3d e0 = random_point(rng), e1 = random_point(rng), w = random_point(rng);
  const Vec3d e = e1 - e0;
  if (e.norm() < 0.3) return false;
  const Vec3d n = e.cross(w);
  if (n.norm() < 0.1 * e.norm()) return false;
  const Vec3d p = e0 + u(rng) * e + L * n.normalized();
  x << p, e0, e1;
  return true;
}

/// Two points at distance L.
inline bool make_random_pair(pce::PointPoint, std::mt19937_64& rng, double L, pce::Vec6<double>& x) {
  const Vec3d q = random_point(rng), w = random_point(rng);
  if (w.norm() < 0.1) return false;
  x << q + L * w.normalized(), q;
  return true;
}

/// Evaluates `x` in `Scalar` and checks that it is a benchmark-worthy active pair:
/// status ok, 0 < L < dhat, psi'' > 0, and the exact 12x12 Hessian has clearly negative
/// eigenvalues (so `Projection::numerical` really clamps). Returns the number of negative
/// eigenvalues (0 = reject) and the ratio min eig / max |eig|.
template <class Pair, class Scalar> int check_pair(const X<Pair, Scalar>& x, double& neg_ratio) {
  typename Pair::template Energy<Scalar> e;
  if (pce::pair_energy<Pair>(x, length<Pair>(), penalty(), e) != pce::Status::ok) return 0;
  if (!(e.length > Scalar(0) && e.length < Scalar(kDhat)) || !(e.psi.second > Scalar(0))) return 0;
  // pce::symmetric_eigenvalues: Eigen's SelfAdjointEigenSolver (eigenvalues only), the
  // instantiation pce::precompiled compiles (declared extern above).
  const pce::VecN<Scalar, Pair::dofs> lam = pce::symmetric_eigenvalues(pce::energy_hessian(e).eval());
  if (!lam.allFinite()) return 0;
  const double big = static_cast<double>(lam.cwiseAbs().maxCoeff());
  neg_ratio = static_cast<double>(lam.minCoeff()) / big;
  if (!(neg_ratio < -1e-5)) return 0;  // well above the eigensolver's noise in float
  int neg = 0;
  for (int i = 0; i < Pair::dofs; ++i) neg += lam[i] < Scalar(-1e-5 * big) ? 1 : 0;
  return neg;
}

}  // namespace detail

/// Statistics of one pool, printed by `pce-bench` before the timings.
struct PoolStats {
  std::size_t draws = 0;    ///< random draws needed (rejections = draws - kPoolSize)
  int min_negative = 12;    ///< fewest clearly negative eigenvalues of an exact Hessian
  int max_negative = 0;     ///< most
  double worst_ratio = -1;  ///< largest (closest to 0) min-eig / max-|eig| over the pool, both scalars
  double gap_median = 0;    ///< ‖analytic − exact‖_F / ‖exact‖_F over the double pool: median
  double gap_max = 0;       ///< ... and maximum
};

/// The pool of one pair kind in one scalar: kPoolSize pairs, each accepted only if it
/// passes `check_pair` in BOTH float and double (the two pools hold the same geometry).
template <class Pair, class Scalar> struct Pool {
  std::vector<detail::X<Pair, Scalar>> x;
  PoolStats stats;
};

template <class Pair> struct PoolPair {
  Pool<Pair, double> d;
  Pool<Pair, float> f;
};

template <class Pair> PoolPair<Pair> build_pools() {
  PoolPair<Pair> pp;
  std::uint64_t seed = kSeed;  // one stream per pair kind
  for (const char* c = Pair::name; *c != '\0'; ++c) seed = seed * 131 + static_cast<unsigned char>(*c);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uL(kLMin * kDhat, kLMax * kDhat);
  PoolStats st;
  while (pp.d.x.size() < kPoolSize) {
    if (++st.draws > 100 * kPoolSize) {
      std::fprintf(stderr, "pce-bench: cannot build a pool of active %s pairs\n", Pair::name);
      std::exit(2);
    }
    detail::X<Pair, double> xd;
    if (!detail::make_random_pair(Pair{}, rng, uL(rng), xd)) continue;
    const detail::X<Pair, float> xf = xd.template cast<float>();
    double rd = 0, rf = 0;
    const int nd = detail::check_pair<Pair, double>(xd, rd);
    const int nf = detail::check_pair<Pair, float>(xf, rf);
    if (nd == 0 || nf == 0) continue;
    st.min_negative = std::min({st.min_negative, nd, nf});
    st.max_negative = std::max({st.max_negative, nd, nf});
    st.worst_ratio = std::max({st.worst_ratio, rd, rf});
    pp.d.x.push_back(xd);
    pp.f.x.push_back(xf);
  }
  // How far the closed-form clamp is from the nearest PSD matrix on this pool (double).
  std::vector<double> gaps;
  for (const auto& x : pp.d.x) {
    typename Pair::template Energy<double> e;
    if (pce::pair_energy<Pair>(x, length<Pair>(), penalty(), e) != pce::Status::ok) continue;  // checked above
    const detail::H<Pair, double> Px = pce::projected_hessian(e, pce::Projection::exact);
    gaps.push_back((pce::projected_hessian(e, pce::Projection::analytic) - Px).norm() / Px.norm());
  }
  std::sort(gaps.begin(), gaps.end());
  st.gap_median = gaps[gaps.size() / 2];
  st.gap_max = gaps.back();
  pp.d.stats = pp.f.stats = st;
  return pp;
}

/// The pools, built once (on first use, before any timing: `register_family` calls it).
template <class Pair> const PoolPair<Pair>& pools() {
  static const PoolPair<Pair> pp = build_pools<Pair>();
  return pp;
}

template <class Pair, class Scalar> const Pool<Pair, Scalar>& pool() {
  if constexpr (std::is_same_v<Scalar, double>)
    return pools<Pair>().d;
  else
    return pools<Pair>().f;
}

inline pce::Projection projection_of(Quantity q) {
  switch (q) {
    case Quantity::analytic:
      return pce::Projection::analytic;
    case Quantity::abs:
      return pce::Projection::abs;
    case Quantity::exact:
      return pce::Projection::exact;
    case Quantity::gauss_newton:
      return pce::Projection::gauss_newton;
    case Quantity::numerical:
      return pce::Projection::numerical;
    case Quantity::batch_analytic:
      return pce::Projection::analytic;
    default:
      return pce::Projection::none;
  }
}

/// One pair per iteration, cycling through the pool, so the reported time per iteration
/// is the time per pair. Outputs go through DoNotOptimize (which also forces them to
/// memory, as an assembly loop would).
template <class Pair, class Scalar, Quantity Q> void bench_pair(benchmark::State& state) {
  const std::vector<detail::X<Pair, Scalar>>& xs = pool<Pair, Scalar>().x;
  const auto len = length<Pair>();
  const auto pen = penalty();
  if constexpr (is_batched(Q)) {
    // the whole pool per call, into outputs allocated once; KeepRunningBatch counts its pairs,
    // so the reported time is per pair
    constexpr int D = Pair::dofs;
    std::vector<Scalar> x(kPoolSize * D), value(kPoolSize), gradient(kPoolSize * D), hessian;
    std::vector<pce::Status> status(kPoolSize);
    for (std::size_t i = 0; i < kPoolSize; ++i)
      for (int c = 0; c < D; ++c) x[i * D + c] = xs[i][c];
    if (Q != Quantity::batch_value_gradient) hessian.resize(kPoolSize * D * D);
    pce::BatchOutput<Scalar> out;
    out.status = status.data();
    out.value = value.data();
    out.gradient = gradient.data();
    if (Q == Quantity::batch_exact_hessian) out.hessian = hessian.data();
    if (Q == Quantity::batch_analytic) out.projected = hessian.data();
    while (state.KeepRunningBatch(static_cast<benchmark::IterationCount>(kPoolSize))) {
      pce::evaluate_batch<Pair>(x.data(), kPoolSize, len, pen, projection_of(Q), out);
      benchmark::ClobberMemory();
    }
    for (const pce::Status s : status)
      if (s != pce::Status::ok) state.SkipWithError("a pool pair is not ok in evaluate_batch");
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
    return;
  }
  std::size_t i = 0;
  for (auto _ : state) {
    const detail::X<Pair, Scalar>& x = xs[i];
    i = (i + 1) & (kPoolSize - 1);
    if constexpr (Q == Quantity::value_only) {
      Scalar v = 0;
      pce::Status s = pce::value_only<Pair>(x, len, pen, v);
      benchmark::DoNotOptimize(s);
      benchmark::DoNotOptimize(v);
      continue;
    } else if constexpr (Q == Quantity::value_gradient) {
      Scalar v = 0;
      detail::X<Pair, Scalar> g = detail::X<Pair, Scalar>::Zero();
      pce::Status s = pce::value_gradient<Pair>(x, len, pen, v, g);
      benchmark::DoNotOptimize(s);
      benchmark::DoNotOptimize(v);
      benchmark::DoNotOptimize(g);
      continue;
    }
    typename Pair::template Energy<Scalar> e;
    pce::Status s = pce::pair_energy<Pair>(x, len, pen, e);
    benchmark::DoNotOptimize(s);
    if (s != pce::Status::ok) continue;  // never taken: the pools hold ok pairs only
    benchmark::DoNotOptimize(e.psi.value);
    if constexpr (Q == Quantity::eigensystem) {
      auto es = pce::energy_eigensystem(e);
      benchmark::DoNotOptimize(es);
    } else {
      detail::X<Pair, Scalar> g = pce::energy_gradient(e);
      benchmark::DoNotOptimize(g);
      if constexpr (Q == Quantity::exact_hessian) {
        detail::H<Pair, Scalar> H = pce::energy_hessian(e);
        benchmark::DoNotOptimize(H);
      } else if constexpr (Q != Quantity::value_gradient) {
        detail::H<Pair, Scalar> H = pce::projected_hessian(e, projection_of(Q));
        benchmark::DoNotOptimize(H);
      }
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

template <class Pair, class Scalar> void register_scalar() {
  using Fn = void (*)(benchmark::State&);
  const Fn fns[] = {
      &bench_pair<Pair, Scalar, Quantity::value_only>,
      &bench_pair<Pair, Scalar, Quantity::value_gradient>,
      &bench_pair<Pair, Scalar, Quantity::exact_hessian>,
      &bench_pair<Pair, Scalar, Quantity::eigensystem>,
      &bench_pair<Pair, Scalar, Quantity::analytic>,
      &bench_pair<Pair, Scalar, Quantity::abs>,
      &bench_pair<Pair, Scalar, Quantity::exact>,
      &bench_pair<Pair, Scalar, Quantity::gauss_newton>,
      &bench_pair<Pair, Scalar, Quantity::numerical>,
      &bench_pair<Pair, Scalar, Quantity::batch_value_gradient>,
      &bench_pair<Pair, Scalar, Quantity::batch_exact_hessian>,
      &bench_pair<Pair, Scalar, Quantity::batch_analytic>,
  };
  static_assert(sizeof(fns) / sizeof(fns[0]) == sizeof(kQuantities) / sizeof(kQuantities[0]));
  for (std::size_t k = 0; k < sizeof(fns) / sizeof(fns[0]); ++k)
    benchmark::RegisterBenchmark(bench_name<Pair, Scalar>(kQuantities[k]).c_str(), fns[k])
        ->Unit(benchmark::kNanosecond)
        // With --benchmark_repetitions: a `<name>_min` aggregate next to mean/median/stddev/cv.
        ->ComputeStatistics("min", [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); });
}

/// Builds and checks the pools of `Pair`, then registers its 16 benchmarks
/// (double first, then float). Returns the pool statistics.
template <class Pair> PoolStats register_family() {
  const PoolStats st = pools<Pair>().d.stats;
  register_scalar<Pair, double>();
  register_scalar<Pair, float>();
  return st;
}

// Defined in bench_vertex_face.cpp and bench_edge_edge.cpp.
PoolStats register_vertex_face_benchmarks();
PoolStats register_edge_edge_benchmarks();
PoolStats register_point_edge_benchmarks();
PoolStats register_point_point_benchmarks();

/// The tetrahedron pool's make-up (`bench_tet.cpp`): tetrahedra, inverted ones (det F < 0),
/// and those whose stable Neo-Hookean scaling block is indefinite (the analytic projection's
/// slower path, a 3×3 eigensolve).
struct TetPoolStats {
  int count, inverted, indefinite;
};
TetPoolStats register_tet_benchmarks();

}  // namespace pce_bench

// SPDX-License-Identifier: MIT
/// @file
/// The PSD strategies a pair's Hessian can be projected with (`pce::Projection`), their
/// names (`pce::kProjectionNames`), and the dispatch from a strategy chosen at run time to the compile-time form
/// `projected_hessian<P>(e)` that every energy type provides.
///
/// Compile cost: `projected_hessian(e, strategy)` must be able to run every strategy, so it
/// instantiates all six, among them `numerical`'s 12×12 Eigen eigensolver (most of a
/// translation unit's compile time). `projected_hessian<Projection::analytic>(e)` compiles
/// only the strategy it names; a program that links `pce::precompiled` gets the run-time
/// form for float, double and long double already compiled (`docs/conventions.md`).
#pragma once

#include <pce/core/enum_names.hpp>
#include <pce/core/types.hpp>

#include <type_traits>

namespace pce {

/// How `projected_hessian` makes the Hessian positive semidefinite (`docs/math.md`).
enum class Projection {
  none,          ///< the exact Hessian ∇²E, not PSD in general
  analytic,      ///< Jᵀ [max(ψ″,0) ggᵀ + Σ max(σψ′λ,0) qqᵀ] J: clamp the closed-form eigenvalues
  numerical,     ///< V max(Λ,0) Vᵀ of the exact 12×12 Hessian: the true nearest PSD matrix
  gauss_newton,  ///< max(ψ″,0) ∇L ∇Lᵀ: drops the length's curvature
  abs,           ///< Jᵀ [|ψ″| ggᵀ + Σ |σψ′λ| qqᵀ] J: flip negative eigenvalues instead
  exact,         ///< the same matrix as `numerical` (the nearest PSD matrix in x-space), through
                 ///< the Hessian's rank ≤ 5 structure: a ≤ 5×5 eigenproblem, no 12×12 eigensolve
};

/// The strategies' names (`pce-probe`'s and the scene's `hessian`, Python's
/// `pce.PROJECTIONS`), in enumerator order.
inline constexpr EnumNames<Projection, 6> kProjectionNames{{
    {Projection::none, "none"},
    {Projection::analytic, "analytic"},
    {Projection::numerical, "numerical"},
    {Projection::gauss_newton, "gauss_newton"},
    {Projection::abs, "abs"},
    {Projection::exact, "exact"},
}};

/// The table of `Projection`'s names (for `name_of` and `parse`).
constexpr const EnumNames<Projection, 6>& enum_names(Projection) { return kProjectionNames; }

/// Name of a strategy (`kProjectionNames`); "unknown" for a value outside the enumeration.
inline const char* to_string(Projection p) {
  const std::string_view name = name_of(p);
  return name.empty() ? "unknown" : name.data();
}

/// A strategy as a type: `ProjectionConstant<P>::value == P`.
template <Projection P> using ProjectionConstant = std::integral_constant<Projection, P>;

/// Calls `f(ProjectionConstant<strategy>{})` and returns its result: the one switch from a
/// run-time strategy to the compile-time forms (a value outside the enumeration is `none`).
/// In device code `numerical`, whose 12×12 eigensolver is Eigen's host-only one, runs as
/// `exact`: the same matrix, the nearest PSD one, through the Hessian's rank ≤ 5 structure
/// (they agree to rounding, `docs/cuda.md`).
template <class F> PCE_HOST_DEVICE decltype(auto) with_projection(Projection strategy, F&& f) {
  switch (strategy) {
    case Projection::analytic:
      return f(ProjectionConstant<Projection::analytic>{});
    case Projection::numerical:
#if defined(__CUDA_ARCH__)
      return f(ProjectionConstant<Projection::exact>{});
#else
      return f(ProjectionConstant<Projection::numerical>{});
#endif
    case Projection::gauss_newton:
      return f(ProjectionConstant<Projection::gauss_newton>{});
    case Projection::abs:
      return f(ProjectionConstant<Projection::abs>{});
    case Projection::exact:
      return f(ProjectionConstant<Projection::exact>{});
    case Projection::none:
      break;
  }
  return f(ProjectionConstant<Projection::none>{});
}

}  // namespace pce

// SPDX-License-Identifier: MIT
/// @file
/// Precompiled instantiations: the heaviest templates of the core (the run-time dispatch of
/// `projected_hessian` for every energy type, `project_psd`'s Eigen eigensolvers and the
/// numerical projection of volumes) compiled once into the optional library
/// `pce::precompiled`, for float, double and long double.
///
/// A target that links `pce::precompiled` gets `PCE_PRECOMPILED` defined, and each header
/// then declares those instantiations `extern template`: a file that includes them compiles
/// none of those bodies, and calls them out of line instead. The results are the same bits
/// (the same source, compiled without fast-math). Without the macro every header is
/// self-contained, as a header-only library is.
#pragma once

/// Applies `M(EXTERN, Scalar)` to each scalar type `pce::precompiled` is built for.
#define PCE_PRECOMPILED_SCALARS(M, EXTERN) \
  M(EXTERN, float)                         \
  M(EXTERN, double)                        \
  M(EXTERN, long double)

/// Declares (`PCE_PRECOMPILED` defined) the instantiations `M` lists as compiled elsewhere.
/// A CUDA translation unit declares none: its device code needs the bodies, and `pce::precompiled`
/// is host code.
#if defined(PCE_PRECOMPILED) && !defined(__CUDACC__)
#define PCE_DECLARE_PRECOMPILED(M) PCE_PRECOMPILED_SCALARS(M, extern)
#else
#define PCE_DECLARE_PRECOMPILED(M)
#endif

// SPDX-License-Identifier: MIT
/// @file
/// Edge-edge pair `x = (ea0, ea1, eb0, eb1)`: edge vectors `e0 = ea1 − ea0`,
/// `e1 = eb1 − eb0`, `e2 = eb0 − ea0`, so the signed length is `l = (eb0 − ea0)·n̂` with
/// `n = (ea1 − ea0) × (eb1 − eb0)` (`docs/conventions.md`), the distance between the two
/// infinite lines with a sign. Same vertex roles as the paper's supplement (v0..v3).
#pragma once

#include <pce/frames/frame.hpp>

namespace pce {

template <class Scalar> struct PairEnergy;

/// Tag type for the edge-edge pair kind.
struct EdgeEdge {
  /// The kind's name, as `pce-probe` and the tests spell it.
  static constexpr const char* name = "edge_edge";
  static constexpr int dofs = 12;       ///< coordinates: four points
  static constexpr int frame_dofs = 9;  ///< frame coordinates (e0, e1⊥, e2⊥)
  /// The evaluated energy of this kind (`energy/pair_energy.hpp`).
  template <class Scalar> using Energy = PairEnergy<Scalar>;

  /// The edge map `D`: rows e0, e1, e2 as combinations of the four vertices.
  template <class Scalar> PCE_HOST_DEVICE static Mat34<Scalar> edge_map() {
    Mat34<Scalar> D;
    D << Scalar(-1), Scalar(1), Scalar(0), Scalar(0),  //
        Scalar(0), Scalar(0), Scalar(-1), Scalar(1),   //
        Scalar(-1), Scalar(0), Scalar(1), Scalar(0);
    return D;
  }

  /// Builds the reduced frame of `x = (ea0, ea1, eb0, eb1)`; `invalid_input` for
  /// non-finite or absurd coordinates, `degenerate` for parallel or zero-length edges; on
  /// failure `f` is untouched.
  /// `Out` may also be `detail::GradientFrame`, the part of the frame `value_gradient` needs.
  template <class Scalar, class Out>
  PCE_HOST_DEVICE PCE_ALWAYS_INLINE static Status frame(const Vec12<Scalar>& x, Out& f) {
    return detail::frame_from_vertices(x, edge_map<Scalar>(), f);
  }
};

/// Reduced frame of an edge-edge pair; see `EdgeEdge::frame`.
template <class Scalar> PCE_HOST_DEVICE Status edge_edge_frame(const Vec12<Scalar>& x, Frame<Scalar>& f) {
  return EdgeEdge::frame(x, f);
}

}  // namespace pce

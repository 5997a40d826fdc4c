// SPDX-License-Identifier: MIT
/// @file
/// Vertex-face pair `x = (p, t0, t1, t2)`: edge vectors `e0 = t1 − t0`, `e1 = t2 − t0`,
/// `e2 = p − t0`, so the signed length is `l = (p − t0)·n̂` with
/// `n = (t1 − t0) × (t2 − t0)`: positive on the side the triangle's right-hand normal
/// points to (`docs/conventions.md`). The paper (supplement Sec. 1) bases the frame at its
/// v2 instead; the length and every derivative are the same function of the 12 coordinates.
#pragma once

#include <pce/frames/frame.hpp>

namespace pce {

template <class Scalar> struct PairEnergy;

/// Tag type for the vertex-face pair kind.
struct VertexFace {
  /// The kind's name, as `pce-probe` and the tests spell it.
  static constexpr const char* name = "vertex_face";
  static constexpr int dofs = 12;       ///< coordinates: four points
  static constexpr int frame_dofs = 9;  ///< frame coordinates (e0, e1⊥, e2⊥)
  /// The evaluated energy of this kind (`energy/pair_energy.hpp`).
  template <class Scalar> using Energy = PairEnergy<Scalar>;

  /// The edge map `D`: rows e0, e1, e2 as combinations of the four vertices.
  template <class Scalar> PCE_HOST_DEVICE static Mat34<Scalar> edge_map() {
    Mat34<Scalar> D;
    D << Scalar(0), Scalar(-1), Scalar(1), Scalar(0),  //
        Scalar(0), Scalar(-1), Scalar(0), Scalar(1),   //
        Scalar(1), Scalar(-1), Scalar(0), Scalar(0);
    return D;
  }

  /// Builds the reduced frame of `x = (p, t0, t1, t2)`; `invalid_input` for non-finite or
  /// absurd coordinates, `degenerate` for a zero-area triangle; on failure `f` is untouched.
  /// `Out` may also be `detail::GradientFrame`, the part of the frame `value_gradient` needs.
  template <class Scalar, class Out>
  PCE_HOST_DEVICE PCE_ALWAYS_INLINE static Status frame(const Vec12<Scalar>& x, Out& f) {
    return detail::frame_from_vertices(x, edge_map<Scalar>(), f);
  }
};

/// Reduced frame of a vertex-face pair; see `VertexFace::frame`.
template <class Scalar> PCE_HOST_DEVICE Status vertex_face_frame(const Vec12<Scalar>& x, Frame<Scalar>& f) {
  return VertexFace::frame(x, f);
}

}  // namespace pce

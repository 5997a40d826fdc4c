// SPDX-License-Identifier: MIT
/// @file
/// Closest-feature evaluation of a vertex-face or edge-edge candidate (`docs/math.md` §10):
/// the pair is classified by the features that hold its closest points, and the energy of
/// the *distance between the primitives* (not the plane or line distance) is evaluated
/// with the matching kind:
///
/// | candidate   | closest features                          | kind evaluated |
/// |-------------|-------------------------------------------|----------------|
/// | vertex-face | p over the triangle's interior            | `point_plane` (VertexFace, unsigned) |
/// |             | p beside an edge                          | `point_edge`   |
/// |             | p beyond a corner                         | `point_point`  |
/// | edge-edge   | both closest points inside the segments   | `line_line` (EdgeEdge, unsigned) |
/// |             | an endpoint and the other segment's inside| `point_edge`   |
/// |             | two endpoints                             | `point_point`  |
///
/// Parallel edges and zero-area triangles are no special case: their closest points lie on
/// an endpoint or an edge, so a point kind is chosen. The distance is continuous across
/// every region boundary and so is its gradient (C¹); the Hessian jumps there (the point
/// kinds carry the curvature `1/d` of the line or sphere around the feature, the plane
/// kinds none). Closest-feature evaluation is **unsigned**: a `SignedLength` request
/// returns `invalid_input`. A distance of exactly 0 on a point kind (p on an edge or on a
/// vertex) has no direction and returns `degenerate`.
#pragma once

#include <pce/energy/pair_energy.hpp>
#include <pce/energy/point_edge_energy.hpp>
#include <pce/energy/point_point_energy.hpp>

#include <array>

namespace pce {

/// The closest features of a pair, i.e. which kind was evaluated.
enum class Feature {
  point_plane,  ///< vertex-face, vertex over the face interior: VertexFace with |l|
  line_line,    ///< edge-edge, closest points inside both segments: EdgeEdge with |l|
  point_edge,   ///< a point and the inside of an edge: PointEdge
  point_point,  ///< two points: PointPoint
};

/// Name of a feature, as `pce-probe` prints it.
PCE_HOST_DEVICE inline const char* to_string(Feature f) {
  switch (f) {
    case Feature::point_plane:
      return "point_plane";
    case Feature::line_line:
      return "line_line";
    case Feature::point_edge:
      return "point_edge";
    case Feature::point_point:
      return "point_point";
  }
  return "unknown";
}

/// A closest-feature evaluation: the feature, which of the pair's four points play the
/// roles of the evaluated kind, and that kind's evaluated energy (only the one named by
/// `feature` is meaningful).
template <class Scalar> struct ClosestFeatureEnergy {
  /// The kind that holds the closest points, and so is evaluated.
  Feature feature;
  /// Point indices (0..3 in the 12-vector) of the evaluated kind's points: (p, e0, e1) for
  /// `point_edge`, (p, q, −) for `point_point`, unused for the plane kinds.
  std::array<int, 3> points;
  PairEnergy<Scalar> plane;        ///< `point_plane` / `line_line`
  PointEdgeEnergy<Scalar> edge;    ///< `point_edge`
  PointPointEnergy<Scalar> point;  ///< `point_point`
  Scalar length{};                 ///< the distance between the primitives
  PenaltyDerivatives<Scalar> psi;  ///< ψ, ψ′, ψ″ at `length`
};

namespace detail {

/// Closest feature of point `p` to segment (a, b), all relative and rescaled: sets the
/// feature and its points and returns the squared distance.
template <class Scalar> PCE_HOST_DEVICE Scalar point_segment(const Vec3<Scalar>& p, const Vec3<Scalar>& a,
                                                             const Vec3<Scalar>& b, int ip, int ia, int ib,
                                                             Feature& feature, std::array<int, 3>& points) {
  const Vec3<Scalar> e = b - a, r = p - a;
  const Scalar ee = e.squaredNorm();
  const Scalar re = r.dot(e);
  if (ee == Scalar(0) || re <= Scalar(0)) {
    feature = Feature::point_point;
    points = {ip, ia, -1};
    return r.squaredNorm();
  }
  if (re >= ee) {
    feature = Feature::point_point;
    points = {ip, ib, -1};
    return (p - b).squaredNorm();
  }
  feature = Feature::point_edge;
  points = {ip, ia, ib};
  return e.cross(r).squaredNorm() / ee;
}

/// Classifies the pair by its closest features (`VertexFace` or `EdgeEdge` layout).
/// `plane_inside` says whether the plane kind's frame exists and its closest point lies
/// inside the primitives, `plane_l` is then its length l. The plane kind is chosen when its
/// foot is inside *and* |l| is not above the nearest point-segment distance (to 64 ε): for a
/// foot inside, |l| is the smallest of them exactly, so the rule changes nothing where the
/// frame is accurate, and where it is not (a triangle or an edge pair at an angle below the
/// scalar's rounding, whose normal is noise) a wrong |l| cannot win over the segments.
template <class Pair, class Scalar> PCE_HOST_DEVICE void classify(const Vec12<Scalar>& x, bool plane_inside,
                                                                  const Scalar& plane_l, Feature& feature,
                                                                  std::array<int, 3>& points) {
  constexpr bool vf = std::is_same_v<Pair, VertexFace>;
  // Points relative to point 0, exactly rescaled so squared distances cannot overflow.
  Vec3<Scalar> y[4];
  Scalar big = Scalar(0);
  for (int j = 1; j < 4; ++j) {
    y[j] = x.template segment<3>(3 * j) - x.template segment<3>(0);
    big = (std::max)(big, y[j].cwiseAbs().maxCoeff());
  }
  y[0].setZero();
  Scalar l_scaled = plane_l;
  if (big > Scalar(0)) {
    const PowerOfTwoScale<Scalar> sc(big);
    for (int j = 1; j < 4; ++j) y[j] = sc.down(y[j]);
    l_scaled = sc.down(plane_l);
  }
  // (point, segment start, segment end) candidates, in a fixed order (ties: first wins).
  static constexpr int vf_cand[3][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}};
  static constexpr int ee_cand[4][3] = {{0, 2, 3}, {1, 2, 3}, {2, 0, 1}, {3, 0, 1}};
  const int count = vf ? 3 : 4;
  Scalar best = Scalar(0);
  for (int c = 0; c < count; ++c) {
    const int* k = vf ? vf_cand[c] : ee_cand[c];
    Feature f;
    std::array<int, 3> pts;
    const Scalar d2 = point_segment(y[k[0]], y[k[1]], y[k[2]], k[0], k[1], k[2], f, pts);
    if (c == 0 || d2 < best) {
      best = d2;
      feature = f;
      points = pts;
    }
  }
  // (64 ε of slack: far above the face, the plane and the nearest edge distances agree to
  // rounding — 1e4 and 1e4 + 4.5e-6 in float — and the plane is then the right kind.)
  if (plane_inside && l_scaled * l_scaled <= best * (Scalar(1) + Scalar(64) * Constants<Scalar>::epsilon())) {
    feature = vf ? Feature::point_plane : Feature::line_line;
    points = {-1, -1, -1};
  }
}

/// The sub-vector of the points `idx` of `x`.
template <int N, class Scalar>
PCE_HOST_DEVICE VecN<Scalar, 3 * N> gather(const Vec12<Scalar>& x, const std::array<int, 3>& idx) {
  VecN<Scalar, 3 * N> y;
  for (int j = 0; j < N; ++j) y.template segment<3>(3 * j) = x.template segment<3>(3 * idx[j]);
  return y;
}

/// Embeds a gradient on the points `idx` into the 12 coordinates (zeros elsewhere).
template <int N, class Scalar>
PCE_HOST_DEVICE Vec12<Scalar> scatter(const VecN<Scalar, 3 * N>& g, const std::array<int, 3>& idx) {
  Vec12<Scalar> out = Vec12<Scalar>::Zero();
  for (int j = 0; j < N; ++j) out.template segment<3>(3 * idx[j]) = g.template segment<3>(3 * j);
  return out;
}

/// Embeds a Hessian on the points `idx` into the 12 coordinates (zeros elsewhere). The
/// embedding is a coordinate selection, so it commutes with every PSD projection.
template <int N, class Scalar>
PCE_HOST_DEVICE Mat12<Scalar> scatter(const MatN<Scalar, 3 * N>& H, const std::array<int, 3>& idx) {
  Mat12<Scalar> out = Mat12<Scalar>::Zero();
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) out.template block<3, 3>(3 * idx[i], 3 * idx[j]) = H.template block<3, 3>(3 * i, 3 * j);
  return out;
}

}  // namespace detail

/// Whether the frame's closest points (the foot (1 − β − γ, β, γ) on the triangle; the points
/// ea0 + β e0 and eb0 − γ e1 on the two lines) are really |l| apart, to √ε of the pair's
/// size. They are wherever the frame is accurate; where it is not — edges or a sliver
/// triangle at an angle below the scalar's rounding, whose normal is noise — β and γ are
/// noise too and can claim "inside" for two collinear disjoint edges whose line distance l
/// is ~0 while the edges are far apart. Such a claim is refused, and the point-segment
/// distances, which are well conditioned, decide.
template <class Pair, class Scalar>
PCE_HOST_DEVICE bool foot_consistent(const Vec12<Scalar>& x, const Frame<Scalar>& f) {
  using std::abs;
  using std::sqrt;
  const Vec3<Scalar> p0 = x.template segment<3>(0), p1 = x.template segment<3>(3), p2 = x.template segment<3>(6),
                     p3 = x.template segment<3>(9);
  Vec3<Scalar> gap;
  if constexpr (std::is_same_v<Pair, VertexFace>)  // p − foot
    gap = (p0 - p1) - f.beta * (p2 - p1) - f.gamma * (p3 - p1);
  else  // (eb0 − γ e1) − (ea0 + β e0)
    gap = (p2 - p0) - f.gamma * (p3 - p2) - f.beta * (p1 - p0);
  Scalar size = Scalar(0);
  for (int j = 1; j < 4; ++j)
    size = (std::max)(size, Scalar((x.template segment<3>(3 * j) - p0).cwiseAbs().maxCoeff()));
  return abs(Scalar(gap.norm()) - abs(f.l)) <= sqrt(Constants<Scalar>::epsilon()) * size;
}

/// Classifies the candidate `x` (`Pair` = `VertexFace`: p, t0, t1, t2; `EdgeEdge`: ea0,
/// ea1, eb0, eb1) by its closest features and evaluates that kind with the unsigned
/// distance. Statuses: `invalid_input` for bad coordinates or parameters or a
/// `SignedLength`; `degenerate` only when the distance is exactly 0 on a point kind;
/// `out_of_domain`, `overflow` as for every kind. `out` is written only on `ok`.
template <class Pair, class Scalar, class Length, class Penalty>
PCE_HOST_DEVICE Status closest_feature_energy(const Vec12<Scalar>& x, const Length&, const Penalty& penalty,
                                              ClosestFeatureEnergy<Scalar>& out) {
  static_assert(std::is_same_v<Pair, VertexFace> || std::is_same_v<Pair, EdgeEdge>,
                "closest-feature evaluation is for vertex-face and edge-edge candidates");
  if (is_signed_length<Length>() || !penalty_valid(penalty) || !detail::coordinates_valid(x))
    return Status::invalid_input;
  ClosestFeatureEnergy<Scalar> e;
  Frame<Scalar> f;
  bool inside = false;
  Scalar l = Scalar(0);
  if (Pair::frame(x, f) == Status::ok) {
    l = f.l;
    if constexpr (std::is_same_v<Pair, VertexFace>)  // barycentrics of the foot: (1 − β − γ, β, γ)
      inside = f.beta >= Scalar(0) && f.gamma >= Scalar(0) && f.beta + f.gamma <= Scalar(1);
    else  // closest points ea0 + β e0 and eb0 − γ e1
      inside = f.beta >= Scalar(0) && f.beta <= Scalar(1) && f.gamma <= Scalar(0) && f.gamma >= Scalar(-1);
    inside = inside && foot_consistent<Pair>(x, f);
  }
  detail::classify<Pair>(x, inside, l, e.feature, e.points);
  Status s = Status::ok;
  switch (e.feature) {
    case Feature::point_plane:
    case Feature::line_line:
      s = pair_energy<Pair>(x, UnsignedLength{}, penalty, e.plane);
      e.length = e.plane.length;
      e.psi = e.plane.psi;
      break;
    case Feature::point_edge:
      s = pair_energy<PointEdge>(detail::gather<3>(x, e.points), UnsignedLength{}, penalty, e.edge);
      e.length = e.edge.length;
      e.psi = e.edge.psi;
      break;
    case Feature::point_point:
      s = pair_energy<PointPoint>(detail::gather<2>(x, e.points), UnsignedLength{}, penalty, e.point);
      e.length = e.point.length;
      e.psi = e.point.psi;
      break;
  }
  if (s != Status::ok) return s;
  out = e;
  return Status::ok;
}

/// ∇E on all 12 coordinates (zeros on points the evaluated kind does not use).
template <class Scalar> PCE_HOST_DEVICE Vec12<Scalar> energy_gradient(const ClosestFeatureEnergy<Scalar>& e) {
  switch (e.feature) {
    case Feature::point_edge:
      return detail::scatter<3>(energy_gradient(e.edge), e.points);
    case Feature::point_point:
      return detail::scatter<2>(energy_gradient(e.point), e.points);
    default:
      return energy_gradient(e.plane);
  }
}

/// Exact ∇²E on all 12 coordinates.
template <class Scalar> PCE_HOST_DEVICE Mat12<Scalar> energy_hessian(const ClosestFeatureEnergy<Scalar>& e) {
  switch (e.feature) {
    case Feature::point_edge:
      return detail::scatter<3>(energy_hessian(e.edge), e.points);
    case Feature::point_point:
      return detail::scatter<2>(energy_hessian(e.point), e.points);
    default:
      return energy_hessian(e.plane);
  }
}

/// PSD Hessian by the strategy `P`, chosen at compile time (only that strategy is
/// compiled), on all 12 coordinates.
template <Projection P, class Scalar>
PCE_HOST_DEVICE Mat12<Scalar> projected_hessian(const ClosestFeatureEnergy<Scalar>& e) {
  switch (e.feature) {
    case Feature::point_edge:
      return detail::scatter<3>(projected_hessian<P>(e.edge), e.points);
    case Feature::point_point:
      return detail::scatter<2>(projected_hessian<P>(e.point), e.points);
    default:
      return projected_hessian<P>(e.plane);
  }
}

/// PSD Hessian by the strategy chosen at run time (compiles every strategy:
/// `energy/projection.hpp`), on all 12 coordinates.
template <class Scalar>
PCE_HOST_DEVICE Mat12<Scalar> projected_hessian(const ClosestFeatureEnergy<Scalar>& e, Projection strategy) {
  return with_projection(strategy, [&e](auto p) { return projected_hessian<decltype(p)::value>(e); });
}

/// The closed-form frame-space eigenvalues of the evaluated kind (9, 6 or 3 of them,
/// ascending), copied into the first `count` entries.
template <class Scalar> struct FeatureEigenvalues {
  /// The eigenvalues in the first `count` entries, zeros after them.
  Vec9<Scalar> values;
  /// 9 (`point_plane`, `line_line`), 6 (`point_edge`) or 3 (`point_point`).
  int count;
};
/// The frame-space eigenvalues of `e.feature`'s kind, from that kind's `energy_eigensystem`.
template <class Scalar>
PCE_HOST_DEVICE FeatureEigenvalues<Scalar> feature_eigenvalues(const ClosestFeatureEnergy<Scalar>& e) {
  FeatureEigenvalues<Scalar> r;
  r.values.setZero();
  switch (e.feature) {
    case Feature::point_edge:
      r.count = 6;
      r.values.template head<6>() = energy_eigensystem(e.edge).values;
      break;
    case Feature::point_point:
      r.count = 3;
      r.values.template head<3>() = energy_eigensystem(e.point).values;
      break;
    default:
      r.count = 9;
      r.values = energy_eigensystem(e.plane).values;
  }
  return r;
}

/// The instantiations `pce::precompiled` compiles (`core/precompiled.hpp`).
// (EXTERN is `extern` or nothing and S a type: neither can be parenthesised.)
// NOLINTBEGIN(bugprone-macro-parentheses)
#define PCE_CLOSEST_FEATURE_INSTANCES(EXTERN, S) \
  EXTERN template Mat12<S> projected_hessian<S>(const ClosestFeatureEnergy<S>&, Projection);
// NOLINTEND(bugprone-macro-parentheses)
PCE_DECLARE_PRECOMPILED(PCE_CLOSEST_FEATURE_INSTANCES)

}  // namespace pce

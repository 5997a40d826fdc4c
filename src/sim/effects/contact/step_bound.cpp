// SPDX-License-Identifier: MIT
// The step bound of self contact (step_bound.hpp), compiled once for vertex-face and
// edge-edge pairs.
#include "step_bound.hpp"

#include "ordered_chunks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pce::sim::contact {

template <bool VF> double StepBound<VF>::max_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) {
  segment_valid_ = false;
  // The validity limit first (cover_step, called before, has queried again where the whole
  // step would have left the set). The same pass lists the candidates that can be active
  // anywhere on x + s dx, s ∈ [0, t_valid] (t_valid bounds what this returns, hence every
  // line-search trial): a pair whose distance at x, less t_valid (ma + mb), is at least its
  // reach is inactive on the whole segment.
  const double t_valid = candidates_->step_limit(x, dx);
  const double scale = std::max(x.cwiseAbs().maxCoeff(), 1.0);
  segment_slack_ = 8 * kSegmentTolerance * scale;
  floor_slack_ = kFloorRounding * scale;
  const double largest_floor = classifier_->largest_floor();
  candidates_->set_floor(largest_floor > 0 ? 2 * largest_floor + 2 * floor_slack_ : 0.0);
  const long n = static_cast<long>(candidates_->size());
  constexpr long chunk = 2048;
  const std::size_t chunks = chunk_count(n, chunk);
  if (segments_.size() < chunks) segments_.resize(chunks);
  if (held_chunks_.size() < chunks) held_chunks_.resize(chunks);
  const double t = min_over_chunks(n, chunk, t_valid, [&](std::size_t c, long begin, long end, double& running) {
    std::vector<std::size_t>& my_segment = segments_[c];
    my_segment.clear();
    held_chunks_[c].clear();
    for (long k = begin; k < end; ++k)
      bound_pair(x, dx, static_cast<std::size_t>(k), t_valid, running, my_segment, held_chunks_[c]);
  });
  join_chunks(segments_, chunks, segment_);
  join_chunks(held_chunks_, chunks, held_);
  segment_x_ = x;
  segment_dx_ = dx;
  segment_t_ = t_valid;
  segment_valid_ = true;
  candidates_->record_step(t_valid, t);
  return std::max(t, 0.0);
}

template <bool VF> void StepBound<VF>::bound_pair(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, std::size_t k,
                                                  double t_valid, double& t, std::vector<std::size_t>& segment,
                                                  std::vector<FloorLimit>& held) const {
  using Geometry = PairGeometry<VF>;
  using Kind = std::conditional_t<VF, VertexFace, EdgeEdge>;
  const double reach = classifier_->reach_of(k);
  // Two questions, each asked at three levels of detail, reading more only while the
  // answer is open: is the pair inactive on the whole segment (`far`: a lower bound on its
  // distance at x, less t_valid times a bound on ma + mb, is at least its reach), and can it
  // not lower t (the same bounds against t)? First from its meshes' drift and step reach
  // (stays_beyond, cannot_limit), then from its primitives' spreads (primitive_lower_bound,
  // step_bound), then from its four vertices.
  bool far = candidates_->stays_beyond(k, reach, t_valid, segment_slack_);
  const bool cannot_limit = candidates_->cannot_limit(k, t_valid);
  if (far && cannot_limit) return;
  {
    const double motion = candidates_->step_bound(k), bound = candidates_->primitive_lower_bound(k);
    const bool far_too = far || bound - reach * (1 + 1e-9) >= (t_valid * motion + segment_slack_) * (1 + 1e-9);
    const bool no_limit =
        cannot_limit || !(motion > 0) || candidates_->clearance(bound) >= std::min(t, t_valid) * motion * (1 + 1e-9);
    if (far_too && no_limit) return;
  }
  const auto v = candidates_->vertices(k);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int j = 0; j < 4; ++j) mean += dx.col(v[static_cast<std::size_t>(j)]);
  mean *= 0.25;
  double ma = 0, mb = 0;  // largest motion on each primitive relative to p̄
  for (int j = 0; j < 4; ++j) {
    const double d = (dx.col(v[static_cast<std::size_t>(j)]) - mean).norm();
    double& m = j < Geometry::first_side_count() ? ma : mb;
    m = std::max(m, d);
  }
  const double reach_along = (t_valid * (ma + mb) + segment_slack_) * (1 + 1e-9);
  const auto beyond_along = [&](double lower_bound) { return lower_bound - reach * (1 + 1e-9) >= reach_along; };
  far = far || beyond_along(candidates_->lower_bound(k, v));
  const bool may_limit =
      !cannot_limit && ma + mb > 0 && !candidates_->cannot_lower(k, v, ma + mb, std::min(t, t_valid));
  if (far && !may_limit) return;
  const Vec12<double> xp = Geometry::gather(x, v);
  // The distance is at least distance_lower_bound, so a pair whose bound already allows the
  // smaller of the running minimum and the validity bound cannot lower the result: it is the
  // same without the pair's distance.
  const double bound = Geometry::distance_lower_bound(xp);
  far = far || beyond_along(bound);
  if (!far) segment.push_back(k);
  if (!may_limit || candidates_->clearance(bound) >= std::min(t, t_valid) * (ma + mb)) return;
  ClosestFeatureEnergy<double> ce;
  const QuadraticPenalty probe{1.0, 0.0};
  if (closest_feature_energy<Kind>(xp, UnsignedLength{}, probe, ce) != Status::ok) return;
  candidates_->tighten(k, v, ce.length);
  const double d0 = ce.length, floor = classifier_->floor_of(k), cap = std::min(t, t_valid);
  // A pair whose tenth would be below twice its floor (with twice the rounding allowance
  // δ) keeps that instead, one closer than that its floor + δ, each bounded along its
  // separating direction less δ: no pair that starts the step at or above its floor comes
  // below it, and a pair pressed in stops at twice its floor first.
  if (const double g = floor_gap(d0, floor, floor_slack_); g > 0) {
    const double tk = directional_advance(xp, Geometry::gather(dx, v), g, floor_slack_, cap);
    if (tk < cap) held.push_back({k, g, d0});
    t = std::min(t, tk);
    return;
  }
  t = std::min(t, advance(xp, Geometry::gather(dx, v), d0, ma + mb, cap));
}

template <bool VF>
bool StepBound<VF>::separation(const Vec12<double>& xp, const Vec12<double>& dxp, double& S, double& r) {
  using Kind = std::conditional_t<VF, VertexFace, EdgeEdge>;
  double length = 0;
  if (!closest_distance<VF>(xp, length) || !(length > 0)) return false;
  // ∇L with a penalty active at L (ψ′ < 0): the first primitive's part sums to ψ′ m, m the
  // unit vector from the second primitive's closest point to the first's.
  ClosestFeatureEnergy<double> cg;
  if (closest_feature_energy<Kind>(xp, UnsignedLength{}, QuadraticPenalty{1.0, 2 * length}, cg) != Status::ok)
    return false;
  const Vec12<double> g = energy_gradient(cg);
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (int j = 0; j < PairGeometry<VF>::first_side_count(); ++j) m -= g.template segment<3>(3 * j);
  const double norm = m.norm();
  if (!(norm > 0) || !std::isfinite(norm)) return false;
  m /= norm;
  double low_a = std::numeric_limits<double>::infinity(), high_b = -low_a;
  double slow_a = low_a, fast_b = -low_a;
  for (int j = 0; j < 4; ++j) {
    const double at = m.dot(xp.template segment<3>(3 * j)), rate = m.dot(dxp.template segment<3>(3 * j));
    if (j < PairGeometry<VF>::first_side_count()) {
      low_a = std::min(low_a, at);
      slow_a = std::min(slow_a, rate);
    } else {
      high_b = std::max(high_b, at);
      fast_b = std::max(fast_b, rate);
    }
  }
  S = low_a - high_b;
  r = fast_b - slow_a;
  return std::isfinite(S) && std::isfinite(r);
}

template <bool VF> double StepBound<VF>::directional_advance(const Vec12<double>& xp, const Vec12<double>& dxp,
                                                             double g, double slack, double cap) {
  return advance_to_gap(
      [&](double t, double& S, double& r) { return separation(Vec12<double>(xp + t * dxp), dxp, S, r); }, g, slack,
      cap);
}

template <bool VF>
double StepBound<VF>::advance(const Vec12<double>& xp, const Vec12<double>& dxp, double d0, double lp, double cap) {
  using Kind = std::conditional_t<VF, VertexFace, EdgeEdge>;
  const double g = 0.1 * d0;
  double t = 0.9 * d0 / lp;
  const QuadraticPenalty probe{1.0, 0.0};
  for (int round = 0; round < 32 && t < cap; ++round) {
    ClosestFeatureEnergy<double> ce;
    if (closest_feature_energy<Kind>(Vec12<double>(xp + t * dxp), UnsignedLength{}, probe, ce) != Status::ok) break;
    const double step = 0.9 * (ce.length - g) / lp;
    if (!(step > 1e-3 * t)) break;
    t += step;
  }
  return t;
}

template <bool VF> const std::vector<std::size_t>* StepBound<VF>::segment_at(const Eigen::Matrix3Xd& x) const {
  if (!segment_valid_ || x.cols() != segment_x_.cols()) return nullptr;
  Eigen::Index row = 0, col = 0;
  const double largest = segment_dx_.cwiseAbs().maxCoeff(&row, &col);
  const double s = largest > 0 ? (x(row, col) - segment_x_(row, col)) / segment_dx_(row, col) : 0.0;
  if (!(s >= 0 && s <= segment_t_ * (1 + 1e-12))) return nullptr;
  const double tolerance = kSegmentTolerance * std::max(segment_x_.cwiseAbs().maxCoeff(), 1.0);
  return ((x - segment_x_) - s * segment_dx_).cwiseAbs().maxCoeff() <= tolerance ? &segment_ : nullptr;
}

template class StepBound<true>;
template class StepBound<false>;

}  // namespace pce::sim::contact

// SPDX-License-Identifier: MIT
// The step bounds of an obstacle-contact effect (obstacle_bounds.hpp).
#include "obstacle_bounds.hpp"

#include "effects/contact/ordered_chunks.hpp"

#include <algorithm>
#include <cmath>

namespace pce::sim::obstacle {

double ObstacleBounds::line_search_bound(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) {
  held_.clear();
  const bool floored = floor_ > 0;
  if (!barrier_ && !floored) return 1.0;
  slack_ = kFloorRounding * std::max(x.cwiseAbs().maxCoeff(), 1.0);
  const double above = 2 * floor_ + 2 * slack_;  // no floor gap is larger
  const std::size_t chunks = contact::chunk_count(x.cols(), kChunk);
  if (held_chunks_.size() < chunks) held_chunks_.resize(chunks);
  const double t = contact::min_over_chunks(x.cols(), kChunk, 1.0, [&](std::size_t c, long begin, long end, double& t) {
    held_chunks_[c].clear();
    for (long i = begin; i < end; ++i) {
      if (!set_->takes_part(i)) continue;  // inside a volume
      const double step = dx.col(i).norm();
      if (!(step > 0)) continue;
      const Eigen::Vector3d p = x.col(i);
      bool barrier_limits = false;  // the barrier's bound of the pair visited next
      set_->near(
          p,
          [&](double lower) {  // d > |Δx|: the barrier's t = 1 is safe; d − |Δx| ≥ 2F + 2δ: the floor's
            barrier_limits = barrier_ && !(lower > step);
            return !barrier_limits && (!floored || lower - step >= above);
          },
          [&](std::size_t k, const SurfaceDistance& s) {
            bound_pair(p, dx.col(i), i, k, s.distance, barrier_limits, t, held_chunks_[c]);
          });
    }
  });
  contact::join_chunks(held_chunks_, chunks, held_);
  return t;
}

void ObstacleBounds::bound_pair(const Eigen::Vector3d& p, const Eigen::Vector3d& dxi, Eigen::Index i, std::size_t k,
                                double d0, bool barrier_limits, double& t, std::vector<FloorLimit>& held) const {
  if (!(d0 > 0)) return;  // inside: outside the domain already, nothing to keep
  const double g = floor_gap(d0, floor_, slack_);
  if (g > 0) {
    const double cap = t;
    const double step = dxi.norm();
    const bool convex = set_->convex(k);
    const double tk = advance_to_gap(
        [&](double s, double& S, double& r) {
          const SurfaceDistance at = set_->distance(k, p + s * dxi);
          S = at.distance;
          r = convex ? -at.normal.dot(dxi) : step;
          return std::isfinite(S) && std::isfinite(r);
        },
        g, slack_, cap);
    if (tk < cap) held.push_back({set_->pair(i, k), g, d0});
    t = std::min(t, tk);
    return;
  }
  if (barrier_limits) t = std::min(t, 0.9 * d0 / dxi.norm());
}

double ObstacleBounds::move_limit(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, Eigen::Index i) const {
  if (!set_->takes_part(i)) return 1.0;  // inside a volume
  const double step = dx.col(i).norm();
  if (!(step > 0)) return 1.0;
  double t = 1.0;
  set_->near(
      x.col(i), [&](double lower) { return lower > 0 && room(lower) >= step; },  // the whole move keeps the room
      [&](std::size_t, const SurfaceDistance& s) {
        if (s.distance > 0) t = std::min(t, room(s.distance) / step);
      });
  return t;
}

double ObstacleBounds::safe_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) const {
  return contact::min_over_chunks(x.cols(), kChunk, 1.0, [&](std::size_t, long begin, long end, double& t) {
    for (long i = begin; i < end; ++i) t = std::min(t, move_limit(x, dx, i));
  });
}

void ObstacleBounds::limit_moves(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, Eigen::VectorXd& limit) const {
#pragma omp parallel for schedule(dynamic, kChunk) if (x.cols() > kChunk)
  for (Eigen::Index i = 0; i < x.cols(); ++i) limit[i] = std::min(limit[i], move_limit(x, dx, i));
}

void ObstacleBounds::vertex_bounds(const Eigen::Matrix3Xd& x, Eigen::VectorXd& bound) const {
#pragma omp parallel for schedule(dynamic, kChunk) if (x.cols() > kChunk)
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    if (!set_->takes_part(i)) continue;
    set_->near(
        x.col(i), [&](double lower) { return lower > 0 && room(lower) >= bound[i]; },
        [&](std::size_t, const SurfaceDistance& s) {
          if (s.distance > 0) bound[i] = std::min(bound[i], room(s.distance));
        });
  }
}

}  // namespace pce::sim::obstacle

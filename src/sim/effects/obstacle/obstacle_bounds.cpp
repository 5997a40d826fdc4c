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
      // With a floor, a pair that stays beyond 2F + 2δ (d − |Δx| ≥ its lower bound less the
      // step) needs no bound; without one, the barrier's pair whose d > |Δx|.
      set_->near(
          p, [&](double lower) { return floored ? lower - step >= above : lower > step; },
          [&](std::size_t k, const SurfaceDistance& s) {
            bound_pair(p, dx.col(i), i, k, s.distance, t, held_chunks_[c]);
          });
    }
  });
  contact::join_chunks(held_chunks_, chunks, held_);
  return t;
}

void ObstacleBounds::bound_pair(const Eigen::Vector3d& p, const Eigen::Vector3d& dxi, Eigen::Index i, std::size_t k,
                                double d0, double& t, std::vector<FloorLimit>& held) const {
  if (!(d0 > 0)) return;  // inside: outside the domain already, nothing to keep
  const double step = dxi.norm();
  if (!(floor_ > 0)) {  // the barrier alone: a tenth of d₀ by the Lipschitz bound
    t = std::min(t, 0.9 * d0 / step);
    return;
  }
  // The floor's gap, or a tenth of d₀ (at least 2F + 2δ) for a pair farther out, kept along
  // the separating direction.
  const double g = floor_gap(d0, floor_, slack_);
  const bool convex = set_->convex(k);
  const double cap = t;
  const double tk = advance_to_gap(
      [&](double s, double& S, double& r) {
        const SurfaceDistance at = set_->distance(k, p + s * dxi);
        S = at.distance;
        r = convex ? -at.normal.dot(dxi) : step;
        return std::isfinite(S) && std::isfinite(r);
      },
      g > 0 ? g : 0.1 * d0, g > 0 ? slack_ : 0.0, cap);
  if (g > 0 && tk < cap) held.push_back({set_->pair(i, k), g, d0});
  t = std::min(t, tk);
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

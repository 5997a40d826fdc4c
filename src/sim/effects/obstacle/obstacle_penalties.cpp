// SPDX-License-Identifier: MIT
// The penalties of an obstacle-contact effect (obstacle_penalties.hpp).
#include "obstacle_penalties.hpp"

#include <algorithm>

namespace pce::sim::obstacle {

double ObstaclePenalties::evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) {
  left_domain_ = visit_penalty(penalty_, [&](const auto& penalty) { return gather(x, penalty); });
  if (left_domain_) return std::numeric_limits<double>::infinity();
  return contact::scatter(terms_, gradient, hessian);
}

long ObstaclePenalties::contacts() const {
  long count = 0;
  terms_.for_each([&](const contact::PairTerm<1>&) { ++count; });
  return count;
}

template <class Penalty> bool ObstaclePenalties::gather(const Eigen::Matrix3Xd& x, const Penalty& penalty) {
  const long n = x.cols();
  const std::size_t chunks = contact::chunk_count(n, kChunk);
  terms_.prepare(chunks);
  chunk_min_.assign(chunks, std::numeric_limits<double>::max());
  chunk_blocked_.assign(chunks, 0);
  const double reach = penalty_.distance;
  contact::for_each_chunk(n, kChunk, [&](std::size_t c, long begin, long end) {
    terms_.clear(c);
    for (long i = begin; i < end; ++i) {
      if (!set_->takes_part(i)) continue;  // inside a volume
      set_->near(
          x.col(i),
          [&](double lower) {
            if (lower < reach) return false;
            chunk_min_[c] = std::min(chunk_min_[c], lower);  // d ≥ lower ≥ reach: inactive
            return true;
          },
          [&](std::size_t k, const SurfaceDistance& s) {
            chunk_min_[c] = std::min(chunk_min_[c], s.distance);
            if (!(s.distance < reach)) return;
            if (penalty_.barrier() && !(s.distance > 0)) chunk_blocked_[c] = 1;
            const PenaltyDerivatives<double> psi = weighted(penalty, i, k).evaluate(s.distance);
            contact::PairTerm<1> t;
            t.k = static_cast<long>(set_->pair(i, k));
            t.vertices = {static_cast<int>(i)};
            t.energy = psi.value;
            t.length = s.distance;
            t.gradient = psi.first * s.normal;
            terms_.terms[c].push_back(t);
            if (psi.second > 0)
              terms_.blocks[c].push_back({t.vertices, psi.second * (s.normal * s.normal.transpose())});
          });
    }
  });
  min_distance_ = *std::min_element(chunk_min_.begin(), chunk_min_.end());
  return std::count(chunk_blocked_.begin(), chunk_blocked_.end(), char(1)) > 0;
}

}  // namespace pce::sim::obstacle

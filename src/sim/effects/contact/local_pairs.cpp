// SPDX-License-Identifier: MIT
// Block descent's bounds and local terms of self contact (local_pairs.hpp), compiled once
// for vertex-face and edge-edge pairs.
#include "local_pairs.hpp"

#include "ordered_chunks.hpp"

#include <algorithm>
#include <cmath>

namespace pce::sim::contact {

template <bool VF>
void LocalPairs<VF>::bounds(const Model& model, const Eigen::Matrix3Xd& x, double apart, Eigen::VectorXd& bound) const {
  using Geometry = PairGeometry<VF>;
  const double cap = kShare * (apart - classifier_->largest_floor());
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    if (model.is_surface_vertex(i)) bound[i] = std::min(bound[i], cap);
  const long n = static_cast<long>(candidates_->size());
  pair_bound_.assign(static_cast<std::size_t>(n), cap);
#pragma omp parallel for schedule(dynamic, 2048) if (n > 2048)
  for (long k = 0; k < n; ++k) {
    const auto uk = static_cast<std::size_t>(k);
    const std::array<int, 4> v = candidates_->vertices(uk);
    const Vec12<double> xp = Geometry::gather(x, v);
    // A lower bound on the distance first; the exact one only where that could lower a bound.
    double D = Geometry::distance_lower_bound(xp);
    const double floor = classifier_->floor_of(uk);
    if (kShare * (D - floor) >= cap) continue;
    double exact = 0;
    if (closest_distance<VF>(xp, exact)) D = std::max(D, exact);
    pair_bound_[uk] = kShare * (D > floor ? D - floor : 0.1 * D);
  }
  for (std::size_t k = 0; k < pair_bound_.size(); ++k) {
    if (!(pair_bound_[k] < cap)) continue;
    for (const int v : candidates_->vertices(k)) bound[v] = std::min(bound[v], pair_bound_[k]);
  }
}

template <bool VF>
void LocalPairs<VF>::begin_sweep(const Eigen::Matrix3Xd& x, const Eigen::VectorXd& reach, Pattern& couplings) {
  constexpr int na = PairGeometry<VF>::first_side_count();
  candidates_->measure_drift(x);
  const long n = static_cast<long>(candidates_->size());
  constexpr long chunk = 4096;
  const std::size_t chunks = chunk_count(n, chunk);
  if (parts_.size() < chunks) parts_.resize(chunks);
  // First against the largest reach of all (no vertex read), then the pair's own.
  double largest = 0;
  for (Eigen::Index i = 0; i < reach.size(); ++i)
    if (std::isfinite(reach[i])) largest = std::max(largest, reach[i]);
  for_each_chunk(n, chunk, [&](std::size_t c, long begin, long end) {
    std::vector<long>& mine = parts_[c];
    mine.clear();
    for (long k = begin; k < end; ++k) {
      const auto uk = static_cast<std::size_t>(k);
      if (candidates_->beyond(uk, classifier_->reach_of(uk) + 2 * largest)) continue;
      const std::array<int, 4> v = candidates_->vertices(uk);
      double a = 0, b = 0;  // the most a vertex of either primitive moves in the sweep
      for (int s = 0; s < 4; ++s) {
        double& side = s < na ? a : b;
        side = std::max(side, reach[v[static_cast<std::size_t>(s)]]);
      }
      if (candidates_->beyond(uk, classifier_->reach_of(uk) + a + b)) continue;
      mine.push_back(k);
    }
  });
  join_chunks(parts_, chunks, listed_);
  // The colouring keeps every listed pair's vertices apart: a pair that becomes active
  // within the sweep then never has two of its vertices updated side by side (colouring
  // only the pairs active at the sweep's start left two sheets resting on a ball jittering
  // at ~0.3 m/s until they slid off).
  for (const long k : listed_) couplings.add(candidates_->vertices(static_cast<std::size_t>(k)));
  incidence_.build(static_cast<int>(x.cols()), listed_.size(),
                   [&](std::size_t i) { return candidates_->vertices(static_cast<std::size_t>(listed_[i])); });
  ready_ = true;
}

template <bool VF>
void LocalPairs<VF>::evaluate(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) const {
  const long count = static_cast<long>(vertices.size());
  visit_penalty(settings_->penalty, [&](const auto& penalty) {
#pragma omp parallel if (count >= 64)
    {
      std::vector<PairBlock<4>> blocks;
      blocks.reserve(1);
#pragma omp for schedule(dynamic, 256)
      for (long j = 0; j < count; ++j) {
        const int v = vertices[static_cast<std::size_t>(j)];
        if (!incidence_.has(v)) continue;
        Eigen::Vector3d g = Eigen::Vector3d::Zero();
        Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
        bool active = false;
        for (const Incident* e = incidence_.begin(v); e != incidence_.end(v); ++e) {
          PairOutcome o;
          blocks.clear();
          potential_->evaluate(x, listed_[static_cast<std::size_t>(e->item)], penalty, &blocks, o, true);
          if (!o.active || !std::isfinite(o.term.energy)) continue;
          active = true;
          g += o.term.gradient.template segment<3>(3 * e->slot);
          if (!blocks.empty()) H += blocks.back().hessian.template block<3, 3>(3 * e->slot, 3 * e->slot);
        }
        terms.gradient.col(j) += g;
        terms.hessian[static_cast<std::size_t>(j)] += H;
        if (active) terms.contact[static_cast<std::size_t>(j)] = 1;
      }
    }
  });
}

template class LocalPairs<true>;
template class LocalPairs<false>;

}  // namespace pce::sim::contact

// SPDX-License-Identifier: MIT
// The declared and active pairs of self contact (active_pairs.hpp), compiled once for
// vertex-face and edge-edge pairs.
#include "active_pairs.hpp"

#include "util/stopwatch.hpp"

#include <pce/sim/instrumentation.hpp>

#include <algorithm>
#include <cmath>

namespace pce::sim::contact {

template <bool VF> void ActivePairs<VF>::declare(Pattern& pattern) const {
  for (std::size_t k = 0; k < candidates_->size(); ++k)
    if (declared_[k]) pattern.add(candidates_->vertices(k));
}

template <bool VF> bool ActivePairs<VF>::update_pattern(const Eigen::Matrix3Xd& x) {
  // At the state of the last full evaluation (the line search's accepted trial), that pass
  // recorded is_active for every candidate; otherwise one pass asks it.
  if (evaluated_x_valid_ && evaluated_x_.cols() == x.cols() && evaluated_x_ == x) {
    near_.assign(candidates_->size(), 0);
    for (const std::size_t k : declared_at_evaluation_) near_[k] = 1;
  } else {
    const long n = static_cast<long>(candidates_->size());
    if (near_.size() < candidates_->size()) near_.resize(candidates_->size());
    candidates_->measure_drift(x);
#pragma omp parallel for schedule(dynamic, 2048) if (n > 2048)
    for (long k = 0; k < n; ++k)
      near_[static_cast<std::size_t>(k)] = classifier_->is_active(x, static_cast<std::size_t>(k));
  }
  bool changed = false;
  active_at_pattern_.clear();
  for (std::size_t k = 0; k < candidates_->size(); ++k) {
    if (near_[k] != declared_[k]) declared_[k] = near_[k], changed = true;
    if (near_[k]) active_at_pattern_.push_back(k);
  }
  pattern_x_ = x;
  pattern_x_valid_ = true;
  return changed;
}

template <bool VF> double ActivePairs<VF>::evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient,
                                                    BlockHessian* hessian, const std::vector<std::size_t>* segment,
                                                    ContactStats& stats) {
  {
    const ScopedTimer timer(stats.pair_ms);
    const bool want_h = hessian != nullptr;
    candidates_->measure_drift(x);
    // At the state of the last update_pattern (the solver's Newton evaluation follows it), the
    // pairs active there are the only ones that can be: is_active is true for every pair the
    // potential finds active (and for degenerate closest-feature pairs, which it skips), so
    // the pass visits those alone, in the same ascending order, with the same result. On the
    // last step bound's segment, the pairs it listed as possibly active there are the only
    // ones that can be (is_active included), again in ascending order with the same result.
    const bool at_pattern = pattern_x_valid_ && pattern_x_.cols() == x.cols() && pattern_x_ == x;
    const std::vector<std::size_t>* list = at_pattern ? &active_at_pattern_ : segment;
    const long n = list ? static_cast<long>(list->size()) : static_cast<long>(candidates_->size());
    // Active pairs (each with a Hessian) come in smaller chunks.
    const long chunk = at_pattern ? 32 : list ? 256 : 2048;
    const std::size_t chunks = chunk_count(n, chunk);
    terms_.prepare(chunks);
    if (declares_.size() < chunks) declares_.resize(chunks);
    unsure_.assign(chunks, 0);
    visit_penalty(settings_->penalty, [&](const auto& penalty) {
      for_each_chunk(n, chunk, [&](std::size_t c, long begin, long end) {
        terms_.clear(c);
        std::vector<std::size_t>& my_declares = declares_[c];
        my_declares.clear();
        for (long i = begin; i < end; ++i) {
          const long k = list ? static_cast<long>((*list)[static_cast<std::size_t>(i)]) : i;
          PairOutcome o;
          potential_->evaluate(x, k, penalty, want_h ? &terms_.blocks[c] : nullptr, o);
          if (o.declare) my_declares.push_back(static_cast<std::size_t>(k));
          if (o.unsure) unsure_[c] = 1;
          if (o.active) terms_.terms[c].push_back(o.term);
        }
      });
    });
    (VF ? instrumentation().vertex_face_pairs_evaluated : instrumentation().edge_edge_pairs_evaluated) += n;
    // A pass over every candidate recorded is_active for each: update_pattern at this x
    // reads it instead of asking again.
    evaluated_x_valid_ = !at_pattern && std::count(unsure_.begin(), unsure_.end(), char(1)) == 0;
    if (evaluated_x_valid_) {
      evaluated_x_ = x;
      join_chunks(declares_, chunks, declared_at_evaluation_);
    }
  }
  const ScopedTimer timer(stats.scatter_ms);
  stats.active = stats.fold_active = 0;
  stats.min_length = std::numeric_limits<double>::infinity();
  terms_.for_each([&](const PairTerm<4>& t) {
    ++stats.active;
    stats.fold_active += candidates_->fold_pair(static_cast<std::size_t>(t.k));
    stats.min_length = std::min(stats.min_length, t.length);
  });
  return scatter(terms_, gradient, hessian);
}

template <bool VF> void ActivePairs<VF>::carry_over(const std::vector<long>& previous) {
  invalidate();
  std::vector<char> declared(previous.size(), 0);
  for (std::size_t k = 0; k < previous.size(); ++k)
    if (previous[k] >= 0) declared[k] = declared_[static_cast<std::size_t>(previous[k])];
  declared_ = std::move(declared);
}

template class ActivePairs<true>;
template class ActivePairs<false>;

}  // namespace pce::sim::contact

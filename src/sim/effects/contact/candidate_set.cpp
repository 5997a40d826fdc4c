// SPDX-License-Identifier: MIT
// The candidate set's queries, validity tests and bounds (declared, with the conditions they
// keep, in candidate_set.hpp), compiled once for vertex-face and edge-edge pairs.
#include "candidate_set.hpp"

#include <omp.h>

#include <utility>

namespace pce::sim::contact {

template <bool VF> CandidateSet<VF>::CandidateSet(const Model& model, BroadPhaseKind kind, double distance,
                                                  bool bounded, std::vector<char> allowed)
    : model_(&model),
      broad_phase_(make_broad_phase(kind)),
      distance_(distance),
      margin_(0.5 * distance),
      bounded_(bounded),
      allowed_(std::move(allowed)) {
  mesh_of_.resize(static_cast<std::size_t>(model.vertex_count()));
  for (std::size_t m = 0; m < model.meshes.size(); ++m)
    for (int i = 0; i < model.meshes[m].vertex_count; ++i)
      mesh_of_[static_cast<std::size_t>(model.meshes[m].first_vertex + i)] = static_cast<int>(m);
  find_fold_pairs();
}

template <bool VF>
bool CandidateSet<VF>::begin_step(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, std::vector<long>& previous) {
  stats_ = {};
  target_.resize(3, 0);
  if (bounded_ && has_query(x0) && still_valid(x0)) return false;
  validity_bound_ = false;
  query(x0, x1, previous);
  return true;
}

template <bool VF> bool CandidateSet<VF>::still_valid(const Eigen::Matrix3Xd& x) const {
  if (validity_bound_) return false;
  const double limit = bounded_ ? 1.0 : 0.5;
  return sweep_use(x) <= limit || validity_use(mesh_drift(x - query_at_), nullptr) <= limit;
}

template <bool VF> void CandidateSet<VF>::refresh(const Eigen::Matrix3Xd& x, std::vector<long>& previous) {
  const Eigen::Matrix3Xd to = target_.cols() == x.cols() ? target_ : x;
  validity_bound_ = false;
  query(x, to, previous);
}

template <bool VF> bool CandidateSet<VF>::cover(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, double reach,
                                                std::vector<long>& previous, bool always) {
  if (!(bounded_ || always) || valid_fraction(x, dx, mesh_drift(dx)) >= 1) return false;
  const double largest = dx.colwise().norm().maxCoeff();
  const double c = largest > reach ? reach / largest : 1.0;
  validity_bound_ = false;
  query(x, x + c * dx, previous);
  return true;
}

template <bool VF> double CandidateSet<VF>::step_limit(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) {
  const MeshDrift step = mesh_drift(dx);
  const double t_valid = valid_fraction(x, dx, step);
  target_ = x + dx;
  measure_drift(x);
  step_reach_ = step_reach(step);
  spreads(dx, step_first_, step_second_);
  return t_valid;
}

template <bool VF> void CandidateSet<VF>::measure_drift(const Eigen::Matrix3Xd& x) {
  drift_ = x - query_at_;
  spreads(drift_, drift_first_, drift_second_);
  rounding_ = 64 * std::numeric_limits<double>::epsilon() * x.cwiseAbs().maxCoeff();
  const MeshDrift m = mesh_drift(drift_);
  const std::size_t M = m.s.size();
  drift_rel_.assign(M * M, 0.0);
  for (std::size_t a = 0; a < M; ++a)
    for (std::size_t b = a; b < M; ++b) drift_rel_[a * M + b] = relative(m, a, b);
}

template <bool VF> void CandidateSet<VF>::restore(std::vector<Pair> pairs) {
  pairs_ = std::move(pairs);
  mark_fold_pairs();
  query_lb_.clear();
  query_at_.resize(3, 0);
  validity_bound_ = false;
}

template <bool VF> void CandidateSet<VF>::spreads(const Eigen::Matrix3Xd& D, std::vector<Spread>& first,
                                                  std::vector<Spread>& second) const {
  const auto of = [&D](const auto& indices, std::vector<Spread>& out) {
    const Eigen::Index count = indices.cols();
    out.resize(static_cast<std::size_t>(count));
    for (Eigen::Index p = 0; p < count; ++p) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (Eigen::Index j = 0; j < indices.rows(); ++j) mean += D.col(indices(j, p));
      mean /= static_cast<double>(indices.rows());
      double radius = 0;
      for (Eigen::Index j = 0; j < indices.rows(); ++j) radius = std::max(radius, (D.col(indices(j, p)) - mean).norm());
      out[static_cast<std::size_t>(p)] = {mean, radius};
    }
  };
  if constexpr (VF) {
    first.resize(static_cast<std::size_t>(D.cols()));
    for (Eigen::Index i = 0; i < D.cols(); ++i) first[static_cast<std::size_t>(i)] = {D.col(i), 0.0};
    of(model_->triangles, second);
  } else {
    of(model_->edges, first);
    second.clear();  // the second primitive is an edge too: first's entries serve
  }
}

template <bool VF> typename CandidateSet<VF>::MeshDrift CandidateSet<VF>::mesh_drift(const Eigen::Matrix3Xd& D) const {
  MeshDrift m;
  for (const MeshRange& r : model_->meshes) {
    const auto block = D.middleCols(r.first_vertex, r.vertex_count);
    const Eigen::Vector3d c = block.rowwise().mean();
    m.c.push_back(c);
    m.s.push_back((block.colwise() - c).colwise().norm().maxCoeff());
  }
  return m;
}

template <bool VF> std::vector<double> CandidateSet<VF>::step_reach(const MeshDrift& step) {
  const std::size_t M = step.s.size();
  std::vector<double> w(M * M, 0.0);
  for (std::size_t a = 0; a < M; ++a)
    for (std::size_t b = a; b < M; ++b) w[a * M + b] = std::max({2 * step.s[a], 2 * step.s[b], relative(step, a, b)});
  return w;
}

template <bool VF> double CandidateSet<VF>::validity_use(const MeshDrift& now, const MeshDrift* step, double* t) const {
  double use = 0;
  const std::size_t M = now.s.size();
  for (std::size_t a = 0; a < M; ++a)
    for (std::size_t b = a; b < M; ++b) {
      const double budget = std::max(margin_, gaps_[a * M + b] - distance_);
      const double rel = relative(now, a, b);
      use = std::max(use, rel / budget);
      if (step && t) {
        const double moving = relative(*step, a, b);
        if (moving > 0) *t = std::min(*t, std::max(0.0, budget - rel) / moving);
      }
    }
  return use;
}

template <bool VF> double CandidateSet<VF>::valid_fraction(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx,
                                                           const MeshDrift& step) const {
  double t_drift = 1.0;
  const bool drift_valid = validity_use(mesh_drift(x - query_at_), &step, &t_drift) <= 1;
  return std::max(drift_valid ? t_drift : 0.0, sweep_step(x, dx));
}

template <bool VF> double CandidateSet<VF>::sweep_use(const Eigen::Matrix3Xd& x) const {
  const double outside = (sweep_lo_ - x).cwiseMax(x - sweep_hi_).maxCoeff();
  return std::max(outside, 0.0) / sweep_room();
}

template <bool VF> double CandidateSet<VF>::sweep_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) const {
  if (sweep_use(x) > 1) return 0.0;
  const double room = sweep_room();
  double t = 1.0;
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = dx(c, i);
      if (d > 0)
        t = std::min(t, (sweep_hi_(c, i) + room - x(c, i)) / d);
      else if (d < 0)
        t = std::min(t, (sweep_lo_(c, i) - room - x(c, i)) / d);
    }
  return std::max(t, 0.0);
}

template <bool VF>
void CandidateSet<VF>::query(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, std::vector<long>& previous) {
  const ScopedTimer timer(stats_.broad_phase_ms);
  // The former query point and bounds: a pair that stays a candidate keeps its bound,
  // less how far it moved since (bound_at_query).
  if (query_lb_.size() == pairs_.size() && query_at_.cols() == x0.cols()) {
    former_lb_.swap(query_lb_);
    moved_ = x0 - query_at_;
    rounding_ = 64 * std::numeric_limits<double>::epsilon() *
                std::max(x0.cwiseAbs().maxCoeff(), query_at_.cwiseAbs().maxCoeff());
  } else {
    former_lb_.clear();
  }
  set_sweep(x0, x1);
  std::vector<Pair> fresh;
  {
    const ScopedTimer tree_timer(stats_.tree_ms);
    const double r = distance_ + margin_;
    if constexpr (VF) {
      broad_phase_->vertex_face(query_at_, query_to_, model_->triangles, r, fresh);
    } else {
      broad_phase_->edge_edge(query_at_, query_to_, model_->edges, r, fresh);
    }
    drop_excluded(fresh);
  }
  // Both lists are sorted: one merge pass finds where each fresh pair was.
  previous.assign(fresh.size(), -1);
  std::size_t old = 0;
  for (std::size_t k = 0; k < fresh.size(); ++k) {
    while (old < pairs_.size() && pairs_[old] < fresh[k]) ++old;
    if (old < pairs_.size() && pairs_[old] == fresh[k]) previous[k] = static_cast<long>(old);
  }
  pairs_ = std::move(fresh);
  mark_fold_pairs();
  bound_at_query(previous);
  stats_.queries += 1;
}

template <bool VF> void CandidateSet<VF>::drop_excluded(std::vector<Pair>& pairs) const {
  if (VF && !model_->surface_vertex.empty())
    pairs.erase(
        std::remove_if(pairs.begin(), pairs.end(), [&](const Pair& p) { return !model_->is_surface_vertex(p[0]); }),
        pairs.end());
  if (allowed_.empty()) return;
  const std::size_t M = model_->meshes.size();
  pairs.erase(std::remove_if(pairs.begin(), pairs.end(),
                             [&](const Pair& p) {
                               const auto v = Geometry::vertices(*model_, p);
                               const auto a = static_cast<std::size_t>(mesh_of_[static_cast<std::size_t>(v[0])]);
                               const auto b = static_cast<std::size_t>(mesh_of_[static_cast<std::size_t>(v[3])]);
                               return !allowed_[a * M + b];
                             }),
              pairs.end());
}

template <bool VF> void CandidateSet<VF>::set_sweep(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1) {
  query_at_ = x0;
  query_to_ = x1;
  sweep_lo_ = x0.cwiseMin(x1);
  sweep_hi_ = x0.cwiseMax(x1);
  const std::size_t M = model_->meshes.size();
  std::vector<Eigen::AlignedBox3d> boxes(M);
  for (std::size_t a = 0; a < M; ++a) {
    const MeshRange& r = model_->meshes[a];
    const auto block = x0.middleCols(r.first_vertex, r.vertex_count);
    boxes[a] = Eigen::AlignedBox3d(block.rowwise().minCoeff(), block.rowwise().maxCoeff());
  }
  gaps_.assign(M * M, 0.0);
  for (std::size_t a = 0; a < M; ++a)
    for (std::size_t b = a + 1; b < M; ++b) gaps_[a * M + b] = std::sqrt(boxes[a].squaredExteriorDistance(boxes[b]));
}

template <bool VF> void CandidateSet<VF>::bound_at_query(const std::vector<long>& previous) {
  const bool carry = !former_lb_.empty();
  const long n = static_cast<long>(pairs_.size());
  const int M = static_cast<int>(model_->meshes.size());
  query_lb_.resize(pairs_.size());
  mesh_pair_.resize(pairs_.size());
#pragma omp parallel for schedule(static) if (n > 2048)
  for (long k = 0; k < n; ++k) {
    const auto uk = static_cast<std::size_t>(k);
    const auto v = vertices(uk);
    query_lb_[uk] = Geometry::distance_lower_bound(Geometry::gather(query_at_, v));
    if (carry && previous[uk] >= 0) {
      query_lb_[uk] = std::max(
          query_lb_[uk], former_lb_[static_cast<std::size_t>(previous[uk])] - rounding_ - relative_motion(moved_, v));
    }
    const int a = mesh_of_[static_cast<std::size_t>(v[0])], b = mesh_of_[static_cast<std::size_t>(v[3])];
    mesh_pair_[uk] = std::min(a, b) * M + std::max(a, b);
  }
}

template <bool VF> void CandidateSet<VF>::find_fold_pairs() {
  const double r = 2 * distance_;
  std::vector<Pair> rest_pairs;
  if constexpr (VF) {
    broad_phase_->vertex_face(model_->rest, model_->triangles, r, rest_pairs);
  } else {
    broad_phase_->edge_edge(model_->rest, model_->edges, r, rest_pairs);
  }
  drop_excluded(rest_pairs);
  const long n = static_cast<long>(rest_pairs.size());
  std::vector<char> near(rest_pairs.size(), 0);
  std::vector<double> rest_distance(rest_pairs.size(), 0.0);
#pragma omp parallel for schedule(static) if (n > 2048)
  for (long k = 0; k < n; ++k) {
    const auto v = Geometry::vertices(*model_, rest_pairs[static_cast<std::size_t>(k)]);
    if (mesh_of_[static_cast<std::size_t>(v[0])] != mesh_of_[static_cast<std::size_t>(v[3])]) continue;
    const Vec12<double> rest = Geometry::gather(model_->rest, v);
    if (Geometry::distance_lower_bound(rest) >= r) continue;
    using Kind = std::conditional_t<VF, VertexFace, EdgeEdge>;
    ClosestFeatureEnergy<double> ce;
    const Status st = closest_feature_energy<Kind>(rest, UnsignedLength{}, QuadraticPenalty{1.0, 0.0}, ce);
    near[static_cast<std::size_t>(k)] = st != Status::ok || ce.length < r;
    rest_distance[static_cast<std::size_t>(k)] = st == Status::ok ? ce.length : 0.0;
  }
  folds_.clear();
  fold_reaches_.clear();
  for (std::size_t k = 0; k < rest_pairs.size(); ++k)
    if (near[k]) {
      folds_.push_back(rest_pairs[k]);
      fold_reaches_.push_back(std::min(distance_, kFoldReach * rest_distance[k]));
    }
}

template <bool VF> void CandidateSet<VF>::mark_fold_pairs() {
  fold_pair_.assign(pairs_.size(), 0);
  fold_reach_.assign(pairs_.size(), 0.0);
  std::size_t j = 0;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    while (j < folds_.size() && folds_[j] < pairs_[k]) ++j;
    fold_pair_[k] = j < folds_.size() && folds_[j] == pairs_[k];
    if (fold_pair_[k]) fold_reach_[k] = fold_reaches_[j];
  }
}

template <bool VF> void CandidateSet<VF>::restore(std::vector<Pair> pairs, const Eigen::Matrix3Xd& at,
                                                  const Eigen::Matrix3Xd& to, bool validity_bound) {
  restore(std::move(pairs));
  set_sweep(at, to);
  former_lb_.clear();
  bound_at_query(std::vector<long>(pairs_.size(), -1));
  validity_bound_ = validity_bound;
}

template class CandidateSet<true>;
template class CandidateSet<false>;

}  // namespace pce::sim::contact

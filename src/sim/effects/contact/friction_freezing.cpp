// SPDX-License-Identifier: MIT
// Friction of self contact (friction_freezing.hpp), compiled once for vertex-face and
// edge-edge pairs.
#include "friction_freezing.hpp"

#include "ordered_chunks.hpp"
#include "util/stopwatch.hpp"

#include <cmath>

namespace pce::sim::contact {

template <bool VF> void FrictionFreezing<VF>::begin_step(const StepContext& ctx) {
  stats_ = {};
  x_start_ = ctx.x_start;
  slip_ = settings_->friction->slip_velocity * ctx.dt;
  rounds_ = 1;
  freeze(*ctx.x_start);
}

template <bool VF> bool FrictionFreezing<VF>::update_lagged(const Eigen::Matrix3Xd& x) {
  if (rounds_ >= settings_->friction->lagged_iterations) return false;
  ++rounds_;
  freeze(x);
  return true;
}

template <bool VF>
double FrictionFreezing<VF>::evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) {
  const ScopedTimer timer(stats_.ms);
  return add_friction(frozen_, x, *x_start_, gradient, hessian, stats_.sticking);
}

template <bool VF> void FrictionFreezing<VF>::evaluate_local(const Eigen::Matrix3Xd& x,
                                                             const std::vector<int>& vertices,
                                                             LocalTerms& terms) const {
  const long count = static_cast<long>(vertices.size());
#pragma omp parallel for schedule(dynamic, 256) if (count >= 64)
  for (long j = 0; j < count; ++j) {
    const int v = vertices[static_cast<std::size_t>(j)];
    if (!incidence_.has(v)) continue;
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    for (const Incident* e = incidence_.begin(v); e != incidence_.end(v); ++e)
      add_friction_local(frozen_[static_cast<std::size_t>(e->item)], e->slot, x, *x_start_, g, H);
    terms.gradient.col(j) += g;
    terms.hessian[static_cast<std::size_t>(j)] += H;
  }
}

template <bool VF> void FrictionFreezing<VF>::report(Counters& c) const {
  c[VF ? Counter::vertex_face_friction_contacts : Counter::edge_edge_friction_contacts] =
      static_cast<double>(frozen_.size());
  c[VF ? Counter::vertex_face_friction_sticking : Counter::edge_edge_friction_sticking] =
      static_cast<double>(stats_.sticking);
  c[VF ? Counter::vertex_face_friction_ms : Counter::edge_edge_friction_ms] = stats_.ms;
}

template <bool VF> void FrictionFreezing<VF>::freeze(const Eigen::Matrix3Xd& x) {
  using Kind = std::conditional_t<VF, VertexFace, EdgeEdge>;
  const ScopedTimer timer(stats_.ms);
  candidates_->measure_drift(x);
  const long n = static_cast<long>(candidates_->size());
  constexpr long chunk = 2048;
  const std::size_t chunks = chunk_count(n, chunk);
  if (parts_.size() < chunks) parts_.resize(chunks);
  const double mu = settings_->friction->coefficient;
  visit_penalty(settings_->penalty, [&](const auto& penalty) {
    for_each_chunk(n, chunk, [&](std::size_t c, long begin, long end) {
      parts_[c].clear();
      for (long k = begin; k < end; ++k) {
        const auto uk = static_cast<std::size_t>(k);
        std::array<int, 4> v;
        Vec12<double> xp;
        Activity a;
        if (!classifier_->active_candidate(x, uk, v, xp, a)) continue;
        const auto pk = classifier_->weighted(penalty, uk);
        double lambda = 0;
        VecN<double, 4> w;
        Eigen::Vector3d normal;
        if (a.mode == Activity::Mode::plane) {
          PenaltyDerivatives<double> psi;
          if (evaluate_penalty(pk, a.sigma * a.frame.l, psi) != Status::ok) continue;
          lambda = -psi.first;
          friction_geometry(a.frame, w, normal);
        } else {
          ClosestFeatureEnergy<double> ce;
          const Status s =
              a.fold ? closest_feature_energy<Kind>(xp, UnsignedLength{}, Classifier<VF>::with_reach(pk, a.limit), ce)
                     : closest_feature_energy<Kind>(xp, UnsignedLength{}, pk, ce);
          if (s != Status::ok || !(ce.length < a.limit) || !friction_geometry(ce, xp, w, normal)) continue;
          lambda = -ce.psi.first;
        }
        if (!(lambda > 0) || !std::isfinite(lambda)) continue;
        FrictionContact<4> fc;
        fc.v = v;
        fc.f.weights = w;
        fc.f.basis = tangent_basis<double>(normal);
        fc.f.mu_lambda = mu * lambda;
        fc.f.static_slip = slip_;
        parts_[c].push_back(fc);
      }
    });
  });
  join_chunks(parts_, chunks, frozen_);
  publish_friction(frozen_, published_);
  incidence_.build(static_cast<int>(x.cols()), frozen_.size(), [&](std::size_t i) { return frozen_[i].v; });
}

template class FrictionFreezing<true>;
template class FrictionFreezing<false>;

}  // namespace pce::sim::contact

// SPDX-License-Identifier: MIT
// The frozen friction of an obstacle-contact effect (obstacle_friction.hpp).
#include "obstacle_friction.hpp"

#include "util/stopwatch.hpp"

#include <cmath>

namespace pce::sim::obstacle {

void ObstacleFriction::begin_step(const StepContext& ctx) {
  stats_ = {};
  const ScopedTimer timer(stats_.ms);
  x_start_ = ctx.x_start;
  slip_ = settings_.slip_velocity * ctx.dt;
  rounds_ = 1;
  freeze(*ctx.x_start, true);
}

bool ObstacleFriction::end_solve(const Eigen::Matrix3Xd& x) {
  if (rounds_ >= settings_.lagged_iterations) return false;
  const ScopedTimer timer(stats_.ms);
  ++rounds_;
  freeze(x, false);
  return true;
}

double ObstacleFriction::evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) {
  const ScopedTimer timer(stats_.ms);
  return add_friction(frozen_, x, *x_start_, gradient, hessian, stats_.sticking);
}

void ObstacleFriction::add_local(const Eigen::Matrix3Xd& x, int i, Eigen::Vector3d& g, Eigen::Matrix3d& H) const {
  if (!incidence_.has(i)) return;
  for (const Incident* e = incidence_.begin(i); e != incidence_.end(i); ++e)
    add_friction_local(frozen_[static_cast<std::size_t>(e->item)], e->slot, x, *x_start_, g, H);
}

void ObstacleFriction::report(EffectCounters& counters) const {
  counters[Counter::obstacle_friction_contacts] = static_cast<double>(frozen_.size());
  counters[Counter::obstacle_friction_sticking] = static_cast<double>(stats_.sticking);
  counters[Counter::obstacle_friction_ms] = stats_.ms;
}

void ObstacleFriction::freeze(const Eigen::Matrix3Xd& x, bool at_start) {
  const double reach = penalties_->penalty().distance;
  const bool barrier = penalties_->penalty().barrier();
  const long n = x.cols();
  const std::size_t chunks = contact::chunk_count(n, kChunk);
  if (parts_.size() < chunks) parts_.resize(chunks);
  visit_penalty(penalties_->penalty(), [&](const auto& penalty) {
    contact::for_each_chunk(n, kChunk, [&](std::size_t c, long begin, long end) {
      parts_[c].clear();
      for (long i = begin; i < end; ++i) {
        if (!set_->takes_part(i)) continue;  // inside a volume
        const Eigen::Vector3d p = x.col(i);
        set_->near(
            p, [&](double lower) { return lower >= reach; },
            [&](std::size_t k, const SurfaceDistance& s) {
              if (!(s.distance < reach) || (barrier && !(s.distance > 0))) return;
              const double lambda = -penalties_->weighted(penalty, i, k).evaluate(s.distance).first;
              if (!(lambda > 0) || !std::isfinite(lambda)) return;
              FrictionContact<1> fc;
              fc.v = {static_cast<int>(i)};
              fc.f.weights << 1.0;
              fc.f.basis = tangent_basis<double>(s.normal);
              const Eigen::Isometry3d &here = set_->pose(k, at_start), &there = set_->pose(k, !at_start);
              const Eigen::Vector3d surface = p - s.distance * s.normal;
              const Eigen::Vector3d moved = there * (here.inverse() * surface);
              fc.f.offset = at_start ? Eigen::Vector3d(moved - surface) : Eigen::Vector3d(surface - moved);
              fc.f.mu_lambda = settings_.coefficient * lambda;
              fc.f.static_slip = slip_;
              parts_[c].push_back(fc);
            },
            at_start);
      }
    });
  });
  contact::join_chunks(parts_, chunks, frozen_);
  publish_friction(frozen_, published_);
  incidence_.build(static_cast<int>(n), frozen_.size(), [&](std::size_t i) { return frozen_[i].v; });
}

}  // namespace pce::sim::obstacle

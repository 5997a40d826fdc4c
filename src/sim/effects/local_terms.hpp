// SPDX-License-Identifier: MIT
/// @file
/// What the element effects (stretching, bending, strands, volumes) share for
/// `Effect::evaluate_local` (internal): the loop over the listed vertices that sums, per
/// vertex, its elements' terms over its row of a `VertexIncidence` built once from the
/// fixed elements.
#pragma once

#include "effects/vertex_incidence.hpp"

#include <pce/sim/effect.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace pce::sim {

/// For each listed vertex j (in parallel over j, OpenMP), sums `add(item, g, B)` over its
/// row of `incidence` in order, from g = 0, B = 0, then adds g to `terms.gradient.col(j)`
/// and B to `terms.hessian[j]`; `add` returns false to drop the vertex's terms (nothing is
/// added for it then). Each j is written by one thread only and its sum is serial: results
/// do not depend on the thread count, and a vertex listed twice gets its full terms twice.
template <class Add>
void add_local_terms(const VertexIncidence& incidence, const std::vector<int>& vertices, LocalTerms& terms, Add add) {
  const auto count = static_cast<long>(vertices.size());
#pragma omp parallel for schedule(static)
  for (long j = 0; j < count; ++j) {
    const int v = vertices[static_cast<std::size_t>(j)];
    if (!incidence.has(v)) continue;
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    Eigen::Matrix3d B = Eigen::Matrix3d::Zero();
    bool keep = true;
    for (const Incident* u = incidence.begin(v); keep && u != incidence.end(v); ++u) keep = add(*u, g, B);
    if (!keep) continue;
    terms.gradient.col(static_cast<Eigen::Index>(j)) += g;
    terms.hessian[static_cast<std::size_t>(j)] += B;
  }
}

}  // namespace pce::sim

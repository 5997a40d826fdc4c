// SPDX-License-Identifier: MIT
// The minimum separation's stiffening of self contact (separation_floor.hpp), compiled once
// for vertex-face and edge-edge pairs.
#include "separation_floor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pce::sim::contact {

template <bool VF> double SeparationFloor<VF>::distance(const Eigen::Matrix3Xd& x, std::size_t k) const {
  double d = 0;
  return closest_distance<VF>(PairGeometry<VF>::gather(x, candidates_->vertices(k)), d)
             ? d
             : std::numeric_limits<double>::infinity();
}

template <bool VF> void SeparationFloor<VF>::begin_step(const Eigen::Matrix3Xd& x) {
  holds_ = 0;
  std::vector<double>& m = classifier_->stiffening();
  bool any = false;
  for (std::size_t k = 0; k < m.size(); ++k) {
    if (m[k] == 1.0) continue;
    if (distance(x, k) >= classifier_->reach_of(k))
      m[k] = 1.0;
    else
      any = true;
  }
  if (!any) m.clear();
}

template <bool VF> bool SeparationFloor<VF>::stiffen(const Eigen::Matrix3Xd& x, const std::vector<FloorLimit>& held) {
  std::vector<double>& m = classifier_->stiffening();
  bool any = false;
  for (const FloorLimit& h : held) {
    const std::size_t k = h.k;
    if (!pressed_in(distance(x, k), h, classifier_->floor_of(k))) continue;
    if (m.empty()) m.assign(candidates_->size(), 1.0);
    if (!stiffen_factor(m[k])) continue;
    ++holds_;
    any = true;
  }
  return any;
}

template <bool VF> void SeparationFloor<VF>::carry_over(const std::vector<long>& previous) {
  std::vector<double>& m = classifier_->stiffening();
  if (m.empty()) return;
  std::vector<double> carried(previous.size(), 1.0);
  bool any = false;
  for (std::size_t k = 0; k < previous.size(); ++k)
    if (previous[k] >= 0) {
      carried[k] = m[static_cast<std::size_t>(previous[k])];
      any = any || carried[k] != 1.0;
    }
  if (any)
    m = std::move(carried);
  else
    m.clear();
}

template <bool VF> long SeparationFloor<VF>::stiffened() const {
  const std::vector<double>& m = classifier_->stiffening();
  return static_cast<long>(std::count_if(m.begin(), m.end(), [](double f) { return f != 1.0; }));
}

template class SeparationFloor<true>;
template class SeparationFloor<false>;

}  // namespace pce::sim::contact

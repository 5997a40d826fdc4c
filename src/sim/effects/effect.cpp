// SPDX-License-Identifier: MIT
// The defaults of Effect and ContactEffect (pce/sim/effect.hpp, pce/sim/contact_effect.hpp).
#include <pce/sim/contact_effect.hpp>
#include <pce/sim/effect.hpp>

#include <stdexcept>

namespace pce::sim {

void Effect::evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) {
  const auto n = static_cast<int>(x.cols());
  Pattern pattern;
  declare(pattern);
  for (const int i : vertices) pattern.add(i);
  BlockHessian hessian;
  hessian.set_pattern(n, pattern);
  Eigen::Matrix3Xd gradient = Eigen::Matrix3Xd::Zero(3, n);
  evaluate(x, &gradient, &hessian);
  for (std::size_t j = 0; j < vertices.size(); ++j) {
    terms.gradient.col(static_cast<Eigen::Index>(j)) += gradient.col(vertices[j]);
    terms.hessian[j] += hessian.diagonal_block(vertices[j]);
  }
}

void ContactEffect::load_state(const std::string& state) {
  if (!state.empty()) throw std::invalid_argument(std::string(name()) + ": unexpected saved state");
}

}  // namespace pce::sim

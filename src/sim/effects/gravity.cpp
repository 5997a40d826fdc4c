// SPDX-License-Identifier: MIT
// Gravity: E = −Σᵢ mᵢ g·xᵢ, a linear potential (zero Hessian, nothing declared), and block
// descent's acceleration field g (pce/sim/block_descent_hooks.hpp).
#include "arguments.hpp"

#include <pce/sim/block_descent_hooks.hpp>
#include <pce/sim/effects.hpp>

namespace pce::sim {

namespace {

class Gravity final : public Effect, public AccelerationField {
 public:
  Gravity(const Model& model, const Eigen::Vector3d& g) : Effect("gravity"), model_(&model), g_(g) {}
  void declare(Pattern& /*pattern*/) const override {}
  /// E = −Σᵢ mᵢ g·xᵢ, ∇ᵢE = −mᵢ g.
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* /*hessian*/) override {
    const Eigen::VectorXd& m = model_->mass;
    const double energy = -(g_.transpose() * x * m)(0);
    if (gradient) gradient->noalias() -= g_ * m.transpose();
    return energy;
  }
  /// ∇ᵢE = −mᵢ g; no Hessian.
  void evaluate_local(const Eigen::Matrix3Xd& /*x*/, const std::vector<int>& vertices, LocalTerms& terms) override {
    for (std::size_t j = 0; j < vertices.size(); ++j)
      terms.gradient.col(static_cast<Eigen::Index>(j)) -= model_->mass[vertices[j]] * g_;
  }
  /// The field: g at every vertex it acts on (every vertex of positive mass in its model).
  void add_acceleration(Eigen::Matrix3Xd& a) const override {
    const Eigen::VectorXd& m = model_->mass;
    for (Eigen::Index i = 0; i < a.cols(); ++i)
      if (m[i] > 0) a.col(i) += g_;
  }

 private:
  const Model* model_;
  Eigen::Vector3d g_;
};

}  // namespace

std::unique_ptr<Effect> make_gravity(const Model& model, const Eigen::Vector3d& acceleration) {
  return std::make_unique<Gravity>(model, args::bounded("acceleration", acceleration, args::kMaxAcceleration,
                                                        "the largest acceleration pce::sim accepts, in m/s²"));
}

}  // namespace pce::sim

// SPDX-License-Identifier: MIT
// Damping as an incremental potential: E = Σᵢ mᵢ c/(2h) |xᵢ − xᵢⁿ|², whose force
// −mᵢ c (xᵢ − xᵢⁿ)/h = −c mᵢ vᵢ is a linear drag on the step's velocity (backward Euler).
#include "arguments.hpp"

#include <pce/sim/effects.hpp>

#include <limits>

namespace pce::sim {

namespace {

class Damping final : public Effect {
 public:
  Damping(const Model& model, double c) : Effect("damping"), model_(&model), c_(c), x_start_(model.rest) {}
  void begin_step(const StepContext& ctx) override {
    if (ctx.x_start) x_start_ = *ctx.x_start;  // same size: no allocation
    if (ctx.dt > 0) h_ = ctx.dt;
  }
  void declare(Pattern& /*pattern*/) const override {}  // diagonal blocks always exist
  /// E = Σᵢ mᵢ c/(2h)|xᵢ − xᵢⁿ|², ∇ᵢE = mᵢ c/h (xᵢ − xᵢⁿ), ∇²ᵢᵢE = mᵢ c/h I.
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) override {
    if (c_ == 0) return 0.0;
    const Eigen::VectorXd& m = model_->mass;
    const double s = c_ / h_;
    double energy = 0;
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      const Eigen::Vector3d d = x.col(i) - x_start_.col(i);
      energy += 0.5 * s * m[i] * d.squaredNorm();
      if (gradient) gradient->col(i) += s * m[i] * d;
      if (hessian) hessian->add_block(static_cast<int>(i), static_cast<int>(i), s * m[i] * Eigen::Matrix3d::Identity());
    }
    return energy;
  }
  /// ∇ᵢE and ∇²ᵢᵢE of the listed vertices.
  void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) override {
    if (c_ == 0) return;
    const double s = c_ / h_;
    for (std::size_t j = 0; j < vertices.size(); ++j) {
      const int i = vertices[j];
      const double w = s * model_->mass[i];
      terms.gradient.col(static_cast<Eigen::Index>(j)) += w * (x.col(i) - x_start_.col(i));
      terms.hessian[j] += w * Eigen::Matrix3d::Identity();
    }
  }

 private:
  const Model* model_;
  double c_;
  double h_ = std::numeric_limits<double>::infinity();  ///< until the first step: c/h = 0, no drag
  Eigen::Matrix3Xd x_start_;
};

}  // namespace

std::unique_ptr<Effect> make_damping(const Model& model, double coefficient) {
  return std::make_unique<Damping>(model, args::nonnegative_at_most("coefficient", coefficient, args::kMaxDamping,
                                                                    "the largest damping pce::sim accepts, in 1/s"));
}

}  // namespace pce::sim

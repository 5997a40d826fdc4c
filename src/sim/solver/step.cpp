// SPDX-License-Identifier: MIT
// The inertia term and the energy passes every solver's step shares (solver/step.hpp).
#include "solver/step.hpp"

#include <cmath>

namespace pce::sim::solver {

void Inertia::start(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, double h) {
  const Eigen::Index n = model.vertex_count();
  mass_ = &model.mass;
  h_ = h;
  mass3_.resize(3 * n);
  for (Eigen::Index i = 0; i < n; ++i) mass3_.segment<3>(3 * i).setConstant(model.mass[i] / (h * h));
  target_ = x + h * v;
}

double Inertia::energy(const Eigen::Matrix3Xd& y) const {
  const Eigen::Map<const Eigen::VectorXd> d(y.data(), y.size());
  const Eigen::Map<const Eigen::VectorXd> t(target_.data(), target_.size());
  return 0.5 * (mass3_.array() * (d - t).array().square()).sum();
}

double Inertia::assembled_energy(const Eigen::Matrix3Xd& y) const {
  return 0.5 * ((y - target_).colwise().squaredNorm().transpose().array() * mass_->array()).sum() / (h_ * h_);
}

void Inertia::gradient(const Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& g) const {
  g = y - target_;
  for (Eigen::Index i = 0; i < g.cols(); ++i) g.col(i) *= (*mass_)[i] / (h_ * h_);
}

double Step::potential(const Eigen::Matrix3Xd& at) {
  double E = inertia.energy(at);
  for (std::size_t k = 0; k < effects.size(); ++k) {
    double ms = 0;
    {
      const ScopedTimer timer(ms);
      E += effects[k]->evaluate(at, nullptr, nullptr);
    }
    effect_ms[k] += ms;
  }
  return E;
}

void Step::fail_non_finite(const Eigen::Matrix3Xd& at, const std::string& where) const {
  const int frame_number = st.frame;
  const std::string head = "frame " + std::to_string(frame_number) + ", " + where + ": ";
  const auto first_bad_column = [](const Eigen::Matrix3Xd& m) {
    for (Eigen::Index i = 0; i < m.cols(); ++i)
      if (!m.col(i).allFinite()) return static_cast<int>(i);
    return -1;
  };
  if (const int i = first_bad_column(at); i >= 0)
    throw SimulationError(frame_number, "", i, head + "the position of vertex " + std::to_string(i) + " is not finite");
  // The inertia term is finite at a finite y: one of the effects is to blame. Each is
  // evaluated alone, in scene order, and the first with a non-finite energy or gradient named.
  Eigen::Matrix3Xd g(3, at.cols());
  for (const auto& e : effects) {
    g.setZero();
    const double E = e->evaluate(at, &g, nullptr);
    const int i = first_bad_column(g);
    if (i >= 0)
      throw SimulationError(frame_number, e->name(), i,
                            head + "effect \"" + e->name() + "\" gives a non-finite gradient at vertex " +
                                std::to_string(i) + " (energy " + std::to_string(E) + ")");
    if (!std::isfinite(E))
      throw SimulationError(
          frame_number, e->name(), -1,
          head + "effect \"" + e->name() + "\" gives a non-finite energy (" + std::to_string(E) + ")");
  }
  throw SimulationError(frame_number, "", -1, head + "the energy or its gradient is not finite");
}

}  // namespace pce::sim::solver

// SPDX-License-Identifier: MIT
/// @file
/// Friction and area weighting shared by the contact effects (internal): the checks of
/// `FrictionSettings`, a frozen friction contact of N vertices and the sum of their
/// potentials (pce/friction/lagged_friction.hpp) into energy, gradient and Hessian.
#pragma once

#include "arguments.hpp"

#include <pce/friction/lagged_friction.hpp>
#include <pce/sim/block_hessian.hpp>
#include <pce/sim/contact_effect.hpp>
#include <pce/sim/effects.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace pce::sim {

/// Throws ArgumentError (`friction.coefficient`, …) unless `f` is absent or valid.
inline void check_friction(const std::optional<FrictionSettings>& f) {
  if (!f) return;
  args::nonnegative_at_most("friction.coefficient", f->coefficient, kMaxFrictionCoefficient,
                            "the largest friction coefficient pce::sim accepts");
  args::positive_at_most("friction.slip_velocity", f->slip_velocity, args::kMaxSpeed,
                         "the largest speed pce::sim accepts, in m/s");
  if (!(f->lagged_iterations >= 1 && f->lagged_iterations <= 100))
    throw ArgumentError("friction.lagged_iterations",
                        "expected an integer in [1, 100], got " + std::to_string(f->lagged_iterations));
}

/// One contact's friction, frozen for a time step: its N vertices and lagged quantities.
template <int N> struct FrictionContact {
  std::array<int, N> v;         ///< the vertices, in the order of the weights
  LaggedFriction<double, N> f;  ///< weights, tangent basis, obstacle motion, μλ, ε_v h
};

/// The contacts in `contacts` whose friction is not zero (μλ > 0), padded to four vertices
/// (weight 0), into `out` (cleared first): the effect's `frozen_friction`.
template <int N>
void publish_friction(const std::vector<FrictionContact<N>>& contacts, std::vector<FrozenFriction>& out) {
  out.clear();
  for (const FrictionContact<N>& c : contacts) {
    if (!(c.f.mu_lambda > 0)) continue;
    FrozenFriction p;
    p.friction.weights.setZero();
    for (int j = 0; j < N; ++j) {
      p.vertices[static_cast<std::size_t>(j)] = c.v[static_cast<std::size_t>(j)];
      p.friction.weights[j] = c.f.weights[j];
    }
    for (int j = N; j < 4; ++j) p.vertices[static_cast<std::size_t>(j)] = c.v[0];
    p.friction.basis = c.f.basis;
    p.friction.offset = c.f.offset;
    p.friction.mu_lambda = c.f.mu_lambda;
    p.friction.static_slip = c.f.static_slip;
    out.push_back(p);
  }
}

/// A contact effect's friction counters of one frame.
struct FrictionStats {
  double ms = 0;      ///< time spent freezing contacts and evaluating the potential
  long sticking = 0;  ///< frozen contacts slipping by less than ε_v h at the last evaluation
};

/// Adds Σ D over `contacts` at positions `x` (displacements from `x_start`): returns the
/// energy, adds the gradient and the PSD Hessian when given, counts the contacts whose slip
/// is below ε (static) into `sticking`.
template <int N> double add_friction(const std::vector<FrictionContact<N>>& contacts, const Eigen::Matrix3Xd& x,
                                     const Eigen::Matrix3Xd& x_start, Eigen::Matrix3Xd* gradient, BlockHessian* hessian,
                                     long& sticking) {
  double energy = 0;
  sticking = 0;
  for (const FrictionContact<N>& c : contacts) {
    Eigen::Matrix<double, 3 * N, 1> dx;
    for (int j = 0; j < N; ++j)
      dx.template segment<3>(3 * j) =
          x.col(c.v[static_cast<std::size_t>(j)]) - x_start.col(c.v[static_cast<std::size_t>(j)]);
    energy += friction_energy(c.f, dx);
    sticking += friction_slip(c.f, dx).norm() < c.f.static_slip;
    if (gradient) {
      const Eigen::Matrix<double, 3 * N, 1> g = friction_gradient(c.f, dx);
      for (int j = 0; j < N; ++j) gradient->col(c.v[static_cast<std::size_t>(j)]) += g.template segment<3>(3 * j);
    }
    if (hessian) {
      if constexpr (N == 1)
        hessian->add_block(c.v[0], c.v[0], c.f.weights[0] * c.f.weights[0] * friction_tangent_block(c.f, dx));
      else
        hessian->add<N>(c.v, friction_hessian(c.f, dx));
    }
  }
  return energy;
}

/// Contact c's friction at `x` (displacements from `x_start`) as seen by its vertex in
/// `slot`: adds that vertex's gradient ∂D/∂x_slot to `g` and w_slot² times the majorizer
/// block μλ (f₁/y) T Tᵀ (`friction_majorizer_block`, ⪰ the Hessian's block) to `H`: block
/// descent's local terms, whose vertex steps would otherwise overshoot a sliding contact.
template <int N> void add_friction_local(const FrictionContact<N>& c, int slot, const Eigen::Matrix3Xd& x,
                                         const Eigen::Matrix3Xd& x_start, Eigen::Vector3d& g, Eigen::Matrix3d& H) {
  Eigen::Matrix<double, 3 * N, 1> dx;
  for (int j = 0; j < N; ++j)
    dx.template segment<3>(3 * j) =
        x.col(c.v[static_cast<std::size_t>(j)]) - x_start.col(c.v[static_cast<std::size_t>(j)]);
  g += friction_gradient(c.f, dx).template segment<3>(3 * slot);
  const double w = c.f.weights[slot];
  H += (w * w) * friction_majorizer_block(c.f, dx);
}

}  // namespace pce::sim

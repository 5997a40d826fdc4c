// SPDX-License-Identifier: MIT
/// @file
/// `linear_solver` amg's preconditioner: one V-cycle of hypre's BoomerAMG on H, set up on
/// one MPI rank (MPI_COMM_SELF). hypre and MPI are included by hypre_amg.cpp only; without
/// hypre (PCE_SIM_HAVE_HYPRE unset) `setup` fails and `hypre_available` is false.
#pragma once

#include "solver/krylov.hpp"

#include <memory>

namespace pce::sim::solver {

/// Whether pce::sim was built with hypre.
bool hypre_available();

/// BoomerAMG's hierarchy of a BlockCsr matrix, as a Preconditioner (z = one V-cycle on
/// H z = r from z = 0).
class HypreAmg final : public Preconditioner {
 public:
  HypreAmg();
  ~HypreAmg() override;
  HypreAmg(const HypreAmg&) = delete;
  HypreAmg& operator=(const HypreAmg&) = delete;
  /// Copies `H` into hypre's matrix and sets BoomerAMG up on it (systems AMG with 3
  /// unknowns per vertex); with `positions` (3 × n, the state H was linearised at) the three
  /// infinitesimal rotations about their centroid join the interpolation (the rigid-body
  /// modes beside the translations each unknown's coarsening keeps). Initialises MPI first if
  /// nobody did. False when hypre reports an error (or there is no hypre).
  bool setup(const BlockCsr& H, const Eigen::Matrix3Xd* positions = nullptr);
  /// Whether a hierarchy is set up.
  bool ready() const;
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace pce::sim::solver

// SPDX-License-Identifier: MIT
// What one time step carries from stage to stage (internal to `Simulation`; its Newton
// stages in simulation.cpp, block descent in block_descent.cpp).
#pragma once

#include "util/stopwatch.hpp"

#include <pce/sim/contact_effect.hpp>
#include <pce/sim/simulation.hpp>

#include <utility>
#include <vector>

namespace pce::sim {

/// What one step carries from stage to stage.
struct Simulation::StepState {
  StepState(LinearState& linear, int n) : ls(linear), n(n) {}
  LinearState& ls;
  int n;
  Clock::time_point t_frame = Clock::now();
  FrameStats st;
  std::vector<double> effect_ms;
  Eigen::Matrix3Xd x_start, v_start;  ///< xⁿ and vⁿ
  Eigen::Matrix3Xd y, g, dxm, y1;     ///< the iterate, its gradient, the direction, a trial
  Eigen::VectorXd dx, rhs;            ///< the direction and −g as vectors
  double E = 0;                       ///< the energy at y with the current candidates
  double E_accepted = 0;              ///< the energy of the last accepted state
  /// The effects' last evaluation was at y with the current candidates: set when a trial
  /// is accepted, cleared by a refresh (and by a trial that is not).
  bool evaluated_at_y = false;
  bool covered = false;  ///< a contact effect queried again over this iteration's step
  /// The contact effects among the scene's (found once per step), with their indices.
  std::vector<std::pair<std::size_t, ContactEffect*>> contacts;
};

}  // namespace pce::sim

// SPDX-License-Identifier: MIT
/// @file
/// What block descent (`Simulation::step` in mode `block_descent`, docs/simulation.md §5.5)
/// tells the effects that implement these interfaces, beyond what it asks of every `Effect`.
/// It finds them among the scene's effects once per time step (`dynamic_cast`) and calls,
/// per time step:
///
///     AccelerationField::add_acceleration(a)    the first guess x̃ + h² a
///     limit_moves(xⁿ, Δx, limit)                the first move, vertex by vertex
///     safe_step(xⁿ, Δx')                        the first move as a whole
///     vertex_bounds(y, bound)                   the bounds at the first move's end
///     per sweep:  begin_sweep(y, reach, couplings)
///                 Effect::evaluate_local(y, colour, terms) per colour
///                 with Chebyshev's acceleration: Requery::still_valid / refresh and
///                 Effect::evaluate(y) (the energy) at the extrapolated state
///                 Requery::still_valid(y), and vertex_bounds(y, …) again when a vertex
///                 used its bound or a candidate set went stale (pce/sim/requery.hpp)
///
/// Newton never calls these. An effect implementing `BlockDescentHooks` names the couplings
/// of its local terms per sweep (`begin_sweep`); block descent reads `Effect::declare` of
/// the others only.
#pragma once

#include <pce/sim/block_hessian.hpp>

#include <Eigen/Core>

namespace pce::sim {

/// Block descent's hooks (see the file comment). Every function has a default that does
/// nothing.
class BlockDescentHooks {
 public:
  virtual ~BlockDescentHooks() = default;

  /// Block descent's first move, before safe_step: an effect whose pairs each hold one
  /// vertex (obstacle contact: the obstacles do not move during the sweeps) lowers limit[i],
  /// the fraction of dxᵢ vertex i alone may move (every other vertex moving any part of its
  /// own), so that the vertices it stops do not stop the rest; the solver then takes the
  /// largest safe_step of the move they leave.
  virtual void limit_moves(const Eigen::Matrix3Xd& /*x*/, const Eigen::Matrix3Xd& /*dx*/, Eigen::VectorXd& /*limit*/) {}
  /// Block descent's first move: the largest fraction t ∈ (0, 1] of the move dx from x along
  /// which no pair this effect sees can cross (its candidates and the set's validity for
  /// self contact, queried again over the move when they would go stale; the obstacles'
  /// surfaces for obstacle contact). 1 by default.
  virtual double safe_step(const Eigen::Matrix3Xd& /*x*/, const Eigen::Matrix3Xd& /*dx*/) { return 1.0; }
  /// Block descent, at the first move's end and whenever the bounds are measured again:
  /// queries the effect's candidates again at x when they are stale and lowers `bound[i]`
  /// (one entry per vertex, +∞ where nothing limits) to a distance vertex i may move away
  /// from x while every other vertex also stays within its bound, such that no pair of the
  /// effect crosses or comes closer than its minimum separation (a pair already closer keeps
  /// nine tenths of its distance), and no pair that is not a candidate comes within reach of
  /// crossing.
  virtual void vertex_bounds(const Eigen::Matrix3Xd& /*x*/, Eigen::VectorXd& /*bound*/) {}
  /// Block descent: a sweep begins at x, in which vertex i moves at most `reach[i]`. An
  /// effect lists what its evaluate_local calls of the sweep can find active, so that they
  /// visit only that, and declares in `couplings` the vertex tuples those couple (the
  /// colouring keeps them apart).
  virtual void begin_sweep(const Eigen::Matrix3Xd& /*x*/, const Eigen::VectorXd& /*reach*/, Pattern& /*couplings*/) {}
};

/// An effect that is a state-independent acceleration field (gravity): block descent starts
/// each step's first move towards xⁿ + h vⁿ + h² a (docs/simulation.md §5.5). Only block
/// descent asks for it.
class AccelerationField {
 public:
  virtual ~AccelerationField() = default;
  /// Adds the field (g at each vertex it acts on) to `a` (3×n).
  virtual void add_acceleration(Eigen::Matrix3Xd& a) const = 0;
};

}  // namespace pce::sim

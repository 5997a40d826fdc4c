// SPDX-License-Identifier: MIT
/// @file
/// An effect whose candidates are queried at a state and go stale as the state moves (self
/// contact's candidate pairs). Both solvers check it after each accepted update: Newton after
/// each accepted line-search trial (after `NewtonHooks::end_line_search`), block descent
/// after each sweep and at the step's end; when `still_valid` says no, Newton and block
/// descent's last check call `refresh` (block descent's sweeps measure their bounds again,
/// `BlockDescentHooks::vertex_bounds`, which queries).
#pragma once

#include <Eigen/Core>

namespace pce::sim {

/// Stale candidates (see the file comment).
class Requery {
 public:
  virtual ~Requery() = default;
  /// Whether the effect's candidates at the last query still hold every pair it must see at
  /// `x`; false when it needs a new query.
  virtual bool still_valid(const Eigen::Matrix3Xd& x) = 0;
  /// Queries again at `x` (after `still_valid` said no).
  virtual void refresh(const Eigen::Matrix3Xd& x) = 0;
};

}  // namespace pce::sim

// SPDX-License-Identifier: MIT
/// @file
/// The state a self-contact effect carries from one step to the next, as bytes for
/// checkpoints (internal; `pce/sim/checkpoint.hpp`): its tracked pairs with their settled
/// sides and declarations, and the query they came from. What the next begin_step keeps (a
/// query carries them over to the fresh candidates; a set still valid is kept whole).
///
/// Format, native byte order: the pair count as uint64; per pair two int32 indices, the side
/// and the declaration as int8; then, when a query was made, the byte 1, the byte of the
/// last step's validity limit (0 or 1), and the query's sweep as 2 × 3n doubles (x0 then x1,
/// column-major); then, when a pair's penalty is stiffened (separation_floor.hpp), the byte
/// 2 and per pair its factor as a double. A state without the query part (older
/// checkpoints) loads too; the next step then queries. One without the factors has none.
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace pce::sim::contact {

/// The decoded state of one self-contact effect (see the file comment).
struct SavedContact {
  std::vector<std::array<int, 2>> pairs;  ///< the tracked pairs, sorted
  std::vector<signed char> sides;         ///< per pair: its settled side (−1, 0, 1)
  std::vector<char> declared;             ///< per pair: in the pattern (0, 1)
  bool with_query = false;                ///< the query's sweep follows
  bool validity_bound = false;            ///< the last step's validity limit bound
  Eigen::Matrix3Xd at, to;                ///< the query's sweep x0 → x1 (with_query)
  std::vector<double> stiffening;         ///< per pair: its stiffening factor; empty when all are 1
};

/// The bytes of `s` (its `at` and `to` are written when with_query).
std::string encode(const SavedContact& s);

/// Decodes `state` for an effect named `name` on a model of `vertices` vertices whose pairs
/// index below (`first_max`, `second_max`). Throws std::invalid_argument, naming the effect
/// and what does not fit, when `state` is not something `encode` writes for such a model.
SavedContact decode(const std::string& state, const char* name, long vertices, long first_max, long second_max);

}  // namespace pce::sim::contact

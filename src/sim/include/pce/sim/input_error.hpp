// SPDX-License-Identifier: MIT
/// @file
/// The one error type of `pce::sim`'s input side (scenes, meshes): every invalid input is
/// reported as one line naming the file, the place in it (a JSON path such as
/// `effects[2].penalty.dhat`, or `line 17`) and what was expected (contract §2,
/// `../shared/design/contracts.md`). Nothing is written before the input is accepted.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace pce::sim {

/// An invalid input: `what()` is the one line `file: where: what`.
class InputError : public std::runtime_error {
 public:
  /// `file: where: what` (a missing `where` is left out)
  InputError(std::string file, std::string where, const std::string& what)
      : std::runtime_error(file + ": " + (where.empty() ? std::string() : where + ": ") + what),
        file_(std::move(file)),
        where_(std::move(where)) {}
  /// The file the input came from.
  const std::string& file() const { return file_; }
  /// The JSON path or `line N` of the offending field; empty for the file as a whole.
  const std::string& where() const { return where_; }

 private:
  std::string file_, where_;
};

}  // namespace pce::sim

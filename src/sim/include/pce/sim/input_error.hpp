// SPDX-License-Identifier: MIT
/// @file
/// The two error types of `pce::sim`'s input side. `InputError`: an invalid scene or mesh
/// file, reported as one line naming the file, the place in it (a JSON path such as
/// `effects[2].penalty.distance`, or `line 17`) and what was expected (`docs/simulation.md`
/// §6.3). `ArgumentError`: an invalid argument to a C++ builder
/// (`pce/sim/effects.hpp`, `build_model`), naming the field. The scene loader calls the same
/// builders and turns their `ArgumentError` into an `InputError` at the field's JSON path.
/// Nothing is built or written before the input is accepted.
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

/// An invalid argument to a C++ builder: `what()` is the one line `field: expected`.
class ArgumentError : public std::invalid_argument {
 public:
  /// `field` names the argument as its scene key would (`stiffness`, `groups[1].vertices`,
  /// `meshes[0]`); empty when the input as a whole is at fault.
  ArgumentError(std::string field, std::string expected)
      : std::invalid_argument((field.empty() ? std::string() : field + ": ") + expected),
        field_(std::move(field)),
        expected_(std::move(expected)) {}
  /// The offending field, relative to the builder's arguments; empty for the whole input.
  const std::string& field() const { return field_; }
  /// What was expected (and what was given).
  const std::string& expected() const { return expected_; }

 private:
  std::string field_, expected_;
};

}  // namespace pce::sim

// SPDX-License-Identifier: MIT
/// @file
/// Typed, checked access to one JSON object of a scene, for the scene parser and the
/// effect factories. Every failed check throws `InputError(file, path, expected)` naming
/// the field's JSON path (`effects[2].penalty.dhat`) and what was expected, so effects
/// never touch JSON or format errors themselves. Internal to pce::sim.
#pragma once

#include <pce/core/enum_names.hpp>
#include <pce/sim/input_error.hpp>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <initializer_list>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace pce::sim {

class Params {
 public:
  /// `object` must be a JSON object (checked); `path` is its JSON path ("" for the root).
  Params(const nlohmann::json& object, std::string file, std::string path);

  const std::string& file() const { return file_; }
  bool has(const std::string& key) const;
  /// The JSON path of `key` inside this object.
  std::string path_of(const std::string& key) const;
  /// Throws InputError naming `key` and `what`.
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;

  /// A finite number; `lo`/`hi` are inclusive bounds (checked) and the default is used
  /// when the key is absent (required when no default is given).
  double number(const std::string& key, std::optional<double> fallback = std::nullopt,
                double lo = -std::numeric_limits<double>::max(), double hi = std::numeric_limits<double>::max()) const;
  /// A number > 0.
  double positive(const std::string& key, std::optional<double> fallback = std::nullopt) const;
  /// A number ≥ 0.
  double nonnegative(const std::string& key, std::optional<double> fallback = std::nullopt) const;
  /// An integer in [lo, hi].
  long integer(const std::string& key, std::optional<long> fallback = std::nullopt, long lo = 0,
               long hi = std::numeric_limits<int>::max()) const;
  bool boolean(const std::string& key, std::optional<bool> fallback = std::nullopt) const;
  std::string string(const std::string& key, std::optional<std::string> fallback = std::nullopt) const;
  /// The enumerator of `E` a string names (`pce::parse<E>`), any of `E`'s table; the
  /// error lists the table's names: `expected one of "a", "b", got "c"`.
  template <class E> E choice(const std::string& key, std::optional<E> fallback = std::nullopt) const {
    return choice_among(key, pce::enumerators<E>(), fallback);
  }
  /// The enumerator a string names, one of `allowed` (an array of enumerators, in the order
  /// the error lists their names).
  template <class Values> auto choice_among(const std::string& key, const Values& allowed,
                                            std::optional<typename Values::value_type> fallback = std::nullopt) const ->
      typename Values::value_type {
    using E = typename Values::value_type;
    if (!has(key) && fallback) return *fallback;
    const std::string v = string(key);
    if (const std::optional<E> e = pce::parse<E>(v))
      for (const E a : allowed)
        if (a == *e) return a;
    fail(key, "expected one of " + pce::quoted_names(allowed) + ", got \"" + v + "\"");
  }
  /// A 3-array of finite numbers.
  Eigen::Vector3d vec3(const std::string& key, std::optional<Eigen::Vector3d> fallback = std::nullopt) const;
  /// An array of integers in [0, hi).
  std::vector<int> indices(const std::string& key, long hi) const;
  /// The nested object at `key` (required).
  Params object(const std::string& key) const;
  /// The array at `key` (empty when absent and `required` is false).
  const nlohmann::json& array(const std::string& key, bool required = false) const;
  /// The i-th element of array `key`, which must be an object.
  Params element(const std::string& key, std::size_t i) const;
  /// Throws for any key not in `known` (catches typos such as "stifness").
  void only(std::initializer_list<const char*> known) const;

  /// Returns `make()`; an `ArgumentError` it throws (a typed builder's, naming a field
  /// relative to this object) becomes an `InputError` at that field's JSON path.
  template <class F> auto build(F&& make) const -> decltype(make()) {
    try {
      return make();
    } catch (const ArgumentError& e) {
      throw InputError(file_, join(e.field()), e.expected());
    }
  }
  /// The number at `key` (finite; `fallback` when absent) passed through a builder's argument
  /// check `check(field, value)` (`args::length`, …, effects/arguments.hpp), whose error
  /// names `key`'s JSON path.
  template <class Check>
  double checked(const std::string& key, Check check, std::optional<double> fallback = std::nullopt) const {
    const double v = number(key, fallback);
    return build([&] { return check(key, v); });
  }
  /// The 3-vector at `key` passed through `check(field, value)` (`args::position`, …).
  template <class Check> Eigen::Vector3d checked_vec3(const std::string& key, Check check,
                                                      std::optional<Eigen::Vector3d> fallback = std::nullopt) const {
    const Eigen::Vector3d v = vec3(key, fallback);
    return build([&] { return Eigen::Vector3d(check(key, v)); });
  }
  /// The JSON path of `field` (a key, `key[i].key`, `[i]`, or "" for this object) inside this object.
  std::string join(const std::string& field) const;

 private:
  const nlohmann::json& at(const std::string& key) const;
  const nlohmann::json* j_;
  std::string file_, path_;
};

}  // namespace pce::sim

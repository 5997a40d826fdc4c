// SPDX-License-Identifier: MIT
/// @file
/// Names, written once for pce::sim (internal): the element of a list that has a given name
/// (a model's mesh, an obstacle, a registered effect) and a list of names joined for a
/// message (`"a", "b"`). Lookups by name and lists of names in pce::sim's error messages go
/// through these.
#pragma once

#include <iterator>
#include <string>
#include <string_view>

namespace pce::sim {

/// The first element of `items` whose member `name` equals `name`, or null. `items` is any
/// range of objects with a `name` (`Model::meshes`, `Simulation::obstacles`, the effect
/// registry); the result points to const when `items` is const.
template <class Items> auto find_named(Items& items, const std::string& name) -> decltype(&*std::begin(items)) {
  for (auto& item : items)
    if (item.name == name) return &item;
  return nullptr;
}

/// The elements of `range`, in their order, each as `name_of(element)` (a string or a C
/// string; the element itself by default) between two `quote`s, joined by ", ": `"a", "b"`
/// with the default quote, `'a', 'b'` with "'", `a, b` with "". An empty range gives "".
template <class Range, class NameOf = std::string_view (*)(std::string_view)> std::string join_names(
    const Range& range, const std::string& quote = "\"", NameOf name_of = [](std::string_view name) { return name; }) {
  std::string list;
  bool first = true;
  for (const auto& element : range) {
    if (!first) list += ", ";
    list += quote;
    list += name_of(element);
    list += quote;
    first = false;
  }
  return list;
}

/// The `name` of each of `items` (objects with a `name`, as for `find_named`), joined as
/// `join_names` joins names: `"cloth", "floor"`.
template <class Items> std::string names_of(const Items& items, const std::string& quote = "\"") {
  return join_names(items, quote, [](const auto& item) -> std::string_view { return item.name; });
}

}  // namespace pce::sim

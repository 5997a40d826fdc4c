// SPDX-License-Identifier: MIT
/// @file
/// Names of enumerators, from one table per enumeration: an `EnumNames<E, N>` of
/// {enumerator, name} pairs declared next to the enumeration, with a function
/// `enum_names(E)` in the enumeration's namespace that returns it (found by
/// argument-dependent lookup). Everything that turns an enumerator into its name or a name
/// into its enumerator (scene files, command lines, Python, error messages) asks the table
/// through `name_of`, `parse` and `quoted_names`. Standard library only.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

namespace pce {

/// The names of an enumeration's enumerators: {enumerator, name} pairs, in the order that
/// lists of names (error messages, documentation, Python) show them.
template <class E, std::size_t N> using EnumNames = std::array<std::pair<E, std::string_view>, N>;

/// The table of `E`'s names (`enum_names(E{})`, declared next to `E`).
template <class E> constexpr const auto& names_of() { return enum_names(E{}); }

/// The name of `e` in its table; empty for a value the table does not list. Every name is a
/// string literal, so `name_of(e).data()` is a null-terminated string.
template <class E> constexpr auto name_of(E e) -> decltype(enum_names(E{}), std::string_view()) {
  for (const auto& entry : enum_names(E{}))
    if (entry.first == e) return entry.second;
  return {};
}

/// The enumerator of `E` named `name`; nothing for a name the table does not list.
template <class E> constexpr std::optional<E> parse(std::string_view name) {
  for (const auto& entry : enum_names(E{}))
    if (entry.second == name) return entry.first;
  return std::nullopt;
}

/// Every enumerator of `E`'s table, in its order.
template <class E> constexpr auto enumerators() {
  constexpr std::size_t n = std::tuple_size<std::decay_t<decltype(names_of<E>())>>::value;
  std::array<E, n> values{};
  for (std::size_t i = 0; i < n; ++i) values[i] = names_of<E>()[i].first;
  return values;
}

/// The names of `values` (a range of enumerators), each in double quotes, separated by
/// ", ": `"a", "b", "c"`.
template <class Values> std::string quoted_names(const Values& values) {
  std::string list;
  for (const auto e : values) {
    if (!list.empty()) list += ", ";
    list += '"';
    list += name_of(e);
    list += '"';
  }
  return list;
}

/// Every name of `E`'s table, in its order, each in double quotes, separated by ", ".
template <class E> std::string quoted_names() { return quoted_names(enumerators<E>()); }

}  // namespace pce

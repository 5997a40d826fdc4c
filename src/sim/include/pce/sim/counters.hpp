// SPDX-License-Identifier: MIT
/// @file
/// The counters of a frame's statistics (`stats.json`'s `counters`, docs/simulation.md
/// §6.1), typed: every counter is an enumerator with one name and one rule for merging the
/// reports of several effects (summed, or the smallest for the minimum distances). Effects
/// write them in `Effect::report`, the solver adds its own and merges the effects'.
#pragma once

#include <algorithm>
#include <array>
#include <bitset>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pce::sim {

/// Every counter of `stats.json` (the enumerator's name is the key).
enum class Counter : int {
  // self contact, per kind
  vertex_face_candidates,
  vertex_face_declared,
  vertex_face_rest_neighbours,
  vertex_face_fold_contacts,
  vertex_face_contacts,
  vertex_face_min_distance,
  edge_edge_candidates,
  edge_edge_declared,
  edge_edge_rest_neighbours,
  edge_edge_fold_contacts,
  edge_edge_contacts,
  edge_edge_min_distance,
  // friction, per kind of contact (reported only by effects with friction)
  vertex_face_friction_contacts,
  vertex_face_friction_sticking,
  vertex_face_friction_ms,
  edge_edge_friction_contacts,
  edge_edge_friction_sticking,
  edge_edge_friction_ms,
  obstacle_friction_contacts,
  obstacle_friction_sticking,
  obstacle_friction_ms,
  // self contact, summed over both kinds
  broad_phase_ms,
  broad_phase_tree_ms,
  broad_phase_queries,
  pair_ms,
  scatter_ms,
  // obstacle contact
  obstacle_contacts,
  obstacle_min_distance,
  // elastic effects and pins
  hinges,
  degenerate_hinges,
  joints,
  degenerate_joints,
  pinned_vertices,
  // volume elasticity, at the accepted state
  tetrahedra,
  inverted_tetrahedra,
  volume_ratio,
  // the solver
  pattern_ms,
  pattern_builds,
  pattern_blocks,
  analyze_ms,
  factorize_ms,
  analyses,
  factorizations,
  cg_iterations,
  count  ///< the number of counters (not a counter)
};

/// A counter's key in `stats.json` and whether several reports merge by their minimum
/// (distances) rather than their sum.
struct CounterInfo {
  const char* name;  ///< the key in `stats.json`
  bool minimum;      ///< several reports merge by their minimum (true) or their sum (false)
};

/// The name and merge rule of `c`.
inline const CounterInfo& counter_info(Counter c) {
  static constexpr std::array<CounterInfo, static_cast<std::size_t>(Counter::count)> table = {{
      {"vertex_face_candidates", false},
      {"vertex_face_declared", false},
      {"vertex_face_rest_neighbours", false},
      {"vertex_face_fold_contacts", false},
      {"vertex_face_contacts", false},
      {"vertex_face_min_distance", true},
      {"edge_edge_candidates", false},
      {"edge_edge_declared", false},
      {"edge_edge_rest_neighbours", false},
      {"edge_edge_fold_contacts", false},
      {"edge_edge_contacts", false},
      {"edge_edge_min_distance", true},
      {"vertex_face_friction_contacts", false},
      {"vertex_face_friction_sticking", false},
      {"vertex_face_friction_ms", false},
      {"edge_edge_friction_contacts", false},
      {"edge_edge_friction_sticking", false},
      {"edge_edge_friction_ms", false},
      {"obstacle_friction_contacts", false},
      {"obstacle_friction_sticking", false},
      {"obstacle_friction_ms", false},
      {"broad_phase_ms", false},
      {"broad_phase_tree_ms", false},
      {"broad_phase_queries", false},
      {"pair_ms", false},
      {"scatter_ms", false},
      {"obstacle_contacts", false},
      {"obstacle_min_distance", true},
      {"hinges", false},
      {"degenerate_hinges", false},
      {"joints", false},
      {"degenerate_joints", false},
      {"pinned_vertices", false},
      {"tetrahedra", false},
      {"inverted_tetrahedra", false},
      {"volume_ratio", false},
      {"pattern_ms", false},
      {"pattern_builds", false},
      {"pattern_blocks", false},
      {"analyze_ms", false},
      {"factorize_ms", false},
      {"analyses", false},
      {"factorizations", false},
      {"cg_iterations", false},
  }};
  return table[static_cast<std::size_t>(c)];
}

/// The counters one effect reports, or a frame's merged record: a value per `Counter`,
/// each either reported or absent (absent counters are not written to `stats.json`).
class Counters {
 public:
  /// The number of counters (`Counter::count`).
  static constexpr std::size_t kCount = static_cast<std::size_t>(Counter::count);

  /// The value of `c`, reported from now on (0 until written).
  double& operator[](Counter c) {
    present_.set(index(c));
    return values_[index(c)];
  }
  /// Whether `c` was reported.
  bool has(Counter c) const { return present_.test(index(c)); }
  /// The value of `c`; throws std::out_of_range when it was not reported.
  double at(Counter c) const {
    if (!has(c)) throw std::out_of_range(std::string("counter not reported: ") + counter_info(c).name);
    return values_[index(c)];
  }
  /// The value of the counter named `name` (its `stats.json` key); throws std::out_of_range
  /// when no counter has that name or it was not reported.
  double at(std::string_view name) const { return at(by_name(name)); }
  /// Whether the counter named `name` was reported (false for an unknown name).
  bool has(std::string_view name) const {
    for (std::size_t i = 0; i < kCount; ++i)
      if (name == counter_info(static_cast<Counter>(i)).name) return present_.test(i);
    return false;
  }
  /// Adds `other`'s reported counters: a counter reported by one side takes its value, by
  /// both their sum or, for a minimum (`CounterInfo::minimum`), the smaller.
  void merge(const Counters& other) {
    for (std::size_t i = 0; i < kCount; ++i) {
      if (!other.present_.test(i)) continue;
      if (!present_.test(i))
        values_[i] = other.values_[i];
      else if (counter_info(static_cast<Counter>(i)).minimum)
        values_[i] = std::min(values_[i], other.values_[i]);
      else
        values_[i] += other.values_[i];
      present_.set(i);
    }
  }
  /// (name, value) of every reported counter, in enumerator order.
  std::vector<std::pair<const char*, double>> entries() const {
    std::vector<std::pair<const char*, double>> out;
    for (std::size_t i = 0; i < kCount; ++i)
      if (present_.test(i)) out.emplace_back(counter_info(static_cast<Counter>(i)).name, values_[i]);
    return out;
  }

 private:
  static std::size_t index(Counter c) { return static_cast<std::size_t>(c); }
  static Counter by_name(std::string_view name) {
    for (std::size_t i = 0; i < kCount; ++i)
      if (name == counter_info(static_cast<Counter>(i)).name) return static_cast<Counter>(i);
    throw std::out_of_range("no counter named " + std::string(name));
  }
  std::array<double, kCount> values_{};
  std::bitset<kCount> present_;
};

}  // namespace pce::sim

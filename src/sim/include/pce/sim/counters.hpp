// SPDX-License-Identifier: MIT
/// @file
/// The counters of a frame's statistics (`stats.json`'s `counters`, docs/simulation.md
/// §6.1), typed: every counter is an enumerator with one name and one rule for merging the
/// reports of several effects (summed, or the smallest for the minimum distances), all
/// three generated from one list (`PCE_SIM_COUNTERS`). Effects
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

/// Every counter of `stats.json`, in enumerator order: `X(id, rule)` with `id` the
/// enumerator and its key, `rule` how several reports merge (`sum`, or `minimum` for the
/// minimum distances). The enumeration `Counter`, the names and the merge rules are all
/// generated from this list, so a counter cannot exist without its name and rule.
#define PCE_SIM_COUNTERS(X)                                                    \
  /* self contact, per kind */                                                 \
  X(vertex_face_candidates, sum)                                               \
  X(vertex_face_declared, sum)                                                 \
  X(vertex_face_rest_neighbours, sum)                                          \
  X(vertex_face_fold_contacts, sum)                                            \
  X(vertex_face_contacts, sum)                                                 \
  X(vertex_face_min_distance, minimum)                                         \
  X(edge_edge_candidates, sum)                                                 \
  X(edge_edge_declared, sum)                                                   \
  X(edge_edge_rest_neighbours, sum)                                            \
  X(edge_edge_fold_contacts, sum)                                              \
  X(edge_edge_contacts, sum)                                                   \
  X(edge_edge_min_distance, minimum)                                           \
  /* friction, per kind of contact (reported only by effects with friction) */ \
  X(vertex_face_friction_contacts, sum)                                        \
  X(vertex_face_friction_sticking, sum)                                        \
  X(vertex_face_friction_ms, sum)                                              \
  X(edge_edge_friction_contacts, sum)                                          \
  X(edge_edge_friction_sticking, sum)                                          \
  X(edge_edge_friction_ms, sum)                                                \
  X(obstacle_friction_contacts, sum)                                           \
  X(obstacle_friction_sticking, sum)                                           \
  X(obstacle_friction_ms, sum)                                                 \
  /* the minimum separation, every contact effect */                           \
  X(floor_holds, sum)                                                          \
  X(stiffened_pairs, sum)                                                      \
  /* self contact, summed over both kinds */                                   \
  X(broad_phase_ms, sum)                                                       \
  X(broad_phase_tree_ms, sum)                                                  \
  X(broad_phase_queries, sum)                                                  \
  X(pair_ms, sum)                                                              \
  X(scatter_ms, sum)                                                           \
  /* obstacle contact */                                                       \
  X(obstacle_contacts, sum)                                                    \
  X(obstacle_min_distance, minimum)                                            \
  /* elastic effects and pins */                                               \
  X(hinges, sum)                                                               \
  X(degenerate_hinges, sum)                                                    \
  X(joints, sum)                                                               \
  X(degenerate_joints, sum)                                                    \
  X(pinned_vertices, sum)                                                      \
  /* volume elasticity, at the accepted state */                               \
  X(tetrahedra, sum)                                                           \
  X(inverted_tetrahedra, sum)                                                  \
  X(volume_ratio, sum)                                                         \
  /* the solver */                                                             \
  X(pattern_ms, sum)                                                           \
  X(pattern_builds, sum)                                                       \
  X(pattern_blocks, sum)                                                       \
  X(analyze_ms, sum)                                                           \
  X(factorize_ms, sum)                                                         \
  X(analyses, sum)                                                             \
  X(factorizations, sum)                                                       \
  X(cg_iterations, sum)                                                        \
  X(preconditioner_setups, sum)                                                \
  X(preconditioner_ms, sum)                                                    \
  /* block descent */                                                          \
  X(colours, sum)                                                              \
  X(colourings, sum)                                                           \
  X(bound_measurements, sum)                                                   \
  X(bound_clamps, sum)                                                         \
  X(first_move, sum)

/// Expands one entry of `PCE_SIM_COUNTERS` to its enumerator (for `Counter`).
#define PCE_SIM_COUNTER_ENUMERATOR(id, rule) id,

/// Every counter of `stats.json` (the enumerator's name is the key; `PCE_SIM_COUNTERS`).
enum class Counter : int {
  // clang-format off
  PCE_SIM_COUNTERS(PCE_SIM_COUNTER_ENUMERATOR)
  // clang-format on
  count  ///< the number of counters (not a counter)
};

#undef PCE_SIM_COUNTER_ENUMERATOR

/// How several reports of one counter merge.
enum class CounterRule {
  sum,      ///< their sum
  minimum,  ///< the smallest (the minimum distances)
};

/// A counter's key in `stats.json` and whether several reports merge by their minimum
/// (distances) rather than their sum.
struct CounterInfo {
  const char* name;  ///< the key in `stats.json`
  bool minimum;      ///< several reports merge by their minimum (true) or their sum (false)
};

/// Expands one entry of `PCE_SIM_COUNTERS` to its `CounterInfo` (for `kCounterInfo`).
#define PCE_SIM_COUNTER_INFO(id, rule) {#id, CounterRule::rule == CounterRule::minimum},

/// Every counter's name and merge rule, indexed by `Counter` (from `PCE_SIM_COUNTERS`).
inline constexpr std::array<CounterInfo, static_cast<std::size_t>(Counter::count)> kCounterInfo{
    {PCE_SIM_COUNTERS(PCE_SIM_COUNTER_INFO)}};

#undef PCE_SIM_COUNTER_INFO

/// The name and merge rule of `c`.
inline const CounterInfo& counter_info(Counter c) { return kCounterInfo[static_cast<std::size_t>(c)]; }

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

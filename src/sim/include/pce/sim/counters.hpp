// SPDX-License-Identifier: MIT
/// @file
/// The counters of a frame's statistics (`stats.json`'s `counters`, docs/simulation.md
/// §6.1), typed: every counter is an enumerator with one name and one rule for merging the
/// reports of several effects and of a frame's substeps (summed, the smallest for the minimum
/// distances, or, for what describes the state, summed over effects and the last substep's),
/// all three generated from one list (`PCE_SIM_COUNTERS`). Effects
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
/// enumerator and its key, `rule` how several reports merge (`sum` for work done, `minimum`
/// for the minimum distances, `state` for counts and measures of the accepted state). The
/// enumeration `Counter`, the names and the merge rules are all
/// generated from this list, so a counter cannot exist without its name and rule.
#define PCE_SIM_COUNTERS(X)                                                    \
  /* self contact, per kind */                                                 \
  X(vertex_face_candidates, state)                                             \
  X(vertex_face_declared, state)                                               \
  X(vertex_face_rest_neighbours, state)                                        \
  X(vertex_face_fold_contacts, state)                                          \
  X(vertex_face_contacts, state)                                               \
  X(vertex_face_min_distance, minimum)                                         \
  X(edge_edge_candidates, state)                                               \
  X(edge_edge_declared, state)                                                 \
  X(edge_edge_rest_neighbours, state)                                          \
  X(edge_edge_fold_contacts, state)                                            \
  X(edge_edge_contacts, state)                                                 \
  X(edge_edge_min_distance, minimum)                                           \
  /* friction, per kind of contact (reported only by effects with friction) */ \
  X(vertex_face_friction_contacts, state)                                      \
  X(vertex_face_friction_sticking, state)                                      \
  X(vertex_face_friction_ms, sum)                                              \
  X(edge_edge_friction_contacts, state)                                        \
  X(edge_edge_friction_sticking, state)                                        \
  X(edge_edge_friction_ms, sum)                                                \
  X(obstacle_friction_contacts, state)                                         \
  X(obstacle_friction_sticking, state)                                         \
  X(obstacle_friction_ms, sum)                                                 \
  /* the minimum separation, every contact effect */                           \
  X(floor_holds, state)                                                        \
  X(stiffened_pairs, state)                                                    \
  /* self contact, summed over both kinds */                                   \
  X(broad_phase_ms, sum)                                                       \
  X(broad_phase_tree_ms, sum)                                                  \
  X(broad_phase_queries, sum)                                                  \
  X(pair_ms, sum)                                                              \
  X(scatter_ms, sum)                                                           \
  /* obstacle contact */                                                       \
  X(obstacle_contacts, state)                                                  \
  X(obstacle_min_distance, minimum)                                            \
  /* elastic effects and pins */                                               \
  X(hinges, state)                                                             \
  X(degenerate_hinges, state)                                                  \
  X(joints, state)                                                             \
  X(degenerate_joints, state)                                                  \
  X(pinned_vertices, state)                                                    \
  /* volume elasticity, at the accepted state */                               \
  X(tetrahedra, state)                                                         \
  X(inverted_tetrahedra, state)                                                \
  X(volume_ratio, state)                                                       \
  /* the solver */                                                             \
  X(pattern_ms, sum)                                                           \
  X(pattern_builds, sum)                                                       \
  X(pattern_blocks, state)                                                     \
  X(analyze_ms, sum)                                                           \
  X(factorize_ms, sum)                                                         \
  X(analyses, sum)                                                             \
  X(factorizations, sum)                                                       \
  X(cg_iterations, sum)                                                        \
  X(preconditioner_setups, sum)                                                \
  X(preconditioner_ms, sum)                                                    \
  /* block descent */                                                          \
  X(colours, state)                                                            \
  X(colourings, sum)                                                           \
  X(bound_measurements, sum)                                                   \
  X(bound_clamps, sum)                                                         \
  X(first_move, state)                                                         \
  X(accelerated_sweeps, sum)                                                   \
  X(acceleration_restarts, sum)

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
  sum,      ///< their sum (work: times, queries, factorisations, clamps)
  minimum,  ///< the smallest (the minimum distances)
  state,    ///< several effects' reports summed; of a frame's substeps, the last one's
};

/// A counter's key in `stats.json` and how several reports merge (`CounterRule`).
struct CounterInfo {
  const char* name;  ///< the key in `stats.json`
  bool minimum;      ///< several reports merge by their minimum (true) or their sum (false)
  bool state;        ///< a frame's substeps: the last one's report stands (`CounterRule::state`)
};

/// Expands one entry of `PCE_SIM_COUNTERS` to its `CounterInfo` (for `kCounterInfo`).
#define PCE_SIM_COUNTER_INFO(id, rule) \
  {#id, CounterRule::rule == CounterRule::minimum, CounterRule::rule == CounterRule::state},

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
  /// Adds the counters of a later substep of the same frame: a `state` counter it reports
  /// takes its value (the state it describes is the later one), the others merge as in `merge`.
  void follow(const Counters& later) {
    for (std::size_t i = 0; i < kCount; ++i)
      if (later.present_.test(i) && counter_info(static_cast<Counter>(i)).state) values_[i] = 0;
    merge(later);
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

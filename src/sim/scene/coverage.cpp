// SPDX-License-Identifier: MIT
// What each effect entry covers and the checks between the entries of one type
// (coverage.hpp). An entry covers units: meshes (gravity, stretching, …), mesh pairs a·M + b
// with a ≤ b (self contact), or (mesh, obstacle) pairs m·O + o (obstacle contact), for M
// meshes and O obstacles. The checks need only the model and the obstacles: no effect is
// built for them.
#include "coverage.hpp"

#include "../util/names.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <utility>

namespace pce::sim {

namespace {

/// The index in `model` of the mesh named by the JSON value `name` (at JSON path `where` of
/// `file`); an error for a value that is no string or no mesh's name.
int mesh_index(const nlohmann::json& name, const Model& model, const std::string& file, const std::string& where) {
  if (!name.is_string()) throw InputError(file, where, "expected a mesh name (a string)");
  const MeshRange* r = find_named(model.meshes, name.get<std::string>());
  if (!r)
    throw InputError(
        file, where,
        "unknown mesh \"" + name.get<std::string>() + "\" (the scene's meshes: " + names_of(model.meshes) + ")");
  return static_cast<int>(r - model.meshes.data());
}

/// What one effect entry covers, for the checks between the entries of its type.
struct Covered {
  std::size_t entry;        ///< k of `effects[k]`
  bool given;               ///< the entry has `meshes`
  std::vector<long> units;  ///< the units it covers, as the file comment numbers them
};

/// The units entry `e` covers: its meshes (every mesh without `meshes`), their pairs (or its
/// named pairs), or its meshes against its obstacles.
Covered covered_by(const EffectEntry& e, long mesh_count, long obstacle_count) {
  Covered c{e.index, e.meshes.given, {}};
  std::vector<int> meshes = e.meshes.meshes;
  if (!e.meshes.given)
    for (int m = 0; m < mesh_count; ++m) meshes.push_back(m);
  switch (e.type->coverage) {
    case Coverage::none:
      break;
    case Coverage::meshes:
      c.units.assign(meshes.begin(), meshes.end());
      break;
    case Coverage::mesh_pairs:
      if (!e.meshes.pairs.empty()) {
        for (const auto& [a, b] : e.meshes.pairs) c.units.push_back(a * mesh_count + b);
      } else {
        for (std::size_t i = 0; i < meshes.size(); ++i)
          for (std::size_t j = i; j < meshes.size(); ++j) c.units.push_back(meshes[i] * mesh_count + meshes[j]);
      }
      break;
    case Coverage::meshes_and_obstacles:
      for (const int m : meshes)
        for (const int o : e.obstacles) c.units.push_back(m * obstacle_count + o);
      break;
  }
  return c;
}

/// The checks between the entries of one type: `entries` are its entries, in scene order.
class TypeCoverage {
 public:
  TypeCoverage(const RegisteredEffect& type, std::vector<Covered> entries, const std::string& file, const Model& model,
               const std::vector<Obstacle>& obstacles)
      : type_(type),
        entries_(std::move(entries)),
        file_(file),
        model_(model),
        obstacles_(obstacles),
        mesh_count_(static_cast<long>(model.meshes.size())),
        obstacle_count_(static_cast<long>(obstacles.size())) {}

  /// Every check: the units entries name, their overlaps, then the gaps.
  void check() const { check_gaps(check_overlaps()); }

 private:
  /// Throws for a unit of an entry with `meshes` that has nothing the type acts on, and for
  /// a unit in two entries; returns each unit's entry (an index into `entries_`).
  std::map<long, std::size_t> check_overlaps() const {
    std::map<long, std::size_t> owner;
    for (std::size_t j = 0; j < entries_.size(); ++j) {
      const Covered& c = entries_[j];
      for (const long u : c.units) {
        if (c.given && !has_elements(u))
          throw InputError(file_, at(c), unit_name(u) + " has no " + type_.what + " for " + type_.name);
        const auto [it, fresh] = owner.emplace(u, j);
        if (!fresh)
          throw InputError(file_, at(c),
                           unit_name(u) + " is also covered by effects[" + std::to_string(entries_[it->second].entry) +
                               "] (" + type_.name + "): each takes one " + type_.name +
                               " entry (name each entry's \"meshes\")");
      }
    }
    return owner;
  }

  /// Throws for a unit with what the type acts on that no entry covers (every mesh, or mesh
  /// pair; for obstacle contact every mesh that meets no obstacle in any entry).
  void check_gaps(const std::map<long, std::size_t>& owner) const {
    std::vector<long> all;
    if (type_.coverage == Coverage::mesh_pairs) {
      for (long a = 0; a < mesh_count_; ++a)
        for (long b = a; b < mesh_count_; ++b) all.push_back(a * mesh_count_ + b);
    } else if (type_.coverage == Coverage::meshes) {
      for (long a = 0; a < mesh_count_; ++a) all.push_back(a);
    }
    for (const long u : all)
      if (has_elements(u) && !owner.count(u)) {
        std::vector<std::string> listed;
        for (const Covered& c : entries_) listed.push_back("effects[" + std::to_string(c.entry) + "]");
        throw InputError(file_, at(entries_.front()),
                         unit_name(u) + " (with " + type_.what + ") is in no " + type_.name + " entry (" +
                             join_names(listed, "") + "): name it in one");
      }
    if (type_.coverage != Coverage::meshes_and_obstacles) return;
    for (long m = 0; m < mesh_count_; ++m) {
      bool met = obstacle_count_ == 0;
      for (long o = 0; o < obstacle_count_ && !met; ++o) met = owner.count(m * obstacle_count_ + o) > 0;
      if (!met)
        throw InputError(file_, at(entries_.front()),
                         mesh_name(m) + " is in no obstacle_contact entry: name it in one");
    }
  }

  /// Whether unit `u` has what the type acts on (`RegisteredEffect::has`).
  bool has_elements(long u) const {
    if (type_.coverage == Coverage::mesh_pairs) return type_.has(mesh(u / mesh_count_), mesh(u % mesh_count_));
    const MeshRange& a = mesh(type_.coverage == Coverage::meshes_and_obstacles ? u / obstacle_count_ : u);
    return type_.has(a, a);
  }

  /// Unit `u` in messages: `mesh "a"`, `the mesh pair ["a", "b"]`, `mesh "a" against obstacle "floor"`.
  std::string unit_name(long u) const {
    switch (type_.coverage) {
      case Coverage::mesh_pairs:
        return "the mesh pair [\"" + mesh(u / mesh_count_).name + "\", \"" + mesh(u % mesh_count_).name + "\"]";
      case Coverage::meshes_and_obstacles:
        return mesh_name(u / obstacle_count_) + " against obstacle \"" +
               obstacles_[static_cast<std::size_t>(u % obstacle_count_)].name + "\"";
      default:
        return mesh_name(u);
    }
  }

  const MeshRange& mesh(long m) const { return model_.meshes[static_cast<std::size_t>(m)]; }
  std::string mesh_name(long m) const { return "mesh \"" + mesh(m).name + "\""; }
  /// An entry's JSON path in messages: its `meshes`, or the entry without them.
  static std::string at(const Covered& c) {
    return "effects[" + std::to_string(c.entry) + "]" + (c.given ? ".meshes" : "");
  }

  const RegisteredEffect& type_;
  const std::vector<Covered> entries_;
  const std::string& file_;
  const Model& model_;
  const std::vector<Obstacle>& obstacles_;
  const long mesh_count_, obstacle_count_;
};

}  // namespace

MeshSelection read_meshes(const Params& p, const Model& model, bool pairs_allowed) {
  MeshSelection s;
  if (!p.has("meshes")) return s;
  s.given = true;
  const nlohmann::json& list = p.array("meshes");
  if (list.empty()) p.fail("meshes", "expected at least one mesh name (leave the field out for every mesh)");
  const bool pairs = list[0].is_array();
  if (pairs && !pairs_allowed)
    throw InputError(p.file(), p.path_of("meshes") + "[0]", "expected a mesh name (pairs are for self contact)");
  std::set<int> named;
  std::set<std::array<int, 2>> seen;
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string where = p.path_of("meshes") + "[" + std::to_string(k) + "]";
    if (!pairs) {
      const int m = mesh_index(list[k], model, p.file(), where);
      if (!named.insert(m).second)
        throw InputError(p.file(), where,
                         "mesh \"" + model.meshes[static_cast<std::size_t>(m)].name + "\" named twice");
      continue;
    }
    if (!list[k].is_array() || list[k].size() != 2)
      throw InputError(p.file(), where, "expected a pair of mesh names, [\"a\", \"b\"] (or every entry a name)");
    const int a = mesh_index(list[k][0], model, p.file(), where + "[0]");
    const int b = mesh_index(list[k][1], model, p.file(), where + "[1]");
    const std::array<int, 2> pair{std::min(a, b), std::max(a, b)};
    if (!seen.insert(pair).second) throw InputError(p.file(), where, "pair named twice");
    s.pairs.push_back(pair);
    named.insert(a);
    named.insert(b);
  }
  s.meshes.assign(named.begin(), named.end());
  return s;
}

void check_coverage(const std::vector<EffectEntry>& entries, const std::string& file, const Model& model,
                    const std::vector<Obstacle>& obstacles) {
  const long mesh_count = static_cast<long>(model.meshes.size());
  const long obstacle_count = static_cast<long>(obstacles.size());
  std::vector<const RegisteredEffect*> types;  // in the order of their first entries
  std::map<const RegisteredEffect*, std::vector<Covered>> covered;
  for (const EffectEntry& e : entries) {
    if (e.type->coverage == Coverage::none) continue;
    if (!covered.count(e.type)) types.push_back(e.type);
    covered[e.type].push_back(covered_by(e, mesh_count, obstacle_count));
  }
  for (const RegisteredEffect* type : types)
    TypeCoverage(*type, std::move(covered[type]), file, model, obstacles).check();
}

}  // namespace pce::sim

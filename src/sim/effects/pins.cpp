// SPDX-License-Identifier: MIT
// Pins: stiff zero-length springs to target positions, E = ½ k Σ_{pinned i} |xᵢ − x̂ᵢ|²,
// grouped so that a group can be released at a frame (the hammock drops its sheets that
// way) or move rigidly. A group's target is its rest position x̄ᵢ, or with a `motion`
// x̂ᵢ(t) = c + d(t) + R(t)(x̄ᵢ − c) (pce/sim/obstacle.hpp, Motion::apply) at the end of the
// step, c the group's centre: d = v τ and R = exp([ω]× τ) for a constant velocity (the
// twist scene turns one end of a ribbon that way), or the keyframes' interpolated
// translation and rotation. A group is active for frames < release_frame (always without
// one). Targets set from outside (`PinsEffect::set_targets`) replace a group's rest
// positions or motion from the next step on.
#include "pins.hpp"

#include "arguments.hpp"
#include "util/names.hpp"

#include <pce/sim/effects.hpp>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

namespace pce::sim {

namespace {

/// A group as the effect runs it.
struct Group {
  std::vector<int> vertices;
  int release_frame = 0;  ///< 0: never released
  bool active = true;
  bool moving = false;  ///< has a motion; else the targets are the rest positions
  Motion motion;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  /// Targets set from outside (one column per vertex of the group), replacing the above.
  std::optional<Eigen::Matrix3Xd> set;
  /// The next begin_step writes the rest positions (a non-moving group's set targets were
  /// cleared).
  bool restore = false;
};

class Pins final : public PinsEffect {
 public:
  Pins(const Model& model, std::vector<Group> groups, double k)
      : PinsEffect("pins"),
        model_(&model),
        groups_(std::move(groups)),
        k_(k),
        target_(model.rest),
        holds_(static_cast<std::size_t>(model.vertex_count()), 0) {
    count_holds();
  }
  void begin_step(const StepContext& ctx) override {
    for (Group& g : groups_) {
      g.active = g.release_frame == 0 || ctx.frame < g.release_frame;
      if (!g.active) continue;
      if (g.set) {
        for (std::size_t j = 0; j < g.vertices.size(); ++j)
          target_.col(g.vertices[j]) = g.set->col(static_cast<Eigen::Index>(j));
      } else if (g.moving) {
        for (int i : g.vertices) target_.col(i) = g.motion.apply(ctx.time, g.centre, model_->rest.col(i));
      } else if (g.restore) {
        for (int i : g.vertices) target_.col(i) = model_->rest.col(i);
        g.restore = false;
      }
    }
    count_holds();
  }

  int group_count() const override { return static_cast<int>(groups_.size()); }

  const std::vector<int>& group_vertices(int group) const override { return groups_[checked(group)].vertices; }

  Eigen::Matrix3Xd group_targets(int group) const override {
    const Group& g = groups_[checked(group)];
    if (g.set) return *g.set;
    Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(g.vertices.size()));
    for (std::size_t j = 0; j < g.vertices.size(); ++j)
      out.col(static_cast<Eigen::Index>(j)) = target_.col(g.vertices[j]);
    return out;
  }

  void set_targets(int group, const Eigen::Matrix3Xd& targets) override {
    Group& g = groups_[checked(group)];
    if (targets.cols() != static_cast<Eigen::Index>(g.vertices.size()))
      throw ArgumentError("targets", "expected one target per vertex of group " + std::to_string(group) + " (" +
                                         std::to_string(g.vertices.size()) + "), got " +
                                         std::to_string(targets.cols()));
    for (Eigen::Index j = 0; j < targets.cols(); ++j)
      args::position("targets[" + std::to_string(j) + "]", targets.col(j));
    g.set = targets;
    g.restore = false;
  }

  void clear_targets(int group) override {
    Group& g = groups_[checked(group)];
    if (g.set && !g.moving) g.restore = true;
    g.set.reset();
  }
  void declare(Pattern& pattern) const override {
    for (const Group& g : groups_)
      if (g.active)
        for (int i : g.vertices) pattern.add(i);
  }
  /// E = ½ k Σ |xᵢ − x̂ᵢ|², ∇ᵢE = k (xᵢ − x̂ᵢ), ∇²ᵢᵢE = k I over the active groups.
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) override {
    double energy = 0;
    const Eigen::Matrix3d K = k_ * Eigen::Matrix3d::Identity();
    for (const Group& g : groups_) {
      if (!g.active) continue;
      for (int i : g.vertices) {
        const Eigen::Vector3d d = x.col(i) - target_.col(i);
        energy += 0.5 * k_ * d.squaredNorm();
        if (gradient) gradient->col(i) += k_ * d;
        if (hessian) hessian->add_block(i, i, K);
      }
    }
    return energy;
  }
  /// ∇ᵢE = c k (xᵢ − x̂ᵢ) and ∇²ᵢᵢE = c k I, c the active groups holding vertex i.
  void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) override {
    for (std::size_t j = 0; j < vertices.size(); ++j) {
      const int i = vertices[j];
      const int c = holds_[static_cast<std::size_t>(i)];
      if (c == 0) continue;
      terms.gradient.col(static_cast<Eigen::Index>(j)) += c * k_ * (x.col(i) - target_.col(i));
      terms.hessian[j] += c * k_ * Eigen::Matrix3d::Identity();
    }
  }
  void report(EffectCounters& counters) const override {
    double pinned = 0;
    for (const Group& g : groups_)
      if (g.active) pinned += static_cast<double>(g.vertices.size());
    counters[Counter::pinned_vertices] = pinned;
  }

 private:
  const Model* model_;
  std::vector<Group> groups_;
  double k_;
  Eigen::Matrix3Xd target_;  ///< x̂ per vertex (rest positions but for moving groups)
  std::vector<int> holds_;   ///< per vertex: the active groups holding it

  /// `group` as an index of groups_; throws ArgumentError ("group") when it is none.
  std::size_t checked(int group) const {
    if (group < 0 || group >= group_count())
      throw ArgumentError("group", "expected a pin group index in [0, " + std::to_string(group_count()) + "), got " +
                                       std::to_string(group));
    return static_cast<std::size_t>(group);
  }

  /// Counts, per vertex, the active groups holding it.
  void count_holds() {
    std::fill(holds_.begin(), holds_.end(), 0);
    for (const Group& g : groups_)
      if (g.active)
        for (int i : g.vertices) ++holds_[static_cast<std::size_t>(i)];
  }
};

}  // namespace

const MeshRange* find_mesh(const Model& model, const std::string& name) { return find_named(model.meshes, name); }

std::vector<int> vertices_in_box(const Model& model, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                 const std::string& mesh) {
  args::finite("min", lo);
  args::finite("max", hi);
  if (!(lo.array() <= hi.array()).all()) throw ArgumentError("max", "expected max >= min in every coordinate");
  int first = 0, size = model.vertex_count();
  if (!mesh.empty()) {
    const MeshRange* r = find_mesh(model, mesh);
    if (!r) throw ArgumentError("mesh", "no mesh named \"" + mesh + "\"");
    first = r->first_vertex, size = r->vertex_count;
  }
  std::vector<int> inside;
  for (int i = first; i < first + size; ++i) {
    const Eigen::Vector3d p = model.rest.col(i);
    if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) inside.push_back(i);
  }
  return inside;
}

std::unique_ptr<PinsEffect> make_pins(const Model& model, std::vector<PinGroup> groups, double stiffness) {
  const double k = args::stiffness("stiffness", stiffness);
  if (groups.empty()) throw ArgumentError("groups", "expected at least one pin group");
  std::vector<Group> run;
  for (std::size_t gi = 0; gi < groups.size(); ++gi) {
    const PinGroup& g = groups[gi];
    const std::string at = "groups[" + std::to_string(gi) + "]";
    if (g.vertices.empty()) throw ArgumentError(at + ".vertices", "expected at least one vertex index");
    for (std::size_t j = 0; j < g.vertices.size(); ++j)
      if (g.vertices[j] < 0 || g.vertices[j] >= model.vertex_count())
        throw ArgumentError(at + ".vertices[" + std::to_string(j) + "]", "expected a vertex index in [0, " +
                                                                             std::to_string(model.vertex_count()) +
                                                                             "), got " + std::to_string(g.vertices[j]));
    if (g.release_frame < 0)
      throw ArgumentError(at + ".release_frame",
                          "expected a frame >= 1 (0: never released), got " + std::to_string(g.release_frame));
    Group group;
    group.vertices = g.vertices;
    group.release_frame = g.release_frame;
    if (g.motion) {
      args::motion(at + ".motion", *g.motion);
      group.motion = *g.motion;
      group.moving = true;
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (int i : group.vertices) centroid += model.rest.col(i);
      group.centre = g.centre ? args::position(at + ".motion.center", *g.centre)
                              : Eigen::Vector3d(centroid / static_cast<double>(group.vertices.size()));
    }
    run.push_back(std::move(group));
  }
  return std::make_unique<Pins>(model, std::move(run), k);
}

}  // namespace pce::sim

// SPDX-License-Identifier: MIT
/// @file
/// `obstacle_contact`: pushes every deformable vertex out of the kinematic obstacles (its
/// scene form and loader: effect_loaders.hpp and .cpp, next to the scene parser). This file
/// wires the rooms of effects/obstacle/, one job each:
///  * the obstacles (obstacle_set.*): shapes, poses at the step's end and start, which
///    vertices take part, and the near-pair visitor every pass goes through;
///  * the penalties (obstacle_penalties.*): E = Σᵢ Σₖ wᵢₖ ψ(dₖ(xᵢ)), its gradient and PSD
///    Hessian, and block descent's per-vertex terms;
///  * the step bounds (obstacle_bounds.*): Newton's line-search bound (a barrier's domain
///    and the minimum separation) and block descent's per-vertex bounds;
///  * the minimum separation (obstacle_floor.*, effects/floor.hpp, the same mechanism as self
///    contact's): held pairs' stiffening, kept in checkpoints;
///  * friction (obstacle_friction.*): the pairs active at the step's start, frozen.
/// Area weighting (`area_weighted`): vertex i's energy is Aᵢ ψ(d), Aᵢ its lumped rest area. A
/// vertex inside a volume (`Model::surface_vertex`) takes part in no obstacle contact: only a
/// volume's surface does.
#include "effects/obstacle/obstacle_bounds.hpp"
#include "effects/obstacle/obstacle_floor.hpp"
#include "effects/obstacle/obstacle_friction.hpp"
#include "effects/obstacle/obstacle_penalties.hpp"
#include "effects/obstacle/obstacle_set.hpp"

#include <pce/sim/contact_effect.hpp>
#include <pce/sim/effects.hpp>

#include <optional>
#include <string>
#include <vector>

namespace pce::sim {

namespace {

class ObstacleContact final : public ContactEffect {
 public:
  ObstacleContact(const ObstacleContactSettings& settings, std::vector<Obstacle> obstacles, Eigen::VectorXd areas,
                  std::vector<char> surface, long vertices)
      : ContactEffect("obstacle_contact"),
        set_(std::move(obstacles), std::move(surface)),
        floor_(set_, settings.min_separation * settings.penalty.distance, vertices),
        penalties_(settings.penalty, set_, floor_, std::move(areas)),
        bounds_(set_, floor_.floor(), settings.penalty.barrier()) {
    if (settings.friction) friction_.emplace(*settings.friction, set_, penalties_);
  }

  void begin_step(const StepContext& ctx) override {
    set_.place(ctx, friction_.has_value());
    floor_.begin_step(*ctx.x_start, penalties_.penalty().distance);
    if (friction_) friction_->begin_step(ctx);
  }

  /// Only diagonal blocks, which every pattern holds.
  void declare(Pattern& /*pattern*/) const override {}

  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) override {
    double energy = penalties_.evaluate(x, gradient, hessian);
    if (penalties_.left_domain()) return energy;
    if (friction_) energy += friction_->evaluate(x, gradient, hessian);
    return energy;
  }

  /// Block descent's local terms: vertex by vertex, its pairs' penalties and frozen friction.
  void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) override {
    const long count = static_cast<long>(vertices.size());
    visit_penalty(penalties_.penalty(), [&](const auto& penalty) {
#pragma omp parallel for schedule(dynamic, 256) if (count >= 64)
      for (long j = 0; j < count; ++j) {
        const int i = vertices[static_cast<std::size_t>(j)];
        if (!set_.takes_part(i)) continue;
        Eigen::Vector3d g = Eigen::Vector3d::Zero();
        Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
        penalties_.add_local(penalty, x.col(i), i, g, H);
        if (friction_) friction_->add_local(x, i, g, H);
        terms.gradient.col(j) += g;
        terms.hessian[static_cast<std::size_t>(j)] += H;
        if (!g.isZero(0) || !H.isZero(0)) terms.contact[static_cast<std::size_t>(j)] = 1;
      }
    });
  }

  double begin_line_search(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) override {
    return bounds_.line_search_bound(x, dx);
  }

  /// The pairs the line search's bound held at their floor that it pressed in are stiffened.
  bool end_line_search(const Eigen::Matrix3Xd& x) override {
    return !bounds_.held().empty() && floor_.stiffen(x, bounds_.held());
  }

  bool end_solve(const Eigen::Matrix3Xd& x) override { return friction_ && friction_->end_solve(x); }

  const std::vector<FrozenFriction>& frozen_friction() const override {
    return friction_ ? friction_->published() : NewtonHooks::frozen_friction();
  }

  double safe_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) override { return bounds_.safe_step(x, dx); }

  void limit_moves(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, Eigen::VectorXd& limit) override {
    bounds_.limit_moves(x, dx, limit);
  }

  void vertex_bounds(const Eigen::Matrix3Xd& x, Eigen::VectorXd& bound) override { bounds_.vertex_bounds(x, bound); }

  std::string save_state() const override { return floor_.save(); }

  void load_state(const std::string& state) override { floor_.load(state, name()); }

  void report(EffectCounters& counters) const override {
    counters[Counter::obstacle_contacts] = static_cast<double>(penalties_.contacts());
    counters[Counter::obstacle_min_distance] = penalties_.min_distance();
    counters[Counter::floor_holds] = static_cast<double>(floor_.holds());
    counters[Counter::stiffened_pairs] = static_cast<double>(floor_.stiffened());
    if (friction_) friction_->report(counters);
  }

 private:
  obstacle::ObstacleSet set_;
  obstacle::ObstacleFloor floor_;
  obstacle::ObstaclePenalties penalties_;
  obstacle::ObstacleBounds bounds_;
  std::optional<obstacle::ObstacleFriction> friction_;
};

/// Throws ArgumentError (field `obstacles[k].…`) unless `o` is a shape the distances handle.
void check_obstacle(const Obstacle& o, const std::string& at) {
  switch (o.kind) {
    case ShapeKind::sphere:
      args::length(at + ".radius", o.radius);
      break;
    case ShapeKind::box:
      args::position(at + ".half_extents", o.half_extents);
      if (!(o.half_extents.minCoeff() > 0))
        throw ArgumentError(at + ".half_extents", "expected three finite numbers > 0");
      break;
    case ShapeKind::capsule:
      args::length(at + ".radius", o.radius);
      args::length(at + ".half_length", o.half_length);
      break;
    case ShapeKind::mesh:
      if (o.mesh.triangles.cols() == 0) throw ArgumentError(at + ".mesh", "a mesh obstacle needs triangles");
      try {
        validate(o.mesh, o.name);
      } catch (const InputError& e) {
        throw ArgumentError(at + ".mesh", e.what());
      }
      break;
    default:
      throw ArgumentError(at + ".kind", "expected sphere, box, capsule or mesh");
  }
  args::position(at + ".position", o.position);
  args::rotation(at + ".rotation", o.rotation);
  args::motion(at + ".motion", o.motion);
}

}  // namespace

std::unique_ptr<ContactEffect> make_obstacle_contact(const std::vector<Obstacle>& obstacles,
                                                     const ContactPenalty& penalty) {
  ObstacleContactSettings settings;
  settings.penalty = penalty;
  return make_obstacle_contact(Model{}, obstacles, settings);  // unweighted: the model is not read
}

std::unique_ptr<ContactEffect> make_obstacle_contact(const Model& model, const std::vector<Obstacle>& obstacles,
                                                     const ObstacleContactSettings& settings) {
  check_penalty(settings.penalty, "penalty.");
  check_friction(settings.friction);
  check_min_separation(settings.min_separation);
  for (std::size_t k = 0; k < obstacles.size(); ++k)
    check_obstacle(obstacles[k], "obstacles[" + std::to_string(k) + "]");
  Eigen::VectorXd areas;
  if (settings.area_weighted) {
    areas = rest_areas(model).vertex;
    for (Eigen::Index i = 0; i < areas.size(); ++i)
      if (!(areas[i] > 0) && model.is_surface_vertex(i))  // a volume's inner vertices take no part
        throw ArgumentError("area_weighted", "vertex " + std::to_string(i) +
                                                 " is no corner of a triangle of positive area (a strand vertex?): it "
                                                 "has no area to weigh its contact by");
  }
  return std::make_unique<ObstacleContact>(settings, obstacles, std::move(areas), model.surface_vertex,
                                           model.vertex_count());
}

}  // namespace pce::sim

// SPDX-License-Identifier: MIT
/// @file
/// `obstacle_contact`: pushes every deformable vertex out of the kinematic obstacles (its
/// scene form and loader: effect_loaders.hpp and .cpp, next to the scene parser).
///
/// Energy: E(x) = Σᵢ Σₖ ψ(dₖ(xᵢ)), dₖ the signed distance from vertex i to obstacle k's
/// surface at the obstacle's pose at the END of the step (`surface_distance`), summed over
/// the pairs with dₖ < the penalty's activation distance (ψ = 0 beyond it).
/// Gradient: ψ′(d) n (∇d = n, the outward unit normal at the closest surface point).
/// Hessian: ∇²E = ψ″ n nᵀ + ψ′ ∇n. For a convex shape (sphere, box, capsule) ∇n is
/// positive semidefinite with n in its null space (for a sphere ∇n = (I − n nᵀ)/|x − c|),
/// and ψ′ ≤ 0 where ψ is active, so ψ′ ∇n is negative semidefinite and shares the
/// eigenvector n: the exact PSD projection of ∇²E is max(ψ″, 0) n nᵀ, which is what is
/// assembled. For a mesh obstacle (unsigned distance to a non-convex surface) the same
/// matrix is the Gauss-Newton approximation, not the exact projection.
///
/// Log barrier: the energy is +∞ (returned, not thrown) when a vertex sits at d ≤ 0, and
/// the line search's bound (`begin_line_search`) keeps every distance positive: since d is 1-Lipschitz in the vertex
/// position, t ≤ 0.9 d / |Δxᵢ| leaves d ≥ 0.1 d > 0 all along the segment.
///
/// Minimum separation (`min_separation` f, docs/simulation.md §4.6): a solve that ends with
/// a vertex closer than f·d to an obstacle's surface (at the end pose), which was not that
/// close at the step's start or has come closer, multiplies that pair's penalty stiffness by
/// kFloorStiffening (16) and the step is solved again from there (`end_solve`, as
/// friction's lagged iterations), up to 8 times a step. A pair held so has a strict floor
/// from then on: a trial that brings it below f·d (or, already below at the iterate,
/// closer) is outside the energy's domain (+∞, as a barrier's), and when the line search
/// finds no trial the pair is stiffened again (`end_line_search`). The factor stays until the
/// pair is beyond d at a step's start. Newton's iterates within a solve may pass the floor
/// otherwise (an obstacle is rigid and its distance signed: a penalty pushes a vertex that
/// passed its surface back out), so a step whose solves end above it is computed as
/// without one.
///
/// Area weighting (`area_weighted`): vertex i's energy is Aᵢ ψ(d), Aᵢ its lumped rest area
/// (the penalty evaluated with stiffness Aᵢ k, which ψ is linear in).
///
/// A vertex inside a volume (`Model::surface_vertex`) takes part in no obstacle contact: only
/// a volume's surface does.
///
/// Friction (`friction`): at the step's start every active (vertex, obstacle) pair is frozen
/// with λ = −ψ′(d) (weighted), the tangent basis of its normal, and the displacement over
/// the step of the obstacle's surface point nearest the vertex (its rigid motion from the
/// step's start pose to its end pose): the vertex's slip is its displacement less that one
/// (friction.hpp, pce/friction/lagged_friction.hpp). With `lagged_iterations` n > 1, after
/// each of the first n − 1 solves the pairs are frozen again at the solve's result with the
/// end poses.
///
/// Culling: a vertex is skipped for obstacle k when |xᵢ − cₖ| − Rₖ ≥ activation distance,
/// with cₖ the obstacle's origin and Rₖ the radius of a sphere about it that bounds the
/// shape (d ≥ |xᵢ − cₖ| − Rₖ for every shape).
#include "effects/contact/ordered_chunks.hpp"
#include "effects/friction.hpp"
#include "effects/vertex_incidence.hpp"
#include "effects/contact_penalty.hpp"
#include "util/stopwatch.hpp"

#include <pce/sim/contact_effect.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace pce::sim {

namespace {

/// Radius of a sphere about the obstacle's origin containing the whole shape.
double bounding_radius(const Obstacle& o) {
  switch (o.kind) {
    case ShapeKind::sphere:
      return o.radius;
    case ShapeKind::box:
      return o.half_extents.norm();
    case ShapeKind::capsule:
      return o.half_length + o.radius;
    case ShapeKind::mesh: {
      double r = 0;
      for (Eigen::Index v = 0; v < o.mesh.positions.cols(); ++v) r = std::max(r, o.mesh.positions.col(v).norm());
      return r;
    }
  }
  return std::numeric_limits<double>::infinity();
}

class ObstacleContact final : public ContactEffect {
 public:
  ObstacleContact(const ObstacleContactSettings& settings, std::vector<Obstacle> obstacles, Eigen::VectorXd areas,
                  std::vector<char> surface, long vertices)
      : ContactEffect("obstacle_contact"),
        penalty_(settings.penalty),
        floor_(settings.min_separation * settings.penalty.distance),
        friction_(settings.friction),
        obstacles_(std::move(obstacles)),
        areas_(std::move(areas)),
        surface_(std::move(surface)),
        surface_count_(vertices) {
    radius_.reserve(obstacles_.size());
    for (const Obstacle& o : obstacles_) radius_.push_back(bounding_radius(o));
    poses_.assign(obstacles_.size(), Eigen::Isometry3d::Identity());
    for (std::size_t k = 0; k < obstacles_.size(); ++k) poses_[k] = obstacles_[k].pose(0.0);
    start_poses_ = poses_;
  }

  void begin_step(const StepContext& ctx) override {
    for (std::size_t k = 0; k < obstacles_.size(); ++k) {
      const Obstacle& o = posed(ctx, k);
      poses_[k] = o.pose(ctx.time);
      if (friction_) start_poses_[k] = o.pose(ctx.time - ctx.dt);
    }
    forget_stiffening(*ctx.x_start);
    x_step_start_ = ctx.x_start;
    floor_solves_ = 0;
    if (!friction_) return;
    friction_stats_ = {};
    const ScopedTimer timer(friction_stats_.ms);
    x_start_ = ctx.x_start;
    slip_ = friction_->slip_velocity * ctx.dt;
    rounds_ = 1;
    freeze(*ctx.x_start, true);
  }

  bool end_solve(const Eigen::Matrix3Xd& x) override {
    const bool stiffened = stiffen_below(x);
    if (!friction_ || rounds_ >= friction_->lagged_iterations) return stiffened;
    const ScopedTimer timer(friction_stats_.ms);
    ++rounds_;
    freeze(x, false);
    return true;
  }

  /// Only diagonal blocks, which every pattern holds.
  void declare(Pattern& /*pattern*/) const override {}

  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) override {
    const bool blocked = visit_penalty(penalty_, [&](const auto& penalty) { return gather(x, penalty); });
    if (blocked) return std::numeric_limits<double>::infinity();
    double energy = contact::scatter(terms_, gradient, hessian);
    if (friction_) {
      const ScopedTimer timer(friction_stats_.ms);
      energy += add_friction(frozen_, x, *x_start_, gradient, hessian, friction_stats_.sticking);
    }
    return energy;
  }

  double begin_line_search(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) override {
    pressed_.clear();
    if (!penalty_.barrier()) return 1.0;
    return contact::min_over_chunks(x.cols(), kChunk, 1.0, [&](std::size_t, long begin, long end, double& t) {
      for (long i = begin; i < end; ++i) {
        if (!surface_.empty() && !surface_[static_cast<std::size_t>(i)]) continue;  // inside a volume
        const double step = dx.col(i).norm();
        if (!(step > 0)) continue;
        const Eigen::Vector3d p = x.col(i);
        for (std::size_t k = 0; k < obstacles_.size(); ++k) {
          if ((p - poses_[k].translation()).norm() - radius_[k] > step) continue;  // d > |Δx|: t = 1 is safe
          const double d = surface_distance(obstacles_[k], poses_[k], p).distance;
          if (d > 0) t = std::min(t, 0.9 * d / step);  // d ≤ 0: already outside the domain, nothing to keep
        }
      }
    });
  }

  /// Block descent's first move: as begin_line_search's bound, for every penalty (a vertex keeps its floor, or
  /// nine tenths of its distance when closer; one inside an obstacle is not limited).
  double safe_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) override {
    return contact::min_over_chunks(x.cols(), kChunk, 1.0, [&](std::size_t, long begin, long end, double& t) {
      for (long i = begin; i < end; ++i) t = std::min(t, move_limit(x, dx, i));
    });
  }

  /// Block descent's first move, per vertex: the fraction of dxᵢ that keeps vertex i's room
  /// (safe_step's rule for one vertex).
  void limit_moves(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, Eigen::VectorXd& limit) override {
#pragma omp parallel for schedule(dynamic, kChunk) if (x.cols() > kChunk)
    for (Eigen::Index i = 0; i < x.cols(); ++i) limit[i] = std::min(limit[i], move_limit(x, dx, i));
  }

  /// Block descent: vertex i may move 0.9 (d − F) towards obstacle k's surface, d its
  /// distance at x (at the step's end pose, which the obstacle keeps during the sweeps) and F
  /// the floor (0.09 d when d ≤ F; inside, d ≤ 0, no limit: the penalty pushes it out).
  void vertex_bounds(const Eigen::Matrix3Xd& x, Eigen::VectorXd& bound) override {
#pragma omp parallel for schedule(dynamic, kChunk) if (x.cols() > kChunk)
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      if (!surface_.empty() && !surface_[static_cast<std::size_t>(i)]) continue;
      const Eigen::Vector3d p = x.col(i);
      for (std::size_t k = 0; k < obstacles_.size(); ++k) {
        const double lower = (p - poses_[k].translation()).norm() - radius_[k];  // d ≥ lower
        if (lower > 0 && room(lower) >= bound[i]) continue;
        const double d = surface_distance(obstacles_[k], poses_[k], p).distance;
        if (d > 0) bound[i] = std::min(bound[i], room(d));
      }
    }
  }

  /// Block descent's local terms: vertex by vertex, the pairs of `gather` and its frozen
  /// friction (a held pair's strict floor is the bounds' to keep).
  void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) override {
    const long count = static_cast<long>(vertices.size());
    const double reach = penalty_.distance;
    visit_penalty(penalty_, [&](const auto& penalty) {
#pragma omp parallel for schedule(dynamic, 256) if (count >= 64)
      for (long j = 0; j < count; ++j) {
        const int i = vertices[static_cast<std::size_t>(j)];
        if (!surface_.empty() && !surface_[static_cast<std::size_t>(i)]) continue;
        const Eigen::Vector3d p = x.col(i);
        Eigen::Vector3d g = Eigen::Vector3d::Zero();
        Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
        for (std::size_t k = 0; k < obstacles_.size(); ++k) {
          if ((p - poses_[k].translation()).norm() - radius_[k] >= reach) continue;
          const SurfaceDistance s = surface_distance(obstacles_[k], poses_[k], p);
          if (!(s.distance < reach) || (penalty_.barrier() && !(s.distance > 0))) continue;
          const PenaltyDerivatives<double> psi = weighted(penalty, i, k).evaluate(s.distance);
          g += psi.first * s.normal;
          if (psi.second > 0) H += psi.second * (s.normal * s.normal.transpose());
        }
        if (friction_ && friction_incidence_.has(i))
          for (const Incident* e = friction_incidence_.begin(i); e != friction_incidence_.end(i); ++e)
            add_friction_local(frozen_[static_cast<std::size_t>(e->item)], e->slot, x, *x_start_, g, H);
        terms.gradient.col(j) += g;
        terms.hessian[static_cast<std::size_t>(j)] += H;
      }
    });
  }

  /// A Newton iteration begins at the iterate x: the held pairs (stiffening above 1) closer
  /// than the floor there, which the floor then keeps no closer than they are. The pattern
  /// is unchanged (diagonal blocks only).
  bool begin_iteration(const Eigen::Matrix3Xd& x) override {
    below_.clear();
    slack_ = kFloorRounding * std::max(x.cwiseAbs().maxCoeff(), 1.0);
    for (std::size_t j = 0; j < stiffening_.size(); ++j) {
      if (stiffening_[j] == 1.0) continue;
      const double d = pair_distance(x, j);
      if (d < floor_) below_.push_back({j, d});
    }
    return false;
  }

  bool end_line_search(const Eigen::Matrix3Xd& x) override {
    // the held pairs whose floor refused a trial of the line search, if x has them
    // within three floors (pressed in, not the full step's overshoot)
    bool any = false;
    std::sort(pressed_.begin(), pressed_.end());
    pressed_.erase(std::unique(pressed_.begin(), pressed_.end()), pressed_.end());
    for (const std::size_t j : pressed_)
      if (pair_distance(x, j) < 3 * floor_) any = stiffen_pair(j, x.cols()) || any;
    pressed_.clear();
    return any;
  }

  std::string save_state() const override {
    std::string out;
    for (std::size_t j = 0; j < stiffening_.size(); ++j) {
      if (stiffening_[j] == 1.0) continue;
      const std::uint64_t index = j;
      out.append(reinterpret_cast<const char*>(&index), sizeof index);
      out.append(reinterpret_cast<const char*>(&stiffening_[j]), sizeof(double));
    }
    return out;
  }

  void load_state(const std::string& state) override {
    constexpr std::size_t record = sizeof(std::uint64_t) + sizeof(double);
    if (state.size() % record != 0)
      throw std::invalid_argument(std::string(name()) + ": the saved state's size is not a whole number of records");
    std::vector<double> loaded;
    for (std::size_t at = 0; at < state.size(); at += record) {
      std::uint64_t index = 0;
      double factor = 0;
      std::memcpy(&index, state.data() + at, sizeof index);
      std::memcpy(&factor, state.data() + at + sizeof index, sizeof factor);
      const std::size_t size = static_cast<std::size_t>(surface_count_) * obstacles_.size();
      if (!(index < size) || !(factor >= 1 && std::isfinite(factor)))
        throw std::invalid_argument(std::string(name()) +
                                    ": a saved stiffening factor does not fit this scene (vertex and obstacle index, "
                                    "a finite factor >= 1)");
      if (loaded.empty()) loaded.assign(size, 1.0);
      loaded[index] = factor;
    }
    stiffening_ = std::move(loaded);
  }

  const std::vector<FrozenFriction>& frozen_friction() const override { return published_; }

  void report(EffectCounters& counters) const override {
    long contacts = 0;
    terms_.for_each([&](const contact::PairTerm<1>&) { ++contacts; });
    counters[Counter::obstacle_contacts] = static_cast<double>(contacts);
    counters[Counter::obstacle_min_distance] = min_distance_;
    counters[Counter::floor_holds] = static_cast<double>(holds_);
    counters[Counter::stiffened_pairs] =
        static_cast<double>(std::count_if(stiffening_.begin(), stiffening_.end(), [](double m) { return m != 1.0; }));
    if (friction_) {
      counters[Counter::obstacle_friction_contacts] = static_cast<double>(frozen_.size());
      counters[Counter::obstacle_friction_sticking] = static_cast<double>(friction_stats_.sticking);
      counters[Counter::obstacle_friction_ms] = friction_stats_.ms;
    }
  }

 private:
  /// Vertices per chunk of the parallel passes.
  static constexpr long kChunk = 1024;

  /// Where obstacle k's poses come from: the simulation's obstacle of its name
  /// (`StepContext::obstacles`, which holds the poses put between steps,
  /// `Simulation::set_obstacle_pose`), or the effect's own copy when the step has none.
  const Obstacle& posed(const StepContext& ctx, std::size_t k) const {
    if (ctx.obstacles)
      for (const Obstacle& o : *ctx.obstacles)
        if (o.name == obstacles_[k].name) return o;
    return obstacles_[k];
  }

  /// The floor's rounding allowance, relative to max(|x|, 1) (as self contact's).
  static constexpr double kFloorRounding = 1e-12;
  /// The most solves of one step that stiffening for the floor asks for (16⁸ is beyond the
  /// largest factor).
  static constexpr int kFloorSolves = 8;

  /// The penalty of vertex i against obstacle k: the effect's, with its stiffness times the
  /// vertex's lumped rest area when area weighted and times the pair's stiffening factor.
  template <class Penalty> Penalty weighted(const Penalty& penalty, Eigen::Index i, std::size_t k) const {
    const double m = stiffening_.empty() ? 1.0 : stiffening_[static_cast<std::size_t>(i) * obstacles_.size() + k];
    if (!areas_.size()) return m == 1.0 ? penalty : scaled(penalty, m);
    return scaled(penalty, areas_[i] * m);
  }

  /// How far a vertex at distance d > 0 from a surface may move towards it (block descent,
  /// safe_step): to its floor less a tenth of the way, or by 0.09 d below the floor.
  double room(double d) const { return 0.9 * (d > floor_ ? d - floor_ : 0.1 * d); }

  /// The largest fraction (≤ 1) of vertex i's move dxᵢ from x that keeps its room(d) to
  /// every obstacle (1 inside a volume, or inside an obstacle: nothing to keep).
  double move_limit(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, Eigen::Index i) const {
    if (!surface_.empty() && !surface_[static_cast<std::size_t>(i)]) return 1.0;  // inside a volume
    const double step = dx.col(i).norm();
    if (!(step > 0)) return 1.0;
    const Eigen::Vector3d p = x.col(i);
    double t = 1.0;
    for (std::size_t k = 0; k < obstacles_.size(); ++k) {
      const double lower = (p - poses_[k].translation()).norm() - radius_[k];  // d ≥ lower
      if (lower > 0 && room(lower) >= step) continue;                          // the whole move keeps the room
      const double d = surface_distance(obstacles_[k], poses_[k], p).distance;
      if (d > 0) t = std::min(t, room(d) / step);
    }
    return t;
  }

  /// Whether pair j (i·K + k) may be at `distance` (below the floor): only when it was never
  /// held (its factor is 1), or was below the floor at the iterate (`below_`) and is no
  /// closer now, less the rounding allowance.
  bool allowed(std::size_t j, double distance) const {
    if (stiffening_.empty() || stiffening_[j] == 1.0) return true;
    const auto it = std::lower_bound(below_.begin(), below_.end(), j,
                                     [](const Below& b, std::size_t pair) { return b.pair < pair; });
    return it != below_.end() && it->pair == j && distance >= it->distance - slack_;
  }

  /// At the end of a solve at x: stiffens (kFloorStiffening) the penalty of every pair x has closer than
  /// the floor that was at least as far at the step's start, or that came closer; true when
  /// one was (the step is then solved again from x), at most kFloorSolves times a step.
  bool stiffen_below(const Eigen::Matrix3Xd& x) {
    if (!(floor_ > 0) || floor_solves_ >= kFloorSolves) return false;
    bool any = false;
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      if (!surface_.empty() && !surface_[static_cast<std::size_t>(i)]) continue;
      const Eigen::Vector3d p = x.col(i);
      for (std::size_t k = 0; k < obstacles_.size(); ++k) {
        if ((p - poses_[k].translation()).norm() - radius_[k] >= floor_) continue;  // d ≥ floor
        const double d = surface_distance(obstacles_[k], poses_[k], p).distance;
        if (!(d < floor_)) continue;
        const double before = surface_distance(obstacles_[k], poses_[k], x_step_start_->col(i)).distance;
        if (before < floor_ && d >= before) continue;  // below the floor from the start, and no closer
        any = stiffen_pair(static_cast<std::size_t>(i) * obstacles_.size() + k, x.cols()) || any;
      }
    }
    if (any) ++floor_solves_;
    return any;
  }

  /// The signed distance at x of pair j (vertex i, obstacle k at j = i·K + k), the obstacle
  /// at its end pose.
  double pair_distance(const Eigen::Matrix3Xd& x, std::size_t j) const {
    const std::size_t k = j % obstacles_.size();
    return surface_distance(obstacles_[k], poses_[k], x.col(static_cast<Eigen::Index>(j / obstacles_.size()))).distance;
  }

  /// Holds pair j: multiplies its penalty's stiffness by kFloorStiffening (up to the largest
  /// factor; `vertices` sizes the factors the first time); true when it grew.
  bool stiffen_pair(std::size_t j, Eigen::Index vertices) {
    if (stiffening_.empty()) stiffening_.assign(static_cast<std::size_t>(vertices) * obstacles_.size(), 1.0);
    if (stiffening_[j] >= kLargestFloorStiffening) return false;
    stiffening_[j] = std::min(stiffening_[j] * kFloorStiffening, kLargestFloorStiffening);
    ++holds_;
    return true;
  }

  /// Forgets the stiffening of pairs beyond d at the step's start `x` (the obstacles at the
  /// step's end pose); zeroes the frame's hold count.
  void forget_stiffening(const Eigen::Matrix3Xd& x) {
    holds_ = 0;
    bool any = false;
    for (std::size_t j = 0; j < stiffening_.size(); ++j) {
      if (stiffening_[j] == 1.0) continue;
      if (pair_distance(x, j) >= penalty_.distance)
        stiffening_[j] = 1.0;
      else
        any = true;
    }
    if (!any) stiffening_.clear();
  }

  /// The active (vertex, obstacle) pairs at `x` with their terms (terms_, in vertex then
  /// obstacle order) and the minimum distance; returns true when a barrier's domain is left
  /// (a vertex at d ≤ 0).
  template <class Penalty> bool gather(const Eigen::Matrix3Xd& x, const Penalty& penalty) {
    const long n = x.cols();
    const std::size_t chunks = contact::chunk_count(n, kChunk);
    terms_.prepare(chunks);
    chunk_min_.assign(chunks, std::numeric_limits<double>::max());
    chunk_blocked_.assign(chunks, 0);
    if (pressed_chunks_.size() < chunks) pressed_chunks_.resize(chunks);
    const double reach = penalty_.distance;
    contact::for_each_chunk(n, kChunk, [&](std::size_t c, long begin, long end) {
      terms_.clear(c);
      pressed_chunks_[c].clear();
      for (long i = begin; i < end; ++i) {
        if (!surface_.empty() && !surface_[static_cast<std::size_t>(i)]) continue;  // inside a volume
        const Eigen::Vector3d p = x.col(i);
        for (std::size_t k = 0; k < obstacles_.size(); ++k) {
          const double bound = (p - poses_[k].translation()).norm() - radius_[k];
          if (bound >= reach) {  // d ≥ bound ≥ reach: inactive
            chunk_min_[c] = std::min(chunk_min_[c], bound);
            continue;
          }
          const SurfaceDistance s = surface_distance(obstacles_[k], poses_[k], p);
          chunk_min_[c] = std::min(chunk_min_[c], s.distance);
          if (!(s.distance < reach)) continue;
          if (penalty_.barrier() && !(s.distance > 0)) chunk_blocked_[c] = 1;
          if (s.distance < floor_ && !allowed(static_cast<std::size_t>(i) * obstacles_.size() + k, s.distance)) {
            chunk_blocked_[c] = 1;  // a held pair below its floor: outside the domain, as a barrier's
            pressed_chunks_[c].push_back(static_cast<std::size_t>(i) * obstacles_.size() + k);
          }
          const PenaltyDerivatives<double> psi = weighted(penalty, i, k).evaluate(s.distance);
          contact::PairTerm<1> t;
          t.k = static_cast<long>(static_cast<std::size_t>(i) * obstacles_.size() + k);  // the pair's index i·K + k
          t.vertices = {static_cast<int>(i)};
          t.energy = psi.value;
          t.length = s.distance;
          t.gradient = psi.first * s.normal;
          terms_.terms[c].push_back(t);
          if (psi.second > 0) terms_.blocks[c].push_back({t.vertices, psi.second * (s.normal * s.normal.transpose())});
        }
      }
    });
    min_distance_ = *std::min_element(chunk_min_.begin(), chunk_min_.end());
    for (std::size_t c = 0; c < chunks; ++c)
      pressed_.insert(pressed_.end(), pressed_chunks_[c].begin(), pressed_chunks_[c].end());
    return std::count(chunk_blocked_.begin(), chunk_blocked_.end(), char(1)) > 0;
  }

  /// Freezes the friction of every pair active at `x`, with the obstacles at their start
  /// poses (`at_start`) or their end poses: λ = −ψ′(d), the tangent basis of the normal, and
  /// the displacement over the step of the surface point nearest the vertex.
  void freeze(const Eigen::Matrix3Xd& x, bool at_start) {
    const std::vector<Eigen::Isometry3d>& at = at_start ? start_poses_ : poses_;
    const std::vector<Eigen::Isometry3d>& other = at_start ? poses_ : start_poses_;
    const double reach = penalty_.distance;
    const long n = x.cols();
    const std::size_t chunks = contact::chunk_count(n, kChunk);
    if (parts_.size() < chunks) parts_.resize(chunks);
    visit_penalty(penalty_, [&](const auto& penalty) {
      contact::for_each_chunk(n, kChunk, [&](std::size_t c, long begin, long end) {
        parts_[c].clear();
        for (long i = begin; i < end; ++i) {
          if (!surface_.empty() && !surface_[static_cast<std::size_t>(i)]) continue;  // inside a volume
          const Eigen::Vector3d p = x.col(i);
          for (std::size_t k = 0; k < obstacles_.size(); ++k) {
            if ((p - at[k].translation()).norm() - radius_[k] >= reach) continue;
            const SurfaceDistance s = surface_distance(obstacles_[k], at[k], p);
            if (!(s.distance < reach) || (penalty_.barrier() && !(s.distance > 0))) continue;
            const double lambda = -weighted(penalty, i, k).evaluate(s.distance).first;
            if (!(lambda > 0) || !std::isfinite(lambda)) continue;
            FrictionContact<1> fc;
            fc.v = {static_cast<int>(i)};
            fc.f.weights << 1.0;
            fc.f.basis = tangent_basis<double>(s.normal);
            const Eigen::Vector3d surface = p - s.distance * s.normal;
            const Eigen::Vector3d moved = other[k] * (at[k].inverse() * surface);
            fc.f.offset = at_start ? Eigen::Vector3d(moved - surface) : Eigen::Vector3d(surface - moved);
            fc.f.mu_lambda = friction_->coefficient * lambda;
            fc.f.static_slip = slip_;
            parts_[c].push_back(fc);
          }
        }
      });
    });
    contact::join_chunks(parts_, chunks, frozen_);
    publish_friction(frozen_, published_);
    friction_incidence_.build(static_cast<int>(n), frozen_.size(), [&](std::size_t i) { return frozen_[i].v; });
  }

  ContactPenalty penalty_;
  double floor_;  ///< the minimum separation f·d (0: none)
  std::optional<FrictionSettings> friction_;
  std::vector<Obstacle> obstacles_;
  Eigen::VectorXd areas_;      ///< per vertex, its lumped rest area (area weighting), else empty
  std::vector<char> surface_;  ///< per vertex, 0 inside a volume (no contact); empty: all take part
  std::vector<double> radius_;
  std::vector<Eigen::Isometry3d> poses_;                ///< at the end of the step
  std::vector<Eigen::Isometry3d> start_poses_;          ///< at its start (friction)
  std::vector<FrictionContact<1>> frozen_;              ///< the step's frozen friction pairs
  VertexIncidence friction_incidence_;                  ///< per vertex, its entries of frozen_
  std::vector<std::vector<FrictionContact<1>>> parts_;  ///< per chunk while freezing
  std::vector<FrozenFriction> published_;               ///< frozen_ with μλ > 0, padded
  const Eigen::Matrix3Xd* x_start_ = nullptr;
  double slip_ = 0;  ///< ε_v h, the slip below which a contact sticks
  int rounds_ = 0;   ///< solves of this step with friction frozen so far
  FrictionStats friction_stats_;
  contact::PairTerms<1> terms_;      ///< per chunk: the active pairs of the last evaluation
  std::vector<double> chunk_min_;    ///< per chunk: its smallest distance (bound) of the last evaluation
  std::vector<char> chunk_blocked_;  ///< per chunk: a barrier's domain was left
  double min_distance_ = std::numeric_limits<double>::max();
  std::vector<double> stiffening_;  ///< per (vertex i, obstacle k) at i·K + k: its factor; empty when all are 1
  /// A held pair (i·K + k) closer than the floor at the iterate, and its distance there.
  struct Below {
    std::size_t pair = 0;
    double distance = 0;
  };
  std::vector<Below> below_;                              ///< at the last begin_iteration, ascending by pair
  double slack_ = 0;                                      ///< the floor's rounding allowance at that iterate
  std::vector<std::size_t> pressed_;                      ///< held pairs whose floor refused a trial since begin_line_search
  std::vector<std::vector<std::size_t>> pressed_chunks_;  ///< per chunk of the evaluation
  const Eigen::Matrix3Xd* x_step_start_ = nullptr;        ///< xⁿ of the step
  int floor_solves_ = 0;                                  ///< solves of this step that stiffen_below asked for
  long holds_ = 0;                                        ///< holds in the frame so far
  long surface_count_ = 0;  ///< the model's vertex count (0 without a model: no factor loads)
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

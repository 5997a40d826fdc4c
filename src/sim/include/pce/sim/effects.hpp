// SPDX-License-Identifier: MIT
/// @file
/// The built-in effects, built from C++: one typed builder per scene effect type, taking
/// what the scene's effect object holds (docs/simulation.md §3 lists the scene forms). The
/// scene loader calls these same builders, so a scene file and its C++ transcription build
/// the same effects and simulate bit for bit alike (`tests/sim/test_effects_api.cpp`).
///
/// Every builder validates its arguments and throws `ArgumentError` naming the field as the
/// scene key would (`stiffness`, `groups[1].vertices`, `penalty.distance`), before anything
/// is built. An effect keeps a pointer to the model it was built from: build it from the
/// `Simulation::model` it will run in, after that model is final.
#pragma once

#include <pce/core/enum_names.hpp>
#include <pce/energy/pair_energy.hpp>
#include <pce/sim/broad_phase.hpp>
#include <pce/sim/contact_effect.hpp>
#include <pce/sim/effect.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/model.hpp>
#include <pce/sim/obstacle.hpp>

#include <pce/volumes/stable_neo_hookean.hpp>

#include <Eigen/Core>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pce::sim {

/// Gravity, E = −Σᵢ mᵢ g·xᵢ (`acceleration` g in m/s², finite).
std::unique_ptr<Effect> make_gravity(const Model& model,
                                     const Eigen::Vector3d& acceleration = Eigen::Vector3d(0, 0, -9.81));

/// Cloth membrane stretching, as-rigid-as-possible: E = Σ_t μ A_t ‖F_t − R(F_t)‖²_F with a
/// closed-form PSD Hessian; `stiffness` μ > 0 (N/m). Every rest triangle needs an area.
std::unique_ptr<Effect> make_stretching(const Model& model, double stiffness);

/// Cloth bending (discrete shells): E = Σ_hinges 3k (θ − θ₀)² |ē|²/(Ā₁ + Ā₂) over the
/// interior manifold edges, Gauss–Newton Hessian; `stiffness` k > 0 (N·m).
std::unique_ptr<Effect> make_bending(const Model& model, double stiffness);

/// Strand stretching: E = Σ_segments ½ k (|e| − L)²/L, exactly projected Hessian;
/// `stiffness` k > 0 (N).
std::unique_ptr<Effect> make_strand_stretching(const Model& model, double stiffness);

/// Strand bending: E = Σ_joints k (φ − φ₀)²/ℓ̄ over the turning angle φ at every vertex shared
/// by two segments; `stiffness` k > 0 (N·m²).
std::unique_ptr<Effect> make_strand_bending(const Model& model, double stiffness);

/// Damping as a potential: E = Σᵢ mᵢ c/(2h) |xᵢ − xᵢⁿ|² (drag force −c m v), `coefficient`
/// c ≥ 0 (1/s). h and xⁿ are each step's (zero energy before the first step begins).
std::unique_ptr<Effect> make_damping(const Model& model, double coefficient);

/// Volume elasticity, stable Neo-Hookean (Smith, de Goes & Kim 2018): E = Σ_T V_T Ψ(F_T)
/// over every tetrahedron of the model (`pce/volumes/stable_neo_hookean.hpp`), with each
/// tetrahedron's Hessian made PSD by the closed-form eigensystem (`analytic`) or a numerical
/// eigendecomposition (`numerical`). Finite for inverted and flat tetrahedra. Throws
/// ArgumentError for an invalid material, `VolumeProjection::none`, or a model without
/// tetrahedra.
std::unique_ptr<Effect> make_volume_elasticity(const Model& model, const StableNeoHookean& material,
                                               VolumeProjection hessian = VolumeProjection::analytic);

/// The strategies the scene's `volume_elasticity.hessian` accepts, in the order its error
/// message lists them (names from `pce::kVolumeProjectionNames`).
inline constexpr std::array<VolumeProjection, 2> kVolumeHessians{VolumeProjection::analytic,
                                                                 VolumeProjection::numerical};

/// A group of pinned vertices (scene `pins.groups[i]`).
struct PinGroup {
  /// Global vertex indices (`Model` columns); at least one, each in range.
  std::vector<int> vertices{};
  /// Pinned for frames < release_frame; 0: never released.
  int release_frame = 0;
  /// Without a motion the targets are the rest positions; with one they follow it
  /// (`Motion::apply`) about `centre`.
  std::optional<Motion> motion = std::nullopt;
  /// The centre the motion turns about; the group's rest centroid when absent.
  std::optional<Eigen::Vector3d> centre = std::nullopt;
};

/// The effect `make_pins` builds, with what a program may change between steps (docs/python.md,
/// `Simulation.set_pin_targets`): the targets of a group, which then replace its rest positions
/// or its motion. Found among `Simulation::effects` by `dynamic_cast`. A vertex held by two
/// groups has one target: that of the last of them whose targets move or are set. Targets set
/// so are not in a checkpoint.
class PinsEffect : public Effect {
 public:
  using Effect::Effect;
  /// The number of groups (the scene's `groups`, in order).
  virtual int group_count() const = 0;
  /// Group `group`'s vertices (model indices, in the group's order). Throws ArgumentError
  /// ("group") for a group not in [0, group_count()).
  virtual const std::vector<int>& group_vertices(int group) const = 0;
  /// Group `group`'s targets, one column per vertex of the group: the ones set, else the
  /// last step's (before the first step: its rest positions). Throws as group_vertices.
  virtual Eigen::Matrix3Xd group_targets(int group) const = 0;
  /// From the next step on, group `group`'s targets at the end of every step are the columns
  /// of `targets` (one per vertex of the group, in its order) instead of its rest positions
  /// or its motion, until set again or cleared; a released group stays released. Throws
  /// ArgumentError for a group not in range ("group"), a matrix that is not 3 × the group's
  /// vertex count, or a coordinate that is not finite or beyond ±`kMaxCoordinate` ("targets").
  virtual void set_targets(int group, const Eigen::Matrix3Xd& targets) = 0;
  /// From the next step on, group `group`'s targets are its rest positions or its motion's
  /// again. Throws as group_vertices.
  virtual void clear_targets(int group) = 0;
};

/// Pins: stiff zero-length springs to targets, E = ½ k Σ_{pinned i} |xᵢ − x̂ᵢ|² over the
/// groups not yet released; `stiffness` k > 0 (N/m).
std::unique_ptr<PinsEffect> make_pins(const Model& model, std::vector<PinGroup> groups, double stiffness = 1e5);

/// The vertices whose rest positions lie in the closed box [lo, hi] (what a scene pin group's
/// `box` selects), optionally only those of the model mesh named `mesh` (empty: all).
/// Throws ArgumentError when `lo > hi` in a coordinate or no mesh has that name.
std::vector<int> vertices_in_box(const Model& model, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                 const std::string& mesh = {});

/// A contact effect's penalty ψ (scene `penalty` object; pce's penalty types).
struct ContactPenalty {
  /// quadratic (`QuadraticPenalty`), cubic (`CubicPenalty`) or log barrier (`LogBarrierPenalty`).
  enum class Kind { quadratic, cubic, log_barrier };
  /// Which penalty.
  Kind kind = Kind::quadratic;
  double stiffness = 0;  ///< k > 0
  double distance = 0;   ///< activation distance > 0: ε (quadratic, cubic) or d̂ (log barrier)
  double delta = 0;      ///< cubic smoothing δ ≥ 0 (cubic only)
  /// Whether ψ is the log barrier (infinite at zero length).
  bool barrier() const { return kind == Kind::log_barrier; }
};

/// The penalties' names (scene key `penalty.type`), in enumerator order.
inline constexpr EnumNames<ContactPenalty::Kind, 3> kPenaltyNames{{
    {ContactPenalty::Kind::quadratic, "quadratic"},
    {ContactPenalty::Kind::cubic, "cubic"},
    {ContactPenalty::Kind::log_barrier, "log_barrier"},
}};

/// The table of `ContactPenalty::Kind`'s names (for `pce::name_of` and `pce::parse`).
constexpr const EnumNames<ContactPenalty::Kind, 3>& enum_names(ContactPenalty::Kind) { return kPenaltyNames; }

/// A contact effect's friction (scene `friction` object): lagged smoothed Coulomb friction
/// (IPC, Li et al. 2020; docs/simulation.md §4, "Friction"). Each time step freezes, at its
/// start, the normal force λ = −ψ′ of every contact active there, its tangent basis and
/// closest points; the potential μλ f₀(|u|) of the contact's tangential slip u over the step
/// then resists sliding with Coulomb's force μλ above the slip velocity and as a stiff
/// spring below it.
struct FrictionSettings {
  /// μ ≥ 0 (dimensionless), at most `kMaxFrictionCoefficient`.
  double coefficient = 0;
  /// ε_v > 0 (m/s): slips slower than this are static friction's spring (a creep of at most
  /// ε_v); at most `args`' largest speed, 1e6 m/s.
  double slip_velocity = 1e-3;
  /// Solves per time step: 1 freezes the normal forces and bases at the step's start; n > 1
  /// solves again n − 1 times with them updated at the previous solve's result. In [1, 100].
  int lagged_iterations = 1;
};

/// The largest friction coefficient accepted: far above any material pair's (rubber on
/// dry rough surfaces reaches ~2).
inline constexpr double kMaxFrictionCoefficient = 100;

/// The default minimum separation of contact effects, as a fraction of the activation
/// distance d (`ContactSettings::min_separation`, `ObstacleContactSettings::min_separation`).
inline constexpr double kDefaultMinSeparation = 0.01;

/// The largest minimum separation a contact effect accepts, as a fraction of d.
inline constexpr double kMaxMinSeparation = 0.5;

/// A self-contact effect's settings (scene `self_vertex_face` / `self_edge_edge` objects).
struct ContactSettings {
  /// The penalty ψ of the pair's length.
  ContactPenalty penalty{};
  /// Signed length (plane mode only) instead of unsigned (scene `length`).
  bool signed_length = false;
  /// Closest-feature evaluation (the distance between the primitives) instead of the plane.
  bool closest_features = false;
  /// The Hessian's PSD strategy (not `Projection::none`).
  Projection hessian = Projection::analytic;
  /// Limit every Newton step so no pair can cross (always on for the barrier).
  bool ccd = true;
  /// The minimum separation, as a fraction of d (of a fold pair's reach): no Newton step
  /// brings a candidate pair that starts it at least this far apart closer, and a pair the
  /// step bound holds there has its penalty stiffened (docs/simulation.md §4.6). In [0, 0.5];
  /// 0 turns the floor off. Applies with the step bound (`ccd` or the barrier).
  double min_separation = kDefaultMinSeparation;
  /// The broad phase that finds the candidate pairs (scene `solver.broad_phase`).
  BroadPhaseKind broad_phase = BroadPhaseKind::fcl;
  /// Weigh each pair's energy by rest areas (vertex-face: the face's area plus the vertex's
  /// lumped area; edge-edge: the two edges' lumped areas), so the stiffness is per unit area
  /// (J/m⁴ quadratic, J/m⁵ cubic, J/m⁴ log barrier) and the contact force per area does not
  /// depend on the mesh resolution. Needs every edge of an edge-edge effect to border a
  /// triangle (strand segments have no area).
  bool area_weighted = false;
  /// Friction on the effect's pairs; none when absent (nothing of it is built).
  std::optional<FrictionSettings> friction = std::nullopt;
  /// The pairs of meshes (by name, either order; the same name twice: a mesh with itself)
  /// whose primitives may meet; empty: every pair of the model's meshes. Build the effect on
  /// `restrict_to_meshes(model, <the meshes named>)` too, so its broad phase sees only those
  /// (scene `meshes` given as pairs; docs/simulation.md §2.5).
  std::vector<std::array<std::string, 2>> mesh_pairs{};
};

/// The strategies a contact effect's `hessian` accepts (scene key, `pce-sim --hessian`,
/// `pce.sim.load(hessian=...)`), in the order their messages list them (names from
/// `pce::kProjectionNames`; `none` is not PSD and not accepted).
inline constexpr std::array<Projection, 5> kContactHessians{
    Projection::analytic, Projection::exact, Projection::numerical, Projection::gauss_newton, Projection::abs};

/// Vertex-face self contact: Σ ψ(L) over candidate (vertex, triangle) pairs of the model's
/// triangles (docs/simulation.md §4). Pairs that share a vertex, and vertices inside a volume,
/// are never candidates; pairs of one mesh closer than 2d at rest (fold pairs) are evaluated by closest features
/// with the activation distance min(d, half their rest distance), and every candidate is in
/// the step bound. Needs triangles; the log barrier needs `closest_features`, which needs
/// the unsigned length; d at most half the model's rest diagonal.
std::unique_ptr<ContactEffect> make_self_vertex_face(const Model& model, const ContactSettings& settings);

/// Edge-edge self contact: Σ ψ(L) over candidate pairs of the model's edges (triangle edges
/// and strand segments). Needs two edges; the same settings rules as vertex-face.
std::unique_ptr<ContactEffect> make_self_edge_edge(const Model& model, const ContactSettings& settings);

/// Contact with kinematic obstacles: Σ ψ(d) over (vertex, obstacle) pairs, d the signed
/// distance to the obstacle's surface (negative inside). The obstacles are copied (their
/// shapes; each step reads their poses from the simulation's obstacles of the same names,
/// `StepContext::obstacles`, when it has them, so poses put between steps reach it); each
/// must be a valid shape (sizes > 0, finite pose, a mesh with triangles). Frictionless and
/// unweighted; the overload below takes every setting.
std::unique_ptr<ContactEffect> make_obstacle_contact(const std::vector<Obstacle>& obstacles,
                                                     const ContactPenalty& penalty);

/// An obstacle-contact effect's settings (scene `obstacle_contact` object, but the list of
/// obstacles).
struct ObstacleContactSettings {
  /// The penalty ψ of the signed distance.
  ContactPenalty penalty{};
  /// Weigh each vertex's energy by its lumped rest area (stiffness per unit area: J/m⁴
  /// quadratic, J/m⁵ cubic, J/m⁴ log barrier). Needs every vertex to be a triangle corner.
  bool area_weighted = false;
  /// The minimum separation from an obstacle's surface, as a fraction of d: no Newton step
  /// brings a vertex that starts it at least this far out closer, and a vertex held there
  /// has its penalty stiffened (docs/simulation.md §4.6). In [0, 0.5]; 0 turns it off.
  double min_separation = kDefaultMinSeparation;
  /// Friction against the obstacles' surfaces, which move with the obstacles (a moving
  /// obstacle drags what rests on it); none when absent.
  std::optional<FrictionSettings> friction = std::nullopt;
};

/// Contact with kinematic obstacles, as above, with area weighting and friction as
/// `settings` says (`model`: the vertices' rest areas).
std::unique_ptr<ContactEffect> make_obstacle_contact(const Model& model, const std::vector<Obstacle>& obstacles,
                                                     const ObstacleContactSettings& settings);

}  // namespace pce::sim

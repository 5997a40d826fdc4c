// SPDX-License-Identifier: MIT
/// @file
/// The effects' scene loaders (defined in effect_loaders.cpp): each reads its effect object
/// through `Params` and calls the typed builder of `pce/sim/effects.hpp`, which checks the
/// values and does the building. The registry (registry.cpp) maps the effect names to them.
/// Internal.
///
/// Scene forms (SI units; every key not listed is an error):
/// - `{"type":"gravity", "acceleration":[ax,ay,az] (m/s², default [0,0,-9.81])}`
/// - `{"type":"stretching", "model":"arap" (default), "stiffness": μ > 0 (N/m)}`
/// - `{"type":"bending", "stiffness": k > 0 (N·m, i.e. J)}`
/// - `{"type":"strand_stretching", "stiffness": k > 0 (N)}`
/// - `{"type":"strand_bending", "stiffness": k > 0 (N·m²)}`
/// - `{"type":"pins", "stiffness": k > 0 (N/m, default 1e5), "groups": [{"vertices":[i,…]
///   | "box":{"min":[…],"max":[…]}, "mesh":"name" (optional), "release_frame": N ≥ 1
///   (optional), "motion":{"velocity", "angular_velocity", "center", "start", "stop"} or
///   {"keyframes", "interpolation", "center"} (optional)}, …]}`; with "mesh", "vertices" are that mesh's local indices
///   and a box selects only its vertices (rest positions inside the closed box); a group is pinned for frames <
///   release_frame (always without one)
/// - `{"type":"damping", "coefficient": c ≥ 0 (1/s)}`
/// - `{"type":"self_vertex_face" | "self_edge_edge", "penalty": {...}, "length": "unsigned"
///   (default) | "signed", "hessian": "analytic" (default) | "exact" | "numerical" |
///   "gauss_newton" | "abs", "closest_features": false (default) | true, "ccd": true
///   (default) | false}`
/// - `{"type":"obstacle_contact", "penalty": {...}, "obstacles": ["name", …] (optional;
///   default: every obstacle of the scene)}`
/// - a contact effect's `"penalty": {"type": "quadratic" | "cubic" | "log_barrier",
///   "stiffness": k > 0, "distance": activation distance (ε, or d̂ for the barrier) > 0,
///   "delta": δ ≥ 0 (cubic only, default 0)}`
#pragma once

#include "factory.hpp"

namespace pce::sim {

/// E = −Σᵢ mᵢ g·xᵢ.
std::unique_ptr<Effect> load_gravity(const Params& params, const BuildContext& ctx);
/// E = Σ_t μ A_t ‖F_t − R(F_t)‖²_F (as-rigid-as-possible membrane, closed-form PSD Hessian).
std::unique_ptr<Effect> load_stretching(const Params& params, const BuildContext& ctx);
/// E = Σ_hinges 3k (θ − θ₀)² |ē|²/(Ā₁ + Ā₂) (discrete shells), Gauss–Newton Hessian.
std::unique_ptr<Effect> load_bending(const Params& params, const BuildContext& ctx);
/// E = Σ_segments ½ k (|e| − L)²/L, exactly projected Hessian.
std::unique_ptr<Effect> load_strand_stretching(const Params& params, const BuildContext& ctx);
/// E = Σ_joints k (φ − φ₀)²/ℓ̄ over the turning angle φ of consecutive segments.
std::unique_ptr<Effect> load_strand_bending(const Params& params, const BuildContext& ctx);
/// E = ½ k Σ_{pinned i} |xᵢ − x̄ᵢ|² over groups not yet released.
std::unique_ptr<Effect> load_pins(const Params& params, const BuildContext& ctx);
/// E = Σᵢ mᵢ c/(2h) |xᵢ − xᵢⁿ|² (drag force −c m v).
std::unique_ptr<Effect> load_damping(const Params& params, const BuildContext& ctx);
/// Σ ψ(L) over candidate (vertex, triangle) pairs (effects/contact/self_contact.cpp).
std::unique_ptr<Effect> load_self_vertex_face(const Params& params, const BuildContext& ctx);
/// Σ ψ(L) over candidate (edge, edge) pairs (effects/contact/self_contact.cpp).
std::unique_ptr<Effect> load_self_edge_edge(const Params& params, const BuildContext& ctx);
/// Σ ψ(d) over (vertex, obstacle) pairs, d the signed distance to the obstacle's surface.
std::unique_ptr<Effect> load_obstacle_contact(const Params& params, const BuildContext& ctx);
/// Σ_T V_T Ψ(F_T) over the tetrahedra, stable Neo-Hookean (effects/volume_elasticity.cpp).
std::unique_ptr<Effect> load_volume_elasticity(const Params& params, const BuildContext& ctx);

}  // namespace pce::sim

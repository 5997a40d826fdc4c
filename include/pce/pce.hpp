// SPDX-License-Identifier: MIT
/// @file
/// Umbrella header: penalty-based collision energies with closed-form eigensystems
/// (Shi & Kim, "A Unified Analysis of Penalty-Based Collision Energies", PACMCGIT 6(3), 2023).
///
/// @mainpage API reference
///
/// The API reference of the header-only core (namespace `pce`, `include/pce`, Eigen only)
/// and of the simulation toolkit (namespace `pce::sim`, `src/sim/include/pce/sim`).
///
/// **Per pair** (`#include <pce/pce.hpp>`): a pair kind (pce::VertexFace, pce::EdgeEdge,
/// pce::PointEdge, pce::PointPoint), a length (pce::SignedLength, pce::UnsignedLength) and
/// a penalty (pce::QuadraticPenalty, pce::CubicPenalty, pce::LogBarrierPenalty) go into
/// pce::pair_energy(), then pce::energy_gradient(), pce::energy_hessian(),
/// pce::energy_eigensystem() and pce::projected_hessian() with a pce::Projection strategy; or
/// everything at once with pce::evaluate(); the energy alone or with its gradient, from the
/// part of the frame they need, with pce::value_only() and pce::value_gradient(); or for an
/// array of pairs, a SIMD packet of pairs at a time where it can, with pce::evaluate_batch()
/// (pce::closest_feature_batch() by closest features). pce::closest_feature_energy() evaluates the
/// distance between the primitives by whichever kind holds the closest points, and
/// pce::mollified_pair_energy() fades the energy out at degenerate frames. The evaluating
/// calls return a pce::Status and write their outputs only on `ok`.
/// A contact's lagged smoothed Coulomb friction (pce::LaggedFriction, pce::friction_energy,
/// pce::friction_gradient, pce::friction_hessian; weights and normal from a frame or a
/// closest-feature evaluation by pce::friction_geometry) is in `friction/lagged_friction.hpp`.
///
/// **Per tetrahedron** (`volumes/`): a rest shape (pce::tet_rest) and the stable Neo-Hookean
/// energy (pce::StableNeoHookean) give pce::snh_tet_energy(), with its Hessian made PSD through
/// the closed-form eigensystem pce::snh_eigensystem() (pce::VolumeProjection).
///
/// **Simulation** (`pce::sim`, the `pce-sim` tool's library): pce::sim::load_scene() builds a
/// pce::sim::Simulation from a JSON scene; pce::sim::Simulation::step advances one frame
/// by projected Newton over the declared pce::sim::Effect terms; contact effects find
/// candidates through a pce::sim::BroadPhase (FCL, Bullet or brute force).
///
/// The prose documentation (mathematics, conventions, stability, fuzzing, pce-probe, the
/// simulator, benchmarks) is in the repository's `docs/` folder, starting at
/// `docs/index.md`. This reference is built by `cmake --build <build> --target pce-docs`
/// into `<build>/docs/api/html/index.html`.
#pragma once

#include <pce/core/enum_names.hpp>
#include <pce/core/jacobi.hpp>
#include <pce/core/orthogonal.hpp>
#include <pce/core/tridiagonal.hpp>
#include <pce/core/types.hpp>
#include <pce/energy/closest_feature.hpp>
#include <pce/energy/evaluate_batch.hpp>
#include <pce/energy/exact_projection.hpp>
#include <pce/energy/mollified_energy.hpp>
#include <pce/energy/pair_energy.hpp>
#include <pce/energy/plane_eigenpairs.hpp>
#include <pce/energy/point_edge_energy.hpp>
#include <pce/energy/point_point_energy.hpp>
#include <pce/energy/psd_projection.hpp>
#include <pce/energy/value_gradient.hpp>
#include <pce/frames/edge_edge.hpp>
#include <pce/frames/frame.hpp>
#include <pce/frames/point_edge.hpp>
#include <pce/frames/point_point.hpp>
#include <pce/frames/vertex_face.hpp>
#include <pce/friction/lagged_friction.hpp>
#include <pce/lengths/length_hessian.hpp>
#include <pce/lengths/signed_length.hpp>
#include <pce/lengths/unsigned_length.hpp>
#include <pce/penalties/cubic.hpp>
#include <pce/penalties/log_barrier.hpp>
#include <pce/penalties/penalty.hpp>
#include <pce/penalties/quadratic.hpp>
#include <pce/volumes/stable_neo_hookean.hpp>
#include <pce/volumes/tet_deformation.hpp>

// SPDX-License-Identifier: MIT
/// @file
/// Umbrella header: penalty-based collision energies with closed-form eigensystems
/// (Shi & Kim, "A Unified Analysis of Penalty-Based Collision Energies", PACMCGIT 6(3), 2023).
#pragma once

#include <pce/core/jacobi.hpp>
#include <pce/core/tridiagonal.hpp>
#include <pce/core/types.hpp>
#include <pce/energy/closest_feature.hpp>
#include <pce/energy/exact_projection.hpp>
#include <pce/energy/mollified_energy.hpp>
#include <pce/energy/pair_energy.hpp>
#include <pce/energy/plane_eigenpairs.hpp>
#include <pce/energy/point_edge_energy.hpp>
#include <pce/energy/point_point_energy.hpp>
#include <pce/energy/psd_projection.hpp>
#include <pce/frames/edge_edge.hpp>
#include <pce/frames/frame.hpp>
#include <pce/frames/point_edge.hpp>
#include <pce/frames/point_point.hpp>
#include <pce/frames/vertex_face.hpp>
#include <pce/lengths/length_hessian.hpp>
#include <pce/lengths/signed_length.hpp>
#include <pce/lengths/unsigned_length.hpp>
#include <pce/penalties/cubic.hpp>
#include <pce/penalties/log_barrier.hpp>
#include <pce/penalties/penalty.hpp>
#include <pce/penalties/quadratic.hpp>

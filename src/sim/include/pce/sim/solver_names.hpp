// SPDX-License-Identifier: MIT
/// @file
/// The names of the solver's enumerations (`pce/sim/simulation.hpp`): the linear solvers
/// (scene key `solver.linear_solver`, docs/simulation.md §2.4) and the reasons a step's
/// Newton iterations end (`stats.json`'s `stop`, §6.1), one table each.
#pragma once

#include <pce/core/enum_names.hpp>
#include <pce/sim/simulation.hpp>

namespace pce::sim {

/// The linear solvers' names, in the order the scene format lists them.
inline constexpr EnumNames<LinearSolver, 4> kLinearSolverNames{{
    {LinearSolver::direct, "direct"},
    {LinearSolver::factor_reuse, "factor_reuse"},
    {LinearSolver::ldlt, "ldlt"},
    {LinearSolver::cg, "cg"},
}};

/// The table of `LinearSolver`'s names (for `pce::name_of` and `pce::parse`).
constexpr const EnumNames<LinearSolver, 4>& enum_names(LinearSolver) { return kLinearSolverNames; }

/// The reasons' names (`stats.json`'s `stop`), in enumerator order.
inline constexpr EnumNames<StopReason, 5> kStopReasonNames{{
    {StopReason::tolerance, "tolerance"},
    {StopReason::rounding, "rounding"},
    {StopReason::line_search, "line_search"},
    {StopReason::iteration_cap, "iteration_cap"},
    {StopReason::single_solve, "single_solve"},
}};

/// The table of `StopReason`'s names (for `pce::name_of` and `pce::parse`).
constexpr const EnumNames<StopReason, 5>& enum_names(StopReason) { return kStopReasonNames; }

}  // namespace pce::sim

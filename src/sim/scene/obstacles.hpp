// SPDX-License-Identifier: MIT
/// @file
/// The scene's obstacles (obstacles.cpp): an `obstacles` entry read into an `Obstacle`, and
/// an obstacle_contact entry's list of the obstacles it acts against. Internal.
#pragma once

#include "params.hpp"

#include <pce/sim/obstacle.hpp>

#include <filesystem>
#include <vector>

namespace pce::sim {

/// An `obstacles` entry: its `name`, `shape` (sphere, box, capsule or a mesh file, relative
/// to `base`) with its sizes, `position`, `rotation` and `motion`.
Obstacle parse_obstacle(const Params& p, const std::filesystem::path& base);

/// The obstacles effect entry `p` lists in `obstacles`, as indices into `obstacles` in the
/// list's order; every obstacle, in order, without the key. An empty list, a name that is
/// not a string, is no obstacle's or is listed twice is an error at its JSON path.
std::vector<int> listed_obstacles(const Params& p, const std::vector<Obstacle>& obstacles);

}  // namespace pce::sim

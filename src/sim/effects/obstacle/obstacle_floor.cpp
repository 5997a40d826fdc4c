// SPDX-License-Identifier: MIT
// The stiffening of an obstacle-contact effect's held pairs (obstacle_floor.hpp).
#include "obstacle_floor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace pce::sim::obstacle {

void ObstacleFloor::begin_step(const Eigen::Matrix3Xd& x, double reach) {
  holds_ = 0;
  bool any = false;
  for (std::size_t j = 0; j < factors_.size(); ++j) {
    if (factors_[j] == 1.0) continue;
    if (set_->pair_distance(x, j) >= reach)
      factors_[j] = 1.0;
    else
      any = true;
  }
  if (!any) factors_.clear();
}

bool ObstacleFloor::stiffen(const Eigen::Matrix3Xd& x, const std::vector<FloorLimit>& held) {
  bool any = false;
  for (const FloorLimit& h : held) {
    if (!pressed_in(set_->pair_distance(x, h.k), h, floor_)) continue;
    if (factors_.empty()) factors_.assign(static_cast<std::size_t>(x.cols()) * set_->size(), 1.0);
    if (!stiffen_factor(factors_[h.k])) continue;
    ++holds_;
    any = true;
  }
  return any;
}

long ObstacleFloor::stiffened() const {
  return static_cast<long>(std::count_if(factors_.begin(), factors_.end(), [](double m) { return m != 1.0; }));
}

std::string ObstacleFloor::save() const {
  std::string out;
  for (std::size_t j = 0; j < factors_.size(); ++j) {
    if (factors_[j] == 1.0) continue;
    const std::uint64_t index = j;
    out.append(reinterpret_cast<const char*>(&index), sizeof index);
    out.append(reinterpret_cast<const char*>(&factors_[j]), sizeof(double));
  }
  return out;
}

void ObstacleFloor::load(const std::string& state, const std::string& effect) {
  constexpr std::size_t record = sizeof(std::uint64_t) + sizeof(double);
  if (state.size() % record != 0)
    throw std::invalid_argument(effect + ": the saved state's size is not a whole number of records");
  std::vector<double> loaded;
  for (std::size_t at = 0; at < state.size(); at += record) {
    std::uint64_t index = 0;
    double factor = 0;
    std::memcpy(&index, state.data() + at, sizeof index);
    std::memcpy(&factor, state.data() + at + sizeof index, sizeof factor);
    const std::size_t size = static_cast<std::size_t>(vertices_) * set_->size();
    if (!(index < size) || !(factor >= 1 && std::isfinite(factor)))
      throw std::invalid_argument(effect +
                                  ": a saved stiffening factor does not fit this scene (vertex and obstacle index, "
                                  "a finite factor >= 1)");
    if (loaded.empty()) loaded.assign(size, 1.0);
    loaded[index] = factor;
  }
  factors_ = std::move(loaded);
}

}  // namespace pce::sim::obstacle

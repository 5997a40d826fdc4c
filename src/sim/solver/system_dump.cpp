// SPDX-License-Identifier: MIT
// Newton's linear systems on disk, and a system solved on its own (system_dump.hpp).
#include "solver/system_dump.hpp"

#include "solver/linear_state.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

namespace pce::sim::solver {

namespace {

constexpr char kMagic[8] = {'P', 'C', 'E', 'S', 'Y', 'S', '1', '\n'};

/// Writes `count` values of `T` from `data`.
template <class T> void put(std::ofstream& out, const T* data, std::size_t count) {
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(count * sizeof(T)));
}

/// Reads `count` values of `T` into `data`.
template <class T> void get(std::ifstream& in, T* data, std::size_t count) {
  in.read(reinterpret_cast<char*>(data), static_cast<std::streamsize>(count * sizeof(T)));
}

}  // namespace

bool write_system(const std::string& path, const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& rhs) {
  std::ofstream out(path, std::ios::binary);
  const std::int64_t head[2] = {upper.rows(), upper.nonZeros()};
  put(out, kMagic, 8);
  put(out, head, 2);
  put(out, upper.outerIndexPtr(), static_cast<std::size_t>(upper.cols()) + 1);
  put(out, upper.innerIndexPtr(), static_cast<std::size_t>(head[1]));
  put(out, upper.valuePtr(), static_cast<std::size_t>(head[1]));
  put(out, rhs.data(), static_cast<std::size_t>(rhs.size()));
  return static_cast<bool>(out);
}

bool read_system(const std::string& path, Eigen::SparseMatrix<double>& upper, Eigen::VectorXd& rhs) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  std::int64_t head[2] = {0, 0};
  get(in, magic, 8);
  get(in, head, 2);
  if (!in || std::memcmp(magic, kMagic, 8) != 0 || head[0] < 0 || head[1] < 0 || head[0] > (1 << 30) ||
      head[1] > (std::int64_t{1} << 31))
    return false;
  upper = Eigen::SparseMatrix<double>(head[0], head[0]);
  upper.resizeNonZeros(head[1]);
  get(in, upper.outerIndexPtr(), static_cast<std::size_t>(head[0]) + 1);
  get(in, upper.innerIndexPtr(), static_cast<std::size_t>(head[1]));
  get(in, upper.valuePtr(), static_cast<std::size_t>(head[1]));
  rhs.resize(head[0]);
  get(in, rhs.data(), static_cast<std::size_t>(head[0]));
  return static_cast<bool>(in) && upper.outerIndexPtr()[head[0]] == head[1];
}

std::unique_ptr<SystemDump> SystemDump::from_environment() {
  const char* dir = std::getenv("PCE_SIM_DUMP_SYSTEM");
  if (!dir || !*dir) return nullptr;
  auto dump = std::make_unique<SystemDump>();
  dump->dir_ = dir;
  if (const char* steps = std::getenv("PCE_SIM_DUMP_STEPS"); steps && *steps) {
    char* end = nullptr;
    dump->first_ = static_cast<int>(std::strtol(steps, &end, 10));
    dump->last_ = *end == ':' ? static_cast<int>(std::strtol(end + 1, nullptr, 10)) : dump->first_;
  }
  return dump;
}

void SystemDump::write(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& rhs) {
  ++iteration_;
  if (step_ < first_ || step_ > last_) return;
  char name[64];
  std::snprintf(name, sizeof name, "/system_s%04d_i%03d.bin", step_, iteration_);
  if (!write_system(dir_ + name, upper, rhs) && !warned_) {
    std::fprintf(stderr, "pce::sim: PCE_SIM_DUMP_SYSTEM: cannot write %s%s\n", dir_.c_str(), name);
    warned_ = true;
  }
}

LinearSystem::LinearSystem() : state_(std::make_unique<LinearState>()) { state_->dump.reset(); }
LinearSystem::~LinearSystem() = default;

void LinearSystem::set_matrix(const Eigen::SparseMatrix<double>& upper) {
  Eigen::SparseMatrix<double>& A = state_->H.matrix();
  const bool same = A.rows() == upper.rows() && A.nonZeros() == upper.nonZeros() &&
                    std::equal(A.outerIndexPtr(), A.outerIndexPtr() + A.cols() + 1, upper.outerIndexPtr()) &&
                    std::equal(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros(), upper.innerIndexPtr());
  A = upper;
  A.makeCompressed();
  if (!same) state_->pattern_changed();
}

bool LinearSystem::solve(const SolverSettings& settings, const Eigen::VectorXd& rhs, Eigen::VectorXd& dx, double eta) {
  return state_->solve(settings, rhs, dx, eta);
}

void LinearSystem::start_step() { state_->start_step(); }

const Counters& LinearSystem::counters() const { return state_->counters; }

}  // namespace pce::sim::solver

// SPDX-License-Identifier: MIT
// Frame files and the output directory (pce/sim/frames.hpp).
#include <pce/sim/frames.hpp>

#include <pce/sim/mesh.hpp>
#include <pce/sim/obj.hpp>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace pce::sim {

std::string frame_path(const std::string& dir, int frame) {
  if (frame < 0) throw std::invalid_argument("frame_path: frame " + std::to_string(frame) + " < 0");
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.obj", frame);
  return (std::filesystem::path(dir) / name).string();
}

void write_frame(const std::string& dir, int frame, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles,
                 const Eigen::Matrix2Xi& segments) {
  Mesh mesh;
  mesh.positions = x;
  mesh.triangles = triangles;
  mesh.segments = segments;
  write_obj(frame_path(dir, frame), mesh);
}

void ensure_directory(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_directory(dir, error)) return;
  if (dir.empty()) throw std::runtime_error("\"\": cannot create directory (empty path)");
  fs::create_directories(dir, error);
  if (error) throw std::runtime_error(dir + ": cannot create directory (" + error.message() + ")");
  if (!fs::is_directory(dir, error)) throw std::runtime_error(dir + ": cannot create directory (not a directory)");
}

}  // namespace pce::sim

// SPDX-License-Identifier: MIT
// Frame files and the output directory (pce/sim/frames.hpp).
#include <pce/sim/frames.hpp>

#include <pce/sim/mesh.hpp>
#include <pce/sim/obj.hpp>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
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

void check_output_file(const std::filesystem::path& path, const std::vector<std::string>& extensions) {
  namespace fs = std::filesystem;
  const auto fail = [&](const std::string& what) { throw std::invalid_argument(path.string() + ": " + what); };
  if (path.empty()) throw std::invalid_argument("\"\": an empty file name");
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (fs::is_directory(status)) fail("is a directory");
  std::string extension = path.extension().string(), expected;
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (std::size_t k = 0; k < extensions.size(); ++k)
    expected += (k == 0 ? "" : k + 1 == extensions.size() ? " or " : ", ") + extensions[k];
  if (std::find(extensions.begin(), extensions.end(), extension) == extensions.end())
    fail("expected a file name ending in " + expected);
  if (fs::exists(status)) {
    if (!fs::is_regular_file(status)) fail("exists and is not a regular file");
    if (access(path.c_str(), W_OK) != 0) fail(std::string("cannot be written (") + std::strerror(errno) + ")");
    return;
  }
  // The nearest existing ancestor must be a directory we may create files in.
  fs::path ancestor = fs::absolute(path, error).parent_path();
  while (!ancestor.empty() && !fs::exists(ancestor, error) && ancestor != ancestor.parent_path())
    ancestor = ancestor.parent_path();
  if (!fs::is_directory(ancestor, error)) fail(ancestor.string() + " is not a directory");
  if (access(ancestor.c_str(), W_OK | X_OK) != 0)
    fail("cannot create files in " + ancestor.string() + " (" + std::strerror(errno) + ")");
}

}  // namespace pce::sim

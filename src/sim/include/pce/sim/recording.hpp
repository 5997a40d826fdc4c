// SPDX-License-Identifier: MIT
/// @file
/// The frames a run keeps for its movie and its USD cache (`pce/sim/movie.hpp`,
/// `pce/sim/usd.hpp`), which are written when the run ends: each recorded frame's number,
/// time and deformable vertex positions, the positions as 32-bit floats, appended to a
/// temporary file and read back in order. The file is removed with the recording.
#pragma once

#include <Eigen/Core>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <vector>

namespace pce::sim {

/// Recorded frames in a temporary file: append, then read back in order.
class FrameRecording {
 public:
  /// Creates (or empties) `file` for frames of `vertex_count` vertices. Throws
  /// `std::runtime_error("<file>: cannot write")` if it cannot be created.
  FrameRecording(std::filesystem::path file, int vertex_count);
  /// Removes the file.
  ~FrameRecording();
  FrameRecording(const FrameRecording&) = delete;
  FrameRecording& operator=(const FrameRecording&) = delete;

  /// Appends frame `frame` at time `time` (s) with positions `x` (3 × `vertex_count`,
  /// rounded to float). Throws `std::invalid_argument` for another vertex count and
  /// `std::runtime_error` naming the file if it cannot be written.
  void append(int frame, double time, const Eigen::Matrix3Xd& x);

  /// Recorded frames so far.
  int size() const { return static_cast<int>(frames_.size()); }
  /// The recorded frames' numbers, in order.
  const std::vector<int>& frames() const { return frames_; }
  /// The recorded frames' times (s), in order.
  const std::vector<double>& times() const { return times_; }
  /// Vertices per frame.
  int vertex_count() const { return vertex_count_; }
  /// The temporary file.
  const std::filesystem::path& file() const { return file_; }

  /// Calls `visit(k, positions)` for each recorded frame k = 0, 1, … in order, with the
  /// positions of vertices [`first`, `first` + `count`) as written (3 × `count` floats).
  /// Throws `std::out_of_range` for a range beyond `vertex_count` and `std::runtime_error`
  /// naming the file if it cannot be read back.
  void for_each(int first, int count, const std::function<void(int, const Eigen::Matrix3Xf&)>& visit) const;
  /// The same for every vertex.
  void for_each(const std::function<void(int, const Eigen::Matrix3Xf&)>& visit) const {
    for_each(0, vertex_count_, visit);
  }

 private:
  std::filesystem::path file_;
  int vertex_count_ = 0;
  std::FILE* out_ = nullptr;
  std::vector<int> frames_;
  std::vector<double> times_;
};

}  // namespace pce::sim

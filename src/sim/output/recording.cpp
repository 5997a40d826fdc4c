// SPDX-License-Identifier: MIT
// Recorded frames in a temporary file (pce/sim/recording.hpp): one record per frame, the
// positions as 3 × V floats, column after column; frame numbers and times stay in memory.
#include <pce/sim/recording.hpp>

#include <memory>
#include <stdexcept>
#include <string>
#include <system_error>

namespace pce::sim {

FrameRecording::FrameRecording(std::filesystem::path file, int vertex_count)
    : file_(std::move(file)), vertex_count_(vertex_count) {
  if (vertex_count < 0) throw std::invalid_argument("FrameRecording: negative vertex count");
  out_ = std::fopen(file_.c_str(), "wb");
  if (!out_) throw std::runtime_error(file_.string() + ": cannot write");
}

FrameRecording::~FrameRecording() {
  if (out_) std::fclose(out_);
  std::error_code ignored;
  std::filesystem::remove(file_, ignored);
}

void FrameRecording::append(int frame, double time, const Eigen::Matrix3Xd& x) {
  if (x.cols() != vertex_count_)
    throw std::invalid_argument("FrameRecording::append: " + std::to_string(x.cols()) + " vertices, expected " +
                                std::to_string(vertex_count_));
  const Eigen::Matrix3Xf f = x.cast<float>();
  const std::size_t n = static_cast<std::size_t>(f.size());
  if (std::fwrite(f.data(), sizeof(float), n, out_) != n || std::fflush(out_) != 0)
    throw std::runtime_error(file_.string() + ": cannot write");
  frames_.push_back(frame);
  times_.push_back(time);
}

void FrameRecording::for_each(int first, int count,
                              const std::function<void(int, const Eigen::Matrix3Xf&)>& visit) const {
  if (first < 0 || count < 0 || first > vertex_count_ - count)
    throw std::out_of_range("FrameRecording::for_each: vertices [" + std::to_string(first) + ", " +
                            std::to_string(first + count) + ") of " + std::to_string(vertex_count_));
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(file_.c_str(), "rb"), std::fclose);
  std::FILE* in = file.get();
  if (!in) throw std::runtime_error(file_.string() + ": cannot read");
  const long record = 3L * vertex_count_ * static_cast<long>(sizeof(float));
  Eigen::Matrix3Xf x(3, count);
  const std::size_t n = static_cast<std::size_t>(x.size());
  for (int k = 0; k < size(); ++k) {
    const long at = k * record + 3L * first * static_cast<long>(sizeof(float));
    if (std::fseek(in, at, SEEK_SET) != 0 || std::fread(x.data(), sizeof(float), n, in) != n) {
      throw std::runtime_error(file_.string() + ": cannot read frame " + std::to_string(frames_[k]) + " back");
    }
    visit(k, x);
  }
}

}  // namespace pce::sim

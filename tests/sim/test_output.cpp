// SPDX-License-Identifier: MIT
// pce::sim output (src/sim/output): the PNG picture read back (size, mesh and strand colours,
// background), robustness to empty, degenerate and non-finite input, write errors; frame
// paths, frames read back, and the output directory.
#include <pce/sim/frames.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/obj.hpp>
#include <pce/sim/render.hpp>

#include <stb/stb_image.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace {
namespace fs = std::filesystem;
using pce::sim::RenderMesh;
using pce::sim::RenderOptions;

fs::path tmp(const std::string& name) { return fs::path(PCE_TEST_TMP) / name; }

struct Image {
  int width = 0, height = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> data{nullptr, stbi_image_free};
  const unsigned char* at(int x, int y) const { return data.get() + (static_cast<std::size_t>(y) * width + x) * 3; }
};

Image load(const fs::path& path) {
  Image image;
  int channels = 0;
  image.data.reset(stbi_load(path.string().c_str(), &image.width, &image.height, &channels, 3));
  EXPECT_TRUE(image.data) << path << ": " << stbi_failure_reason();
  return image;
}

/// Pixels where channel `c` exceeds both others by more than 60.
long dominant(const Image& image, int c) {
  long n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const unsigned char* p = image.at(x, y);
      n += p[c] > p[(c + 1) % 3] + 60 && p[c] > p[(c + 2) % 3] + 60;
    }
  return n;
}

/// Pixels equal to the default background (0.92, 0.92, 0.93) → (235, 235, 237).
long background(const Image& image) {
  long n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const unsigned char* p = image.at(x, y);
      n += p[0] == 235 && p[1] == 235 && p[2] == 237;
    }
  return n;
}

RenderMesh red_cloth() {
  const pce::sim::Mesh g = pce::sim::grid(1.0, 1.0, 20, 20);
  RenderMesh m;
  m.positions = g.positions;
  for (Eigen::Index i = 0; i < m.positions.cols(); ++i)
    m.positions(2, i) = 0.1 * std::sin(6 * m.positions(0, i)) * std::cos(4 * m.positions(1, i));
  m.triangles = g.triangles;
  m.color = Eigen::Vector3f(0.9f, 0.15f, 0.1f);
  return m;
}

RenderMesh blue_strand() {
  const pce::sim::Mesh s = pce::sim::strands(1, 20, 1.0, 0.1, 0.1);
  RenderMesh m;
  m.positions = s.positions;
  m.positions.row(2).array() += 0.5;  // hanging from above the cloth down through it
  m.segments = s.segments;
  m.color = Eigen::Vector3f(0.1f, 0.2f, 0.95f);
  return m;
}

TEST(Render, GridAndStrandReadBack) {
  const fs::path path = tmp("render_grid_strand.png");
  fs::remove(path);
  RenderOptions opts;
  opts.width = 320;
  opts.height = 240;
  pce::sim::render_png(path.string(), {red_cloth(), blue_strand()}, opts);
  const Image image = load(path);
  ASSERT_TRUE(image.data);
  EXPECT_EQ(image.width, 320);
  EXPECT_EQ(image.height, 240);
  const long pixels = 320L * 240L;
  EXPECT_GT(dominant(image, 0), pixels / 10) << "the cloth's red";
  EXPECT_GT(dominant(image, 2), 50) << "the strand's blue";
  EXPECT_GT(background(image), pixels / 10);
  // The margin: the corners and the border rows are background.
  for (const auto& [x, y] : {std::pair{0, 0}, {319, 0}, {0, 239}, {319, 239}, {160, 0}, {160, 239}}) {
    const unsigned char* p = image.at(x, y);
    EXPECT_EQ(p[0], 235) << x << ", " << y;
    EXPECT_EQ(p[2], 237) << x << ", " << y;
  }
}

TEST(Render, CentresWhatItDraws) {
  // A tall scene (two cloths 0.8 m apart) seen steeply from above: the picture of every vertex is
  // centred and fits, so the drawn pixels' box is centred and the border rows are empty.
  // (The vertical centring once had its sign flipped: tall scenes lost their top.)
  RenderMesh low = red_cloth(), high = red_cloth();
  high.positions.row(2).array() += 0.8;
  RenderOptions opts;
  opts.width = 320;
  opts.height = 240;
  opts.view_direction = Eigen::Vector3d(-0.8, -1.6, -1.0);  // the hammock's: steeply down
  const fs::path path = tmp("render_centred.png");
  pce::sim::render_png(path.string(), {low, high}, opts);
  const Image image = load(path);
  ASSERT_TRUE(image.data);
  int x0 = image.width, x1 = -1, y0 = image.height, y1 = -1;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const unsigned char* p = image.at(x, y);
      if (p[0] == 235 && p[1] == 235 && p[2] == 237) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  ASSERT_GE(x1, 0);
  EXPECT_NEAR(0.5 * (x0 + x1), 0.5 * (image.width - 1), 3.0);
  EXPECT_NEAR(0.5 * (y0 + y1), 0.5 * (image.height - 1), 3.0);
  EXPECT_GT(y0, 0);
  EXPECT_LT(y1, image.height - 1);
  // it fills the image along the limiting axis, but for the 5 % margin
  EXPECT_GT(std::max((x1 - x0 + 1) / 320.0, (y1 - y0 + 1) / 240.0), 0.85);
}

TEST(Render, ShadingVaries) {
  const fs::path path = tmp("render_shading.png");
  RenderOptions opts;
  opts.width = 200;
  opts.height = 150;
  pce::sim::render_png(path.string(), {red_cloth()}, opts);
  const Image image = load(path);
  ASSERT_TRUE(image.data);
  int lo = 255, hi = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const unsigned char* p = image.at(x, y);
      if (p[0] > p[1] + 60) lo = std::min<int>(lo, p[0]), hi = std::max<int>(hi, p[0]);
    }
  EXPECT_GT(hi - lo, 40) << "a curved cloth is not lit uniformly";
}

TEST(Render, EmptyDegenerateAndNonFiniteDoNotCrash) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  RenderOptions opts;
  opts.width = 64;
  opts.height = 48;

  pce::sim::render_png(tmp("render_nothing.png").string(), {}, opts);
  Image image = load(tmp("render_nothing.png"));
  ASSERT_TRUE(image.data);
  EXPECT_EQ(background(image), 64L * 48L);

  RenderMesh bad;
  bad.positions.resize(3, 6);
  bad.positions << 0, 1, 2, nan, 0, 5,  //
      0, 0, 0, 0, 1, inf,               //
      0, 0, 0, 0, 0, 0;
  bad.triangles.resize(3, 4);
  bad.triangles << 0, 0, 0, 0,  //
      1, 1, 3, 1,               //
      2, 2, 4, 9;               // collinear, repeated, non-finite, out of range
  bad.segments.resize(2, 3);
  bad.segments << 0, 3, 0,  //
      0, 5, -2;
  pce::sim::render_png(tmp("render_bad.png").string(), {bad, RenderMesh{}}, opts);
  image = load(tmp("render_bad.png"));
  ASSERT_TRUE(image.data);
  EXPECT_EQ(image.width, 64);

  RenderMesh point;  // one vertex: no extent to fit
  point.positions = Eigen::Matrix3Xd::Zero(3, 1);
  point.segments = Eigen::Matrix2Xi::Zero(2, 1);
  pce::sim::render_png(tmp("render_point.png").string(), {point}, opts);
  EXPECT_TRUE(load(tmp("render_point.png")).data);

  opts.width = 0;
  EXPECT_THROW(pce::sim::render_png(tmp("render_zero.png").string(), {}, opts), std::invalid_argument);
}

TEST(Render, UnwritablePathThrowsNamingIt) {
  const std::string path = (tmp("no_such_dir") / "sub" / "picture.png").string();
  try {
    pce::sim::render_png(path, {red_cloth()}, RenderOptions{});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path + ": cannot write PNG");
  }
}

TEST(Render, TimeAtDefaultSize) {
  const pce::sim::Mesh g = pce::sim::grid(1.0, 1.0, 100, 100);
  RenderMesh cloth;
  cloth.positions = g.positions;
  cloth.triangles = g.triangles;
  for (Eigen::Index i = 0; i < cloth.positions.cols(); ++i)
    cloth.positions(2, i) = 0.1 * std::sin(9 * cloth.positions(0, i) + 7 * cloth.positions(1, i));
  const auto start = std::chrono::steady_clock::now();
  pce::sim::render_png(tmp("render_time.png").string(), {cloth, blue_strand()}, RenderOptions{});
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::cout << "render 960 x 720, 20000 triangles + 20 segments: " << ms << " ms\n";
  RecordProperty("milliseconds", std::to_string(ms));
  EXPECT_TRUE(load(tmp("render_time.png")).data);
}

TEST(Frames, Paths) {
  EXPECT_EQ(pce::sim::frame_path("out", 1), (fs::path("out") / "frame_0001.obj").string());
  EXPECT_EQ(pce::sim::frame_path("out", 0), (fs::path("out") / "frame_0000.obj").string());
  EXPECT_EQ(pce::sim::frame_path("out/run", 9999), (fs::path("out/run") / "frame_9999.obj").string());
  EXPECT_EQ(pce::sim::frame_path("out", 12345), (fs::path("out") / "frame_12345.obj").string());
  EXPECT_EQ(pce::sim::frame_path("out", 1), "out/frame_0001.obj");
  EXPECT_THROW(pce::sim::frame_path("out", -1), std::invalid_argument);
}

TEST(Frames, WrittenFrameReadsBack) {
  const std::string dir = tmp("frames_out").string();
  fs::remove_all(dir);
  pce::sim::ensure_directory(dir);
  const pce::sim::Mesh g = pce::sim::grid(1.0, 2.0, 3, 2);
  Eigen::Matrix3Xd x = g.positions;
  x(2, 3) = 0.1 + 1e-17;
  const Eigen::Matrix2Xi segments = (Eigen::Matrix2Xi(2, 1) << 0, 11).finished();
  pce::sim::write_frame(dir, 7, x, g.triangles, segments);
  const pce::sim::Mesh back = pce::sim::read_obj(fs::path(dir) / "frame_0007.obj");
  EXPECT_EQ(back.positions, x);
  EXPECT_EQ(back.triangles, g.triangles);
  EXPECT_EQ(back.segments, segments);
}

TEST(Frames, EnsureDirectory) {
  const fs::path base = tmp("ensure_dir");
  fs::remove_all(base);
  const std::string nested = (base / "a" / "b").string();
  pce::sim::ensure_directory(nested);
  EXPECT_TRUE(fs::is_directory(nested));
  pce::sim::ensure_directory(nested);  // already there
  // A directory under a regular file cannot be made; the error names it.
  std::ofstream(base / "file") << "x";
  const std::string under_file = (base / "file" / "sub").string();
  try {
    pce::sim::ensure_directory(under_file);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(under_file + ": cannot create directory", 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
  EXPECT_THROW(pce::sim::ensure_directory((base / "file").string()), std::runtime_error);  // exists, not a dir
}

}  // namespace

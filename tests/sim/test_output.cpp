// SPDX-License-Identifier: MIT
// pce::sim output (src/sim/output): the PNG picture read back (size, mesh and strand colours,
// background), robustness to empty, degenerate and non-finite input, write errors; frame
// paths, frames read back, and the output directory. A view fitted to several frames frames
// each of them; recorded frames read back as floats; the checks of a movie's or cache's
// path; ffmpeg found on PATH only, its failures reported with its message; the USD cache of
// a scene with cloth, strands, a volume and every obstacle shape read back by a small parser.
#include <pce/sim/frames.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/movie.hpp>
#include <pce/sim/obj.hpp>
#include <pce/sim/recording.hpp>
#include <pce/sim/render.hpp>
#include <pce/sim/scene.hpp>
#include <pce/sim/usd.hpp>

#include "ffprobe.hpp"
#include "usda_reader.hpp"

#include <stb/stb_image.h>

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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

TEST(Render, PngIsTheRgbOfTheViewFittedToItsMeshes) {
  const std::vector<RenderMesh> meshes{red_cloth(), blue_strand()};
  RenderOptions opts;
  opts.width = 320, opts.height = 200;
  pce::sim::render_png(tmp("fit_same.png").string(), meshes, opts);
  pce::sim::ViewFit fit(opts);
  for (const RenderMesh& m : meshes) fit.include(m.positions);
  for (const RenderMesh& m : meshes) fit.cover(m.positions);
  const std::vector<std::uint8_t> rgb = pce::sim::render_rgb(meshes, opts, fit.view());
  const Image png = load(tmp("fit_same.png"));
  ASSERT_EQ(rgb.size(), std::size_t{320 * 200 * 3});
  EXPECT_TRUE(std::equal(rgb.begin(), rgb.end(), png.data.get()));
  EXPECT_THROW(fit.include(meshes[0].positions), std::logic_error);  // the first pass is over
  RenderOptions other = opts;
  other.width = 322;
  EXPECT_THROW(pce::sim::render_rgb(meshes, other, fit.view()), std::invalid_argument);
  // Nothing finite to fit: the background.
  pce::sim::ViewFit empty(opts);
  EXPECT_FALSE(empty.view().valid);
  const std::vector<std::uint8_t> blank = pce::sim::render_rgb(meshes, opts, empty.view());
  EXPECT_TRUE(std::all_of(blank.begin(), blank.end(), [](std::uint8_t c) { return c == 235 || c == 237; }));
}

/// Pixels of `rgb` (w × h) where red exceeds green and blue by more than 60, and how many of
/// them lie within `border` pixels of the image's edge.
std::pair<long, long> red_pixels(const std::vector<std::uint8_t>& rgb, int w, int h, int border, double* mean_x) {
  long n = 0, edge = 0;
  double sx = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::uint8_t* p = rgb.data() + (static_cast<std::size_t>(y) * w + x) * 3;
      if (p[0] > p[1] + 60 && p[0] > p[2] + 60) {
        ++n, sx += x;
        edge += x < border || y < border || x >= w - border || y >= h - border;
      }
    }
  if (mean_x) *mean_x = n ? sx / n : -1;
  return {n, edge};
}

TEST(Render, OneViewFramesEveryFrame) {
  // The cloth at two places 3 m apart: one view fitted to both shows it whole in each
  // picture, once on the left and once on the right, smaller than a picture fitted to one.
  RenderMesh here = red_cloth(), there = red_cloth();
  there.positions.row(0).array() += 3.0;
  RenderOptions opts;
  opts.width = 400, opts.height = 300, opts.view_direction = Eigen::Vector3d(0, 0.3, -1);
  pce::sim::ViewFit fit(opts);
  fit.include(here.positions), fit.include(there.positions);
  fit.cover(here.positions), fit.cover(there.positions);
  const pce::sim::RenderView view = fit.view();
  ASSERT_TRUE(view.valid);
  double x_here = 0, x_there = 0;
  const auto [n_here, edge_here] = red_pixels(pce::sim::render_rgb({here}, opts, view), 400, 300, 8, &x_here);
  const auto [n_there, edge_there] = red_pixels(pce::sim::render_rgb({there}, opts, view), 400, 300, 8, &x_there);
  EXPECT_GT(n_here, 1000);
  EXPECT_GT(n_there, 1000);
  EXPECT_EQ(edge_here, 0);  // within the margin: nothing cut off
  EXPECT_EQ(edge_there, 0);
  EXPECT_LT(x_here, 200);
  EXPECT_GT(x_there, 200);
  pce::sim::ViewFit alone(opts);
  alone.include(here.positions), alone.cover(here.positions);
  const auto [n_alone, edge_alone] = red_pixels(pce::sim::render_rgb({here}, opts, alone.view()), 400, 300, 8, nullptr);
  EXPECT_GT(n_alone, 2 * n_here);
  EXPECT_EQ(edge_alone, 0);
}

TEST(Recording, ReadsBackWhatWasAppendedAsFloats) {
  const fs::path file = tmp("recording.tmp");
  Eigen::Matrix3Xd a(3, 4), b(3, 4);
  a << 0.1, 1.0 / 3, -2.5, 1e-7, 4, 5, 6, 7, 8, 9, 10, 11;
  b = a * 1.5;
  {
    pce::sim::FrameRecording r(file, 4);
    EXPECT_TRUE(fs::is_regular_file(file));
    r.append(0, 0.0, a);
    r.append(5, 0.125, b);
    EXPECT_THROW(r.append(6, 0.2, Eigen::Matrix3Xd(3, 3)), std::invalid_argument);
    EXPECT_EQ(r.size(), 2);
    EXPECT_EQ(r.frames(), (std::vector<int>{0, 5}));
    EXPECT_EQ(r.times(), (std::vector<double>{0.0, 0.125}));
    int visits = 0;
    r.for_each([&](int k, const Eigen::Matrix3Xf& x) {
      EXPECT_EQ(k, visits++);
      EXPECT_EQ(x, (k == 0 ? a : b).cast<float>());
    });
    EXPECT_EQ(visits, 2);
    r.for_each(
        1, 2, [&](int k, const Eigen::Matrix3Xf& x) { EXPECT_EQ(x, (k == 0 ? a : b).middleCols(1, 2).cast<float>()); });
    EXPECT_THROW(r.for_each(3, 2, [](int, const Eigen::Matrix3Xf&) {}), std::out_of_range);
  }
  EXPECT_FALSE(fs::exists(file));  // removed with the recording
}

TEST(OutputFile, ChecksNameKindAndPlace) {
  const fs::path base = tmp("output_file");
  fs::remove_all(base);
  fs::create_directories(base / "dir.mp4");
  std::ofstream(base / "file") << "x";
  std::ofstream(base / "old.mp4") << "x";
  const std::vector<std::string> movie = pce::sim::movie_extensions();
  EXPECT_NO_THROW(pce::sim::check_output_file(base / "new" / "deeper" / "movie.mp4", movie));  // made when written
  EXPECT_NO_THROW(pce::sim::check_output_file(base / "old.mp4", movie));                       // overwritten
  EXPECT_NO_THROW(pce::sim::check_output_file(base / "MOVIE.MKV", movie));
  const auto message = [&](const fs::path& p, const std::vector<std::string>& endings) -> std::string {
    try {
      pce::sim::check_output_file(p, endings);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no exception";
  };
  EXPECT_EQ(message(base / "movie.gif", movie),
            (base / "movie.gif").string() + ": expected a file name ending in .mp4, .m4v, .mov or .mkv");
  EXPECT_EQ(message(base / "cache.txt", pce::sim::usd_extensions()),
            (base / "cache.txt").string() + ": expected a file name ending in .usda or .usd");
  EXPECT_EQ(message(base / "dir.mp4", movie), (base / "dir.mp4").string() + ": is a directory");
  EXPECT_EQ(
      message(base / "file" / "movie.mp4", movie),
      (base / "file" / "movie.mp4").string() + ": " + fs::absolute(base / "file").string() + " is not a directory");
  EXPECT_EQ(message("", movie), "\"\": an empty file name");
  EXPECT_TRUE(fs::is_empty(base / "dir.mp4"));
  EXPECT_FALSE(fs::exists(base / "new"));  // nothing written
}

TEST(Usd, IdentifiersAreValidPrimNames) {
  EXPECT_EQ(pce::sim::usd_identifier("cloth"), "cloth");
  EXPECT_EQ(pce::sim::usd_identifier("sheet 1"), "sheet_1");
  EXPECT_EQ(pce::sim::usd_identifier("2d-grid.v2"), "_2d_grid_v2");
  EXPECT_EQ(pce::sim::usd_identifier(""), "_");
  EXPECT_EQ(pce::sim::usd_identifier("Ünï"), "__n__");  // each byte of a UTF-8 letter: one "_"
  EXPECT_EQ(pce::sim::usd_identifier("_x9"), "_x9");
}

/// A scene with a cloth named with a space, strands, a volume, a mesh named "obstacles" and
/// one obstacle of each shape (the box moving); gravity only. The cloth and the strands are
/// turned, so that their coordinates need all nine digits of a float.
std::unique_ptr<pce::sim::Scene> usd_scene() {
  const fs::path dir = tmp("usd_scene");
  fs::create_directories(dir);
  std::ofstream(dir / "tri.obj") << "v 0 0 0\nv 0.5 0 0\nv 0 0.5 0\nf 1 2 3\n";
  const std::string text = R"({
    "dt": 0.02, "frames": 3,
    "meshes": [
      {"name": "sheet 1", "generator": {"type": "grid", "width": 0.4, "height": 0.4, "nx": 3, "ny": 2},
       "transform": {"rotation": {"axis": [1, 2, 3], "degrees": 17}, "translation": [0.1234567, 0, 0]}},
      {"name": "hair", "generator": {"type": "strands", "count": 2, "segments": 3, "length": 0.3, "spacing": 0.1},
       "transform": {"rotation": {"axis": [3, 1, 0], "degrees": 10}, "translation": [1, 0, 1]}},
      {"name": "block", "generator": {"type": "tet_box", "size": [0.2, 0.2, 0.2], "n": [1, 1, 1]},
       "transform": {"translation": [-1, 0, 0.5]}},
      {"name": "obstacles", "generator": {"type": "grid", "width": 0.2, "height": 0.2, "nx": 1, "ny": 1},
       "transform": {"translation": [0, 1, 0.5]}}
    ],
    "obstacles": [
      {"name": "ball", "shape": "sphere", "radius": 0.25, "position": [2, 0, 0]},
      {"name": "slider", "shape": "box", "half_extents": [0.1, 0.2, 0.3], "position": [0, -2, 0],
       "motion": {"velocity": [1, 0, 0], "angular_velocity": [0, 0, 2]}},
      {"name": "rod", "shape": "capsule", "radius": 0.05, "half_length": 0.3, "position": [0, 0, -1],
       "rotation": {"axis": [1, 0, 0], "degrees": 90}},
      {"name": "tri", "shape": "mesh", "file": "tri.obj", "position": [3, 3, 0]}
    ],
    "effects": [{"type": "gravity"}]
  })";
  return pce::sim::load_scene_text(text, "usd_scene.json", dir);
}

/// A USD matrix4d (a tuple of four row tuples) as the 4 × 4 matrix it is the transpose of.
Eigen::Matrix4d usd_matrix(const pce::sim::usda::Value& v) {
  Eigen::Matrix4d m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m(j, i) = v.items.at(i).items.at(j).x;
  return m;
}

TEST(Usd, CacheOfASceneReadsBack) {
  namespace usda = pce::sim::usda;
  auto scene = usd_scene();
  pce::sim::Simulation& sim = scene->simulation;
  const fs::path file = tmp("usd_scene") / "out" / "cache.usda";
  fs::remove_all(file.parent_path());
  // Frames 0, 1 and 3 recorded (not 2): the time codes are the frame numbers.
  std::vector<Eigen::Matrix3Xd> x;
  std::vector<double> t;
  {
    pce::sim::FrameRecording recording(tmp("usd_scene") / "frames.tmp", sim.model.vertex_count());
    for (int f = 0; f <= 3; ++f) {
      if (f > 0) sim.step();
      if (f == 2) continue;
      recording.append(sim.frame, sim.time, sim.x);
      x.push_back(sim.x);
      t.push_back(sim.time);
    }
    pce::sim::write_usda(file, *scene, recording);
  }
  EXPECT_FALSE(fs::exists(fs::path(file.string() + ".tmp")));
  const usda::Layer layer = usda::read(file.string());
  EXPECT_EQ(layer.metadata.at("defaultPrim").text, "World");
  EXPECT_EQ(layer.metadata.at("upAxis").text, "Z");
  EXPECT_EQ(layer.metadata.at("metersPerUnit").x, 1.0);
  EXPECT_EQ(layer.metadata.at("timeCodesPerSecond").x, 1 / 0.02);
  EXPECT_EQ(layer.metadata.at("framesPerSecond").x, 1 / 0.02);
  EXPECT_EQ(layer.metadata.at("startTimeCode").x, 0.0);
  EXPECT_EQ(layer.metadata.at("endTimeCode").x, 3.0);
  ASSERT_EQ(layer.root.children.size(), 1u);
  const usda::Prim& world = *layer.root.children[0];
  EXPECT_EQ(world.type, "Xform");
  std::vector<std::string> names;
  for (const auto& c : world.children) names.push_back(c->type + " " + c->name);
  EXPECT_EQ(names, (std::vector<std::string>{"Mesh sheet_1", "BasisCurves hair", "Mesh block", "Mesh obstacles_2",
                                             "Scope obstacles"}));
  const std::vector<double> times{0, 1, 3};
  // Meshes: topology once, points and extent at every recorded frame, as recorded (float).
  for (const auto& [path, mesh] : std::vector<std::pair<std::string, int>>{
           {"/World/sheet_1", 0}, {"/World/block", 2}, {"/World/obstacles_2", 3}}) {
    SCOPED_TRACE(path);
    const pce::sim::MeshRange& r = sim.model.meshes[static_cast<std::size_t>(mesh)];
    const usda::Prim* p = layer.at(path);
    ASSERT_TRUE(p);
    const auto& a = p->attributes;
    EXPECT_EQ(a.at("subdivisionScheme").value.text, "none");
    EXPECT_EQ(a.at("doubleSided").value.text, r.tetrahedron_count > 0 ? "false" : "true");
    EXPECT_EQ(usda::ints(a.at("faceVertexCounts").value),
              std::vector<int>(static_cast<std::size_t>(r.triangle_count), 3));
    const Eigen::Matrix3Xi tri =
        sim.model.triangles.middleCols(r.first_triangle, r.triangle_count).array() - r.first_vertex;
    EXPECT_EQ(usda::ints(a.at("faceVertexIndices").value), std::vector<int>(tri.data(), tri.data() + tri.size()));
    EXPECT_TRUE(a.at("points").samples.size() == 3 && !a.at("points").has_value);
    for (std::size_t k = 0; k < 3; ++k) {
      const Eigen::Matrix3Xf want = x[k].middleCols(r.first_vertex, r.vertex_count).cast<float>();
      EXPECT_EQ(usda::floats(a.at("points").samples.at(times[k])),
                std::vector<float>(want.data(), want.data() + want.size()))
          << "time " << times[k];
      const std::vector<float> extent = usda::floats(a.at("extent").samples.at(times[k]));
      ASSERT_EQ(extent.size(), 6u);
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(extent[static_cast<std::size_t>(c)], want.row(c).minCoeff());
        EXPECT_EQ(extent[static_cast<std::size_t>(3 + c)], want.row(c).maxCoeff());
      }
    }
    EXPECT_EQ(a.at("points").type, "point3f[]");
  }
  // The volume's triangles are its 12 boundary faces; its points are all its vertices.
  EXPECT_EQ(sim.model.meshes[2].triangle_count, 12);
  // Strands: one linear curve per strand.
  {
    const usda::Prim* p = layer.at("/World/hair");
    ASSERT_TRUE(p);
    const pce::sim::MeshRange& r = sim.model.meshes[1];
    EXPECT_EQ(p->attributes.at("type").value.text, "linear");
    EXPECT_EQ(usda::ints(p->attributes.at("curveVertexCounts").value), (std::vector<int>{4, 4}));
    EXPECT_EQ(p->attributes.at("widths").metadata.at("interpolation").text, "constant");
    EXPECT_FLOAT_EQ(static_cast<float>(p->attributes.at("widths").value.items.at(0).x), 0.01f);  // a tenth of 0.1 m
    for (std::size_t k = 0; k < 3; ++k) {
      const Eigen::Matrix3Xf want = x[k].middleCols(r.first_vertex, r.vertex_count).cast<float>();
      EXPECT_EQ(usda::floats(p->attributes.at("points").samples.at(times[k])),
                std::vector<float>(want.data(), want.data() + want.size()));
    }
  }
  // Obstacles: each shape under an Xform; the moving box's transform at every recorded
  // frame, the others' once.
  const auto shape = [&](const std::string& name) { return layer.at("/World/obstacles/" + name + "/shape"); };
  ASSERT_TRUE(shape("ball") && shape("slider") && shape("rod") && shape("tri"));
  EXPECT_EQ(shape("ball")->type, "Sphere");
  EXPECT_EQ(shape("ball")->attributes.at("radius").value.x, 0.25);
  EXPECT_EQ(shape("slider")->type, "Cube");
  EXPECT_EQ(shape("slider")->attributes.at("size").value.x, 2.0);
  const usda::Value& scale = shape("slider")->attributes.at("xformOp:scale").value;
  EXPECT_EQ(scale.items.at(0).x, 0.1);
  EXPECT_EQ(scale.items.at(1).x, 0.2);
  EXPECT_EQ(scale.items.at(2).x, 0.3);
  EXPECT_EQ(shape("rod")->type, "Capsule");
  EXPECT_EQ(shape("rod")->attributes.at("height").value.x, 0.6);
  EXPECT_EQ(shape("rod")->attributes.at("axis").value.text, "Z");
  EXPECT_EQ(shape("tri")->type, "Mesh");
  EXPECT_EQ(usda::floats(shape("tri")->attributes.at("points").value),
            (std::vector<float>{0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 0}));
  for (std::size_t o = 0; o < sim.obstacles.size(); ++o) {
    const pce::sim::Obstacle& obstacle = sim.obstacles[o];
    SCOPED_TRACE(obstacle.name);
    const usda::Prim* xform = layer.at("/World/obstacles/" + obstacle.name);
    EXPECT_EQ(xform->type, "Xform");
    const usda::Attribute& m = xform->attributes.at("xformOp:transform");
    EXPECT_EQ(m.type, "matrix4d");
    if (obstacle.name == "slider") {
      ASSERT_EQ(m.samples.size(), 3u);
      for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(usd_matrix(m.samples.at(times[k])), obstacle.pose(t[k]).matrix());
    } else {
      ASSERT_TRUE(m.has_value && m.samples.empty());
      EXPECT_EQ(usd_matrix(m.value), obstacle.pose(0).matrix());
    }
  }
}

TEST(Usd, UnwritablePlaceIsAnErrorNamingTheFile) {
  auto scene = usd_scene();
  const fs::path base = tmp("usd_unwritable");
  fs::remove_all(base);
  fs::create_directories(base);
  std::ofstream(base / "file") << "x";
  pce::sim::FrameRecording recording(base / "frames.tmp", scene->simulation.model.vertex_count());
  EXPECT_THROW(pce::sim::write_usda(base / "c.usda", *scene, recording), std::runtime_error);  // nothing recorded
  recording.append(0, 0, scene->simulation.x);
  try {
    pce::sim::write_usda(base / "file" / "c.usda", *scene, recording);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find((base / "file").string()), std::string::npos) << e.what();
  }
}

/// Sets PATH to `value` for the test's scope, then puts the old value back.
class PathFor {
 public:
  explicit PathFor(const std::string& value) : old_(std::getenv("PATH") ? std::getenv("PATH") : "") {
    setenv("PATH", value.c_str(), 1);
  }
  ~PathFor() { setenv("PATH", old_.c_str(), 1); }

 private:
  std::string old_;
};

/// A folder holding an executable `ffmpeg` shell script with `body`.
fs::path fake_ffmpeg(const std::string& name, const std::string& body) {
  const fs::path dir = tmp(name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "ffmpeg") << "#!/bin/sh\n" << body << "\n";
  chmod((dir / "ffmpeg").c_str(), 0755);
  return dir;
}

TEST(Movie, FfmpegIsFoundOnPathOnly) {
  const fs::path empty = tmp("path_empty");
  fs::create_directories(empty);
  {
    PathFor path(empty.string());
    EXPECT_TRUE(pce::sim::find_ffmpeg().empty());
  }
  const fs::path fake = fake_ffmpeg("path_fake", "exit 0");
  {
    PathFor path(empty.string() + ":" + fake.string());
    EXPECT_EQ(pce::sim::find_ffmpeg(), fake / "ffmpeg");
  }
  chmod((fake / "ffmpeg").c_str(), 0644);  // not executable: not found
  {
    PathFor path(fake.string());
    EXPECT_TRUE(pce::sim::find_ffmpeg().empty());
  }
  EXPECT_NE(pce::sim::ffmpeg_missing().find("apt-get install ffmpeg"), std::string::npos);
}

/// A three-frame recording of the USD test's scene (the cloth falling).
struct SmallRun {
  std::unique_ptr<pce::sim::Scene> scene = usd_scene();
  std::unique_ptr<pce::sim::FrameRecording> recording;
  explicit SmallRun(const std::string& name) {
    pce::sim::Simulation& sim = scene->simulation;
    recording = std::make_unique<pce::sim::FrameRecording>(tmp(name + ".tmp"), sim.model.vertex_count());
    for (int f = 0; f < 3; ++f) {
      if (f > 0) sim.step();
      recording->append(sim.frame, sim.time, sim.x);
    }
  }
};

TEST(Movie, FfmpegFailureIsAnErrorWithItsMessages) {
  SmallRun run("movie_fail");
  RenderOptions small;  // 90 kB a frame, more than a pipe holds: a write meets the closed pipe
  small.width = 200, small.height = 150;
  const fs::path movie = tmp("movie_fail") / "m.mp4";
  // ffmpeg ends at once, reading nothing (the frames meet a closed pipe: no SIGPIPE may end
  // the process), and ffmpeg reading everything and then failing.
  for (const std::string body : {"echo 'fake: Unknown encoder' >&2; echo 'fake: second line' >&2; exit 3",
                                 "/bin/cat > /dev/null; echo 'fake: late' >&2; exit 4"}) {
    SCOPED_TRACE(body);
    PathFor path(fake_ffmpeg("ffmpeg_fails", body).string());
    try {
      pce::sim::write_movie(movie, *run.scene, *run.recording, 25, small);
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      if (body.rfind("echo", 0) == 0) {
        EXPECT_EQ(what, movie.string() + ": ffmpeg failed (exit status 3): fake: Unknown encoder; fake: second line");
      } else {
        EXPECT_EQ(what, movie.string() + ": ffmpeg failed (exit status 4): fake: late");
      }
    }
    EXPECT_FALSE(fs::exists(movie.string() + ".ffmpeg-log"));  // ffmpeg's messages: removed
  }
  PathFor none(tmp("path_empty").string());
  try {
    pce::sim::write_movie(movie, *run.scene, *run.recording, 25, small);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), movie.string() + ": " + pce::sim::ffmpeg_missing());
  }
  EXPECT_THROW(pce::sim::write_movie(movie, *run.scene, *run.recording, 0, small), std::invalid_argument);
}

using pce::sim::testing::have_ffmpeg_and_ffprobe;
using pce::sim::testing::probe;

TEST(Movie, OneVideoFramePerRecordedFrame) {
  if (!have_ffmpeg_and_ffprobe()) GTEST_SKIP() << "ffmpeg or ffprobe is not installed (Debian: apt-get install ffmpeg)";
  SmallRun run("movie_frames");
  RenderOptions small;
  small.width = 160, small.height = 120;
  const fs::path movie = tmp("movie_frames") / "sub dir" / "m:1.mp4";  // a folder made, a colon in the name
  fs::remove_all(movie.parent_path().parent_path());
  pce::sim::write_movie(movie, *run.scene, *run.recording, 12.5, small);
  const auto p = probe(movie);
  EXPECT_EQ(p.count("nb_read_frames") ? p.at("nb_read_frames") : "", "3");
  EXPECT_EQ(p.count("codec_name") ? p.at("codec_name") : "", "h264");
  EXPECT_EQ(p.count("pix_fmt") ? p.at("pix_fmt") : "", "yuv420p");
  EXPECT_EQ(p.count("width") ? p.at("width") : "", "160");
  EXPECT_EQ(p.count("height") ? p.at("height") : "", "120");
  EXPECT_EQ(p.count("r_frame_rate") ? p.at("r_frame_rate") : "", "25/2");
  EXPECT_FALSE(fs::exists(movie.string() + ".ffmpeg-log"));
}

TEST(Movie, OneCameraForTheWholeRun) {
  // A cloth recorded at two places 3 m apart: decoded, the movie shows it on the left in its
  // first frame and on the right in its second, at about the same size (a camera fitted to
  // each frame would centre both).
  if (!have_ffmpeg_and_ffprobe()) GTEST_SKIP() << "ffmpeg or ffprobe is not installed (Debian: apt-get install ffmpeg)";
  auto scene = pce::sim::load_scene_text(R"({"dt": 0.01, "frames": 1, "view_direction": [0, 0.3, -1],
      "meshes": [{"name": "cloth", "generator": {"type": "grid", "width": 1, "height": 1, "nx": 8, "ny": 8}}],
      "effects": [{"type": "gravity"}]})",
                                         "one_camera.json", PCE_TEST_TMP);
  const Eigen::Matrix3Xd here = scene->simulation.x;
  Eigen::Matrix3Xd there = here;
  there.row(0).array() += 3.0;
  pce::sim::FrameRecording recording(tmp("one_camera.tmp"), static_cast<int>(here.cols()));
  recording.append(0, 0, here);
  recording.append(1, 0.01, there);
  RenderOptions opts;
  opts.width = 320, opts.height = 240, opts.view_direction = scene->view_direction;
  const fs::path movie = tmp("one_camera.mp4");
  pce::sim::write_movie(movie, *scene, recording, 10, opts);
  const std::string command = "ffmpeg -v error -i '" + movie.string() + "' -f rawvideo -pix_fmt rgb24 -";
  std::FILE* pipe = popen(command.c_str(), "r");
  ASSERT_TRUE(pipe);
  std::vector<std::uint8_t> frame(320 * 240 * 3);
  std::vector<std::pair<long, double>> seen;
  while (std::fread(frame.data(), 1, frame.size(), pipe) == frame.size()) {
    double mean_x = 0;
    const auto [n, edge] = red_pixels(frame, 320, 240, 4, &mean_x);
    EXPECT_EQ(edge, 0);
    seen.emplace_back(n, mean_x);
  }
  pclose(pipe);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_GT(seen[0].first, 500);
  EXPECT_LT(seen[0].second, 130);
  EXPECT_GT(seen[1].second, 190);
  EXPECT_NEAR(static_cast<double>(seen[1].first) / static_cast<double>(seen[0].first), 1.0, 0.2);
}

}  // namespace

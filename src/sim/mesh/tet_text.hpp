// SPDX-License-Identifier: MIT
/// @file
/// What the tetrahedral mesh readers share (internal; tet_io.cpp, msh.cpp): a text file read
/// line by line into tokens with errors naming the file and the line, number parsing, the
/// positions and positive tetrahedra a reader collects, and the mesh they make.
#pragma once

#include <pce/sim/input_error.hpp>
#include <pce/sim/mesh.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pce::sim::tet_text {

/// Largest element count a file may declare: a tetrahedral mesh has about six tetrahedra per
/// vertex, and a Gmsh file also lists its boundary triangles, lines and points. Counts above
/// are refused before anything is allocated.
constexpr long kMaxElements = 8 * kMaxVertices;

/// A text file read line by line, split into whitespace-separated tokens; blank lines (and,
/// with `comments`, everything from `#` on) are skipped. Errors name the file and the line.
class Lines {
 public:
  Lines(const std::filesystem::path& path, bool comments, const std::string& cannot_open = "cannot open the mesh file")
      : file_(path.string()), in_(path), comments_(comments) {
    if (!in_) throw InputError(file_, "", cannot_open);
  }

  /// The next non-blank line's tokens; false at the end of the file.
  bool next(std::vector<std::string>& tokens) {
    std::string text, token;
    while (std::getline(in_, text)) {
      ++line_;
      if (comments_) text = text.substr(0, text.find('#'));
      std::istringstream s(text);
      tokens.clear();
      while (s >> token) tokens.push_back(token);
      if (!tokens.empty()) return true;
    }
    if (in_.bad()) throw InputError(file_, "", "read error");
    return false;
  }

  /// `next`, or an error naming the line after the last one if the file ends before `expected`.
  void need(std::vector<std::string>& tokens, const std::string& expected) {
    if (!next(tokens)) {
      ++line_;
      fail("unexpected end of the file (expected " + expected + ")");
    }
  }

  /// An `InputError` naming the file and the current line.
  [[noreturn]] void fail(const std::string& what) const { fail_at(line_, what); }

  /// An `InputError` naming the file and line `line`.
  [[noreturn]] void fail_at(int line, const std::string& what) const {
    throw InputError(file_, "line " + std::to_string(line), what);
  }

  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  std::ifstream in_;
  bool comments_;
  int line_ = 0;
};

/// A finite decimal number (a coordinate).
inline double parse_real(const std::string& token, const Lines& in) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end == token.c_str() || *end != '\0' || errno == ERANGE) in.fail("expected a number, found '" + token + "'");
  if (!std::isfinite(v)) in.fail("non-finite coordinate '" + token + "'");
  return v;
}

/// A decimal integer in [lo, hi]; `what` names it in the errors.
inline long parse_integer(const std::string& token, long lo, long hi, const std::string& what, const Lines& in) {
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(token.c_str(), &end, 10);
  if (end == token.c_str() || *end != '\0' || errno == ERANGE)
    in.fail("expected " + what + " (an integer), found '" + token + "'");
  if (v < lo || v > hi)
    in.fail(what + " " + token + " out of range (expected " + std::to_string(lo) + " to " + std::to_string(hi) + ")");
  return v;
}

/// Checks that `t` has `count` tokens; `what` says what the line holds.
inline void require_tokens(const std::vector<std::string>& t, std::size_t count, const std::string& what,
                           const Lines& in) {
  if (t.size() != count)
    in.fail("expected " + what + " (" + std::to_string(count) + " values), found " + std::to_string(t.size()) +
            " values");
}

/// Positions and positive tetrahedra as a reader collects them.
struct Collected {
  std::vector<Eigen::Vector3d> x;
  std::vector<std::array<int, 4>> tets;

  /// Adds tetrahedron `v` (indices into `x`; `names` are the file's words for them),
  /// swapping c and d when its signed volume is negative. A repeated vertex or a flat
  /// tetrahedron (by `validate`'s measure) is an error at the current line.
  void add(std::array<int, 4> v, const std::array<std::string, 4>& names, const Lines& in) {
    const std::string which = "tetrahedron " + std::to_string(tets.size());
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < i; ++j)
        if (v[i] == v[j]) in.fail(which + " uses vertex " + names[i] + " twice");
    const Eigen::Vector3d e1 = x[v[1]] - x[v[0]], e2 = x[v[2]] - x[v[0]], e3 = x[v[3]] - x[v[0]];
    const double volume = e1.dot(e2.cross(e3)) / 6.0;
    const double longest = std::max({e1.norm(), e2.norm(), e3.norm(), (x[v[2]] - x[v[1]]).norm(),
                                     (x[v[3]] - x[v[1]]).norm(), (x[v[3]] - x[v[2]]).norm()});
    // Coordinates so large that these overflow are refused by `validate`, by vertex.
    if (std::isfinite(volume) && std::isfinite(longest) && !(std::abs(volume) > 1e-12 * longest * longest * longest)) {
      std::ostringstream s;
      s.precision(17);
      s << which << " (vertices " << names[0] << ", " << names[1] << ", " << names[2] << ", " << names[3]
        << ") is flat: volume " << volume << ", expected a volume above 1e-12 of its longest edge cubed";
      in.fail(s.str());
    }
    if (volume < 0) std::swap(v[2], v[3]);
    tets.push_back(v);
  }
};

/// The mesh of `c`: boundary faces as its triangles, no segments, validated as `source`.
inline Mesh finish(const Collected& c, const std::string& source) {
  if (c.tets.empty()) throw InputError(source, "", "no tetrahedra in the file");
  Mesh m;
  m.positions.resize(3, static_cast<Eigen::Index>(c.x.size()));
  for (std::size_t i = 0; i < c.x.size(); ++i) m.positions.col(static_cast<Eigen::Index>(i)) = c.x[i];
  m.tetrahedra.resize(4, static_cast<Eigen::Index>(c.tets.size()));
  for (std::size_t i = 0; i < c.tets.size(); ++i)
    m.tetrahedra.col(static_cast<Eigen::Index>(i)) << c.tets[i][0], c.tets[i][1], c.tets[i][2], c.tets[i][3];
  m.triangles = boundary_faces(m.tetrahedra);
  m.segments.resize(2, 0);
  validate(m, source);
  return m;
}

/// Reads a Gmsh .msh file (ASCII 2.x, 4.0 or 4.1): its nodes and tetrahedra (msh.cpp).
Mesh read_msh(const std::filesystem::path& path);

}  // namespace pce::sim::tet_text

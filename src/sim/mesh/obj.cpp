// SPDX-License-Identifier: MIT
#include <pce/sim/input_error.hpp>
#include <pce/sim/obj.hpp>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pce::sim {

namespace {

struct LineReader {
  std::string file;
  int line = 0;
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(file, "line " + std::to_string(line), what);
  }
};

double parse_coordinate(const std::string& token, const LineReader& r) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end == token.c_str() || *end != '\0' || errno == ERANGE) r.fail("expected a number, found '" + token + "'");
  if (!std::isfinite(v)) r.fail("non-finite coordinate '" + token + "'");
  return v;
}

/// The vertex index of an `f`/`l` token (`i`, `i/t`, `i//n`, `i/t/n`), 0-based.
int parse_index(const std::string& token, long vertex_count, const LineReader& r) {
  const std::string head = token.substr(0, token.find('/'));
  errno = 0;
  char* end = nullptr;
  const long i = std::strtol(head.c_str(), &end, 10);
  if (head.empty() || end == head.c_str() || *end != '\0' || errno == ERANGE)
    r.fail("expected a vertex index, found '" + token + "'");
  if (i == 0) r.fail("vertex index 0 (OBJ indices start at 1)");
  const long zero_based = i > 0 ? i - 1 : vertex_count + i;  // negative: relative to the vertices so far
  if (zero_based < 0 || zero_based >= vertex_count)
    r.fail("vertex index " + std::to_string(i) + " out of range (" + std::to_string(vertex_count) +
           " vertices so far)");
  return static_cast<int>(zero_based);
}

}  // namespace

Mesh read_obj(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) throw InputError(file, "", "cannot open the mesh file");
  std::vector<std::array<double, 3>> v;
  std::vector<std::array<int, 3>> f;
  std::vector<std::array<int, 2>> l;
  LineReader r{file};
  std::string text, keyword, token;
  while (std::getline(in, text)) {
    ++r.line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    std::istringstream ls(text);
    if (!(ls >> keyword) || keyword[0] == '#') continue;
    std::vector<std::string> t;
    while (ls >> token) {
      if (token[0] == '#') break;
      t.push_back(token);
    }
    if (keyword == "v") {
      if (t.size() < 3 || t.size() > 4) r.fail("a vertex needs 3 coordinates (and an optional weight)");
      v.push_back({parse_coordinate(t[0], r), parse_coordinate(t[1], r), parse_coordinate(t[2], r)});
    } else if (keyword == "f") {
      if (t.size() < 3) r.fail("a face needs at least 3 vertices");
      std::vector<int> idx;
      for (const auto& s : t) idx.push_back(parse_index(s, static_cast<long>(v.size()), r));
      for (std::size_t k = 1; k + 1 < idx.size(); ++k) f.push_back({idx[0], idx[k], idx[k + 1]});  // fan
    } else if (keyword == "l") {
      if (t.size() < 2) r.fail("a polyline needs at least 2 vertices");
      std::vector<int> idx;
      for (const auto& s : t) idx.push_back(parse_index(s, static_cast<long>(v.size()), r));
      for (std::size_t k = 0; k + 1 < idx.size(); ++k) l.push_back({idx[k], idx[k + 1]});
    }
    // vt, vn, o, g, s, usemtl, mtllib, …: not needed
  }
  if (in.bad()) throw InputError(file, "", "read error");
  Mesh m;
  m.positions.resize(3, static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) m.positions.col(static_cast<Eigen::Index>(i)) << v[i][0], v[i][1], v[i][2];
  m.triangles.resize(3, static_cast<Eigen::Index>(f.size()));
  for (std::size_t i = 0; i < f.size(); ++i) m.triangles.col(static_cast<Eigen::Index>(i)) << f[i][0], f[i][1], f[i][2];
  m.segments.resize(2, static_cast<Eigen::Index>(l.size()));
  for (std::size_t i = 0; i < l.size(); ++i) m.segments.col(static_cast<Eigen::Index>(i)) << l[i][0], l[i][1];
  validate(m, file);
  return m;
}

void write_obj(const std::filesystem::path& path, const Mesh& mesh) {
  const std::string file = path.string();
  std::FILE* out = std::fopen(file.c_str(), "w");
  if (!out) throw InputError(file, "", "cannot open the file for writing");
  bool ok = true;
  for (Eigen::Index i = 0; i < mesh.positions.cols(); ++i)
    ok = ok && std::fprintf(out, "v %.17g %.17g %.17g\n", mesh.positions(0, i), mesh.positions(1, i),
                            mesh.positions(2, i)) > 0;
  for (Eigen::Index i = 0; i < mesh.triangles.cols(); ++i)
    ok = ok && std::fprintf(out, "f %d %d %d\n", mesh.triangles(0, i) + 1, mesh.triangles(1, i) + 1,
                            mesh.triangles(2, i) + 1) > 0;
  for (Eigen::Index i = 0; i < mesh.segments.cols(); ++i)
    ok = ok && std::fprintf(out, "l %d %d\n", mesh.segments(0, i) + 1, mesh.segments(1, i) + 1) > 0;
  ok = (std::fclose(out) == 0) && ok;
  if (!ok) throw InputError(file, "", "write error");
}

}  // namespace pce::sim

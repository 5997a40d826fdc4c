// SPDX-License-Identifier: MIT
// The USD cache of a run (pce/sim/usd.hpp): the recorded frames as a text USD layer,
// written prim by prim, each prim's time samples read back from the recording.
#include <pce/sim/frames.hpp>
#include <pce/sim/movie.hpp>
#include <pce/sim/usd.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>

namespace pce::sim {

namespace fs = std::filesystem;

const std::vector<std::string>& usd_extensions() {
  static const std::vector<std::string> extensions{".usda", ".usd"};
  return extensions;
}

std::string usd_identifier(const std::string& name) {
  std::string id = name;
  for (char& c : id)
    if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) c = '_';
  if (id.empty() || (id[0] >= '0' && id[0] <= '9')) id.insert(id.begin(), '_');
  return id;
}

namespace {

/// `base`, or `base_2`, `base_3`, … : the first not in `used`, which then holds it.
std::string unique_name(const std::string& base, std::set<std::string>& used) {
  std::string name = base;
  for (int k = 2; used.count(name); ++k) name = base + "_" + std::to_string(k);
  used.insert(name);
  return name;
}

/// The shortest of %.15g, %.16g, %.17g that reads back as `v`.
std::string number(double v) {
  char text[40];
  for (const int digits : {15, 16, 17}) {
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    if (std::strtod(text, nullptr) == v) break;
  }
  return text;
}

/// Text written to a FILE*, with the file's name in the error.
class Writer {
 public:
  Writer(const fs::path& path, const fs::path& named) : named_(named), file_(std::fopen(path.c_str(), "wb")) {
    if (!file_) fail();
  }
  ~Writer() {
    if (file_) std::fclose(file_);
  }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  Writer& operator<<(const std::string& s) {
    if (std::fwrite(s.data(), 1, s.size(), file_) != s.size()) fail();
    return *this;
  }
  Writer& operator<<(const char* s) { return *this << std::string(s); }
  Writer& operator<<(long v) { return *this << std::to_string(v); }
  Writer& operator<<(int v) { return *this << std::to_string(v); }
  /// A float as 9 significant digits: read back as float, exactly the same value.
  void put(float v) {
    char text[32];
    const int n = std::snprintf(text, sizeof text, "%.9g", static_cast<double>(v));
    if (std::fwrite(text, 1, static_cast<std::size_t>(n), file_) != static_cast<std::size_t>(n)) fail();
  }
  /// "(x, y, z)"
  void put(const Eigen::Vector3f& p) {
    *this << "(";
    put(p.x());
    *this << ", ";
    put(p.y());
    *this << ", ";
    put(p.z());
    *this << ")";
  }
  /// "[(x, y, z), …]" of the columns of `x` listed in `order` (all columns if empty).
  void put_points(const Eigen::Matrix3Xf& x, const std::vector<int>& order) {
    *this << "[";
    const Eigen::Index n = order.empty() ? x.cols() : static_cast<Eigen::Index>(order.size());
    for (Eigen::Index i = 0; i < n; ++i) {
      if (i > 0) *this << ", ";
      put(Eigen::Vector3f(x.col(order.empty() ? i : order[static_cast<std::size_t>(i)])));
    }
    *this << "]";
  }
  /// "[a, b, …]"
  void put_ints(const std::vector<int>& v) {
    *this << "[";
    for (std::size_t i = 0; i < v.size(); ++i) *this << (i > 0 ? ", " : "") << std::to_string(v[i]);
    *this << "]";
  }
  /// Closes the file; throws if anything failed.
  void close() {
    const bool ok = std::fflush(file_) == 0 && !std::ferror(file_);
    const int closed = std::fclose(file_);
    file_ = nullptr;
    if (!ok || closed != 0) fail();
  }

 private:
  [[noreturn]] void fail() const { throw std::runtime_error(named_.string() + ": cannot write"); }
  fs::path named_;
  std::FILE* file_;
};

/// A USD matrix4d of a pose: row vectors, so row i is column i of the 4 × 4 matrix.
std::string matrix(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix4d m = pose.matrix();
  std::string s = "( ";
  for (int i = 0; i < 4; ++i) {
    s += i > 0 ? ", (" : "(";
    for (int j = 0; j < 4; ++j) s += (j > 0 ? ", " : "") + number(m(j, i));
    s += ")";
  }
  return s + " )";
}

std::string color(const Eigen::Vector3f& c) {
  return "[(" + number(c.x()) + ", " + number(c.y()) + ", " + number(c.z()) + ")]";
}

/// The strands of a mesh's segments (local vertex indices) as linear curves: a curve goes on
/// while a segment starts where the one before it ended. Returns the vertex counts and
/// fills `order` with the curves' vertices, one after the other.
std::vector<int> curves(const Eigen::Matrix2Xi& segments, std::vector<int>& order) {
  std::vector<int> counts;
  order.clear();
  for (Eigen::Index s = 0; s < segments.cols(); ++s) {
    if (s == 0 || segments(0, s) != segments(1, s - 1)) {
      counts.push_back(1);
      order.push_back(segments(0, s));
    }
    ++counts.back();
    order.push_back(segments(1, s));
  }
  return counts;
}

/// The time-sampled `points` and `extent` (padded by `pad`) of one prim: vertices
/// [first, first + count) of every recorded frame, in `order` (empty: as they are).
void put_samples(Writer& out, const FrameRecording& frames, int first, int count, const std::vector<int>& order,
                 float pad) {
  out << "        float3[] extent.timeSamples = {\n";
  frames.for_each(first, count, [&](int k, const Eigen::Matrix3Xf& x) {
    Eigen::Vector3f lo = Eigen::Vector3f::Zero(), hi = Eigen::Vector3f::Zero();
    const Eigen::Index n = order.empty() ? x.cols() : static_cast<Eigen::Index>(order.size());
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Vector3f p = x.col(order.empty() ? i : order[static_cast<std::size_t>(i)]);
      lo = i == 0 ? p : Eigen::Vector3f(lo.cwiseMin(p));
      hi = i == 0 ? p : Eigen::Vector3f(hi.cwiseMax(p));
    }
    out << "            " << frames.frames()[static_cast<std::size_t>(k)] << ": [";
    out.put(Eigen::Vector3f(lo.array() - pad));
    out << ", ";
    out.put(Eigen::Vector3f(hi.array() + pad));
    out << "],\n";
  });
  out << "        }\n";
  out << "        point3f[] points.timeSamples = {\n";
  frames.for_each(first, count, [&](int k, const Eigen::Matrix3Xf& x) {
    out << "            " << frames.frames()[static_cast<std::size_t>(k)] << ": ";
    out.put_points(x, order);
    out << ",\n";
  });
  out << "        }\n";
}

void put_obstacle(Writer& out, const Obstacle& o, const std::string& name, const FrameRecording& frames) {
  out << "        def Xform \"" << name << "\"\n        {\n";
  std::vector<Eigen::Isometry3d> poses;
  for (const double t : frames.times()) poses.push_back(o.pose(t));
  const bool moves = std::any_of(poses.begin(), poses.end(),
                                 [&](const Eigen::Isometry3d& p) { return p.matrix() != poses.front().matrix(); });
  if (moves) {
    out << "            matrix4d xformOp:transform.timeSamples = {\n";
    for (std::size_t k = 0; k < poses.size(); ++k)
      out << "                " << frames.frames()[k] << ": " << matrix(poses[k]) << ",\n";
    out << "            }\n";
  } else {
    out << "            matrix4d xformOp:transform = " << matrix(poses.front()) << "\n";
  }
  out << "            uniform token[] xformOpOrder = [\"xformOp:transform\"]\n\n";
  const std::string grey = "            color3f[] primvars:displayColor = " + color({0.62f, 0.62f, 0.66f}) + "\n";
  switch (o.kind) {
    case ShapeKind::sphere:
      out << "            def Sphere \"shape\"\n            {\n";
      out << "                double radius = " << number(o.radius) << "\n";
      break;
    case ShapeKind::box:
      out << "            def Cube \"shape\"\n            {\n";
      out << "                double size = 2\n";
      out << "                double3 xformOp:scale = (" << number(o.half_extents.x()) << ", "
          << number(o.half_extents.y()) << ", " << number(o.half_extents.z()) << ")\n";
      out << "                uniform token[] xformOpOrder = [\"xformOp:scale\"]\n";
      break;
    case ShapeKind::capsule:
      out << "            def Capsule \"shape\"\n            {\n";
      out << "                uniform token axis = \"Z\"\n";
      out << "                double height = " << number(2 * o.half_length) << "\n";
      out << "                double radius = " << number(o.radius) << "\n";
      break;
    case ShapeKind::mesh: {
      out << "            def Mesh \"shape\"\n            {\n";
      std::vector<int> counts(static_cast<std::size_t>(o.mesh.triangles.cols()), 3);
      std::vector<int> indices(o.mesh.triangles.data(), o.mesh.triangles.data() + o.mesh.triangles.size());
      out << "                int[] faceVertexCounts = ";
      out.put_ints(counts);
      out << "\n                int[] faceVertexIndices = ";
      out.put_ints(indices);
      out << "\n                point3f[] points = ";
      out.put_points(o.mesh.positions.cast<float>(), {});
      out << "\n                uniform token subdivisionScheme = \"none\"\n";
      break;
    }
  }
  out << "    " << grey << "            }\n        }\n";  // the shape's colour, then the ends of both prims
}

/// A mesh's triangles as a Mesh prim with time-sampled points.
void put_mesh(Writer& out, const Simulation& sim, const MeshRange& r, const FrameRecording& frames,
              const std::string& name, const std::string& colour) {
  out << "    def Mesh \"" << name << "\"\n    {\n";
  const Eigen::Matrix3Xi t =
      sim.model.triangles.middleCols(r.first_triangle, r.triangle_count).array() - r.first_vertex;
  out << "        uniform bool doubleSided = " << (r.tetrahedron_count > 0 ? "false" : "true") << "\n";
  put_samples(out, frames, r.first_vertex, r.vertex_count, {}, 0.0f);
  out << "        int[] faceVertexCounts = ";
  out.put_ints(std::vector<int>(static_cast<std::size_t>(t.cols()), 3));
  out << "\n        int[] faceVertexIndices = ";
  out.put_ints(std::vector<int>(t.data(), t.data() + t.size()));
  out << "\n        color3f[] primvars:displayColor = " << colour << "\n";
  out << "        uniform token subdivisionScheme = \"none\"\n    }\n\n";
}

/// A mesh's strand segments as a BasisCurves prim with time-sampled points.
void put_curves(Writer& out, const Simulation& sim, const MeshRange& r, const FrameRecording& frames,
                const std::string& name, const std::string& colour) {
  const Eigen::Matrix2Xi s = sim.model.segments.middleCols(r.first_segment, r.segment_count).array() - r.first_vertex;
  std::vector<int> order;
  const std::vector<int> counts = curves(s, order);
  // Width: a tenth of the mean rest segment length (the curves are drawn as tubes).
  double length = 0;
  for (Eigen::Index e = 0; e < s.cols(); ++e)
    length += (sim.model.rest.col(r.first_vertex + s(0, e)) - sim.model.rest.col(r.first_vertex + s(1, e))).norm();
  const float width = static_cast<float>(0.1 * length / static_cast<double>(s.cols()));
  bool identity = order.size() == static_cast<std::size_t>(r.vertex_count);
  for (std::size_t i = 0; identity && i < order.size(); ++i) identity = order[i] == static_cast<int>(i);
  out << "    def BasisCurves \"" << name << "\"\n    {\n";
  out << "        int[] curveVertexCounts = ";
  out.put_ints(counts);
  out << "\n";
  put_samples(out, frames, r.first_vertex, r.vertex_count, identity ? std::vector<int>{} : order, 0.5f * width);
  out << "        color3f[] primvars:displayColor = " << colour << "\n";
  out << "        uniform token type = \"linear\"\n";
  out << "        float[] widths = [";
  out.put(width);
  out << "] (\n            interpolation = \"constant\"\n        )\n";
  out << "        uniform token wrap = \"nonperiodic\"\n    }\n\n";
}

}  // namespace

void write_usda(const fs::path& path, const Scene& scene, const FrameRecording& frames) {
  if (frames.size() == 0) throw std::runtime_error(path.string() + ": no frame recorded");
  const Simulation& sim = scene.simulation;
  if (frames.vertex_count() != sim.model.vertex_count())
    throw std::invalid_argument("write_usda: the recording's vertex count is not the model's");
  if (path.has_parent_path()) ensure_directory(path.parent_path().string());
  fs::path temporary = path;
  temporary += ".tmp";
  try {
    Writer out(temporary, path);
    const std::string rate = number(1.0 / sim.solver.dt);
    std::string doc = "pce-sim: " + scene.file.filename().string() + ", frames " +
                      std::to_string(frames.frames().front()) + " to " + std::to_string(frames.frames().back());
    for (char& c : doc)
      if (c == '"' || c == '\\' || c == '\n') c = '_';
    out << "#usda 1.0\n(\n";
    out << "    defaultPrim = \"World\"\n";
    out << "    doc = \"" << doc << "\"\n";
    out << "    endTimeCode = " << frames.frames().back() << "\n";
    out << "    framesPerSecond = " << rate << "\n";
    out << "    metersPerUnit = 1\n";
    out << "    startTimeCode = " << frames.frames().front() << "\n";
    out << "    timeCodesPerSecond = " << rate << "\n";
    out << "    upAxis = \"Z\"\n)\n\n";
    out << "def Xform \"World\"\n{\n";
    std::set<std::string> used;
    if (!sim.obstacles.empty()) used.insert("obstacles");
    std::size_t k = 0;
    for (const MeshRange& r : sim.model.meshes) {
      const std::string base = usd_identifier(r.name), colour = color(mesh_color(k++));
      if (r.triangle_count > 0) put_mesh(out, sim, r, frames, unique_name(base, used), colour);
      if (r.segment_count > 0)
        put_curves(out, sim, r, frames, unique_name(r.triangle_count > 0 ? base + "_curves" : base, used), colour);
    }
    if (!sim.obstacles.empty()) {
      out << "    def Scope \"obstacles\"\n    {\n";
      std::set<std::string> names;
      for (const Obstacle& o : sim.obstacles) put_obstacle(out, o, unique_name(usd_identifier(o.name), names), frames);
      out << "    }\n";
    }
    out << "}\n";
    out.close();
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
  std::error_code error;
  fs::rename(temporary, path, error);
  if (error) {
    fs::remove(temporary, error);
    throw std::runtime_error(path.string() + ": cannot write (" + error.message() + ")");
  }
}

}  // namespace pce::sim

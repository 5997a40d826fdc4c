// SPDX-License-Identifier: MIT
// build_model (model.hpp): meshes concatenated into one model, masses lumped.
#include <pce/sim/input_error.hpp>
#include <pce/sim/model.hpp>

#include "util/names.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <set>
#include <sstream>
#include <string>

namespace pce::sim {

namespace {
void check_density(const std::string& field, double v) {
  if (!(std::isfinite(v) && v >= kMinDensity && v <= kMaxDensity)) {
    std::ostringstream s;
    s << "expected a number in [" << kMinDensity << ", " << kMaxDensity
      << "] (the densities pce::sim accepts, kg/m³, kg/m² or kg/m), got ";
    s.precision(17);
    s << v;
    throw ArgumentError(field, s.str());
  }
}
/// Adds mesh k's lumped masses (a volume's by its tetrahedra, a surface's by its triangles,
/// strands by their segments) to `mass` from vertex v0 on; throws ArgumentError for a vertex
/// left without mass.
void lump_masses(const ModelMesh& s, std::size_t k, int v0, Eigen::VectorXd& mass) {
  const int cv = static_cast<int>(s.mesh.vertex_count()), ct = static_cast<int>(s.mesh.triangles.cols()),
            cs = static_cast<int>(s.mesh.segments.cols()), cT = static_cast<int>(s.mesh.tetrahedra.cols());
  for (int t = 0; t < cT; ++t) {
    const auto tet = s.mesh.tetrahedra.col(t);
    const auto X = [&](int j) { return s.mesh.positions.col(tet[j]); };
    const double volume = (X(1) - X(0)).dot((X(2) - X(0)).cross(X(3) - X(0))) / 6.0;
    for (int j = 0; j < 4; ++j) mass[v0 + tet[j]] += s.density * volume / 4.0;
  }
  for (int t = 0; t < ct && cT == 0; ++t) {
    const auto tri = s.mesh.triangles.col(t);
    const double area = 0.5 * (s.mesh.positions.col(tri[1]) - s.mesh.positions.col(tri[0]))
                                  .cross(s.mesh.positions.col(tri[2]) - s.mesh.positions.col(tri[0]))
                                  .norm();
    for (int j = 0; j < 3; ++j) mass[v0 + tri[j]] += s.density * area / 3.0;
  }
  for (int e = 0; e < cs; ++e) {
    const auto seg = s.mesh.segments.col(e);
    const double len = (s.mesh.positions.col(seg[1]) - s.mesh.positions.col(seg[0])).norm();
    for (int j = 0; j < 2; ++j) mass[v0 + seg[j]] += s.linear_density * len / 2.0;
  }
  for (int i = 0; i < cv; ++i)
    if (!(mass[v0 + i] > 0))
      throw ArgumentError("meshes[" + std::to_string(k) + "]",
                          "vertex " + std::to_string(i) +
                              (cT > 0 ? " belongs to no tetrahedron (it would have no mass)"
                                      : " belongs to no triangle or segment of positive size (it would have no mass)"));
}

}  // namespace

Model build_model(const std::vector<ModelMesh>& meshes) {
  if (meshes.empty()) throw ArgumentError("meshes", "expected at least one mesh");
  std::set<std::string> names;
  int nv = 0, nt = 0, ns = 0, nT = 0;
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    const ModelMesh& s = meshes[k];
    const std::string at = "meshes[" + std::to_string(k) + "]";
    if (s.name.empty()) throw ArgumentError(at + ".name", "expected a non-empty name");
    if (!names.insert(s.name).second) throw ArgumentError(at + ".name", "duplicate mesh name \"" + s.name + "\"");
    try {
      validate(s.mesh, s.name);
    } catch (const InputError& e) {
      throw ArgumentError(at, e.what());
    }
    check_density(at + ".density", s.density);
    check_density(at + ".linear_density", s.linear_density);
    if (nv + s.mesh.vertex_count() > kMaxVertices)
      throw ArgumentError(at, "the model would have more than " + std::to_string(kMaxVertices) + " vertices");
    nv += static_cast<int>(s.mesh.vertex_count());
    nt += static_cast<int>(s.mesh.triangles.cols());
    ns += static_cast<int>(s.mesh.segments.cols());
    nT += static_cast<int>(s.mesh.tetrahedra.cols());
  }
  Model m;
  m.rest.resize(3, nv);
  m.triangles.resize(3, nt);
  m.segments.resize(2, ns);
  m.tetrahedra.resize(4, nT);
  m.mass = Eigen::VectorXd::Zero(nv);
  m.boundary_triangle.assign(static_cast<std::size_t>(nt), 0);
  m.surface_vertex.assign(static_cast<std::size_t>(nv), 0);
  int v0 = 0, t0 = 0, s0 = 0, T0 = 0;
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    const ModelMesh& s = meshes[k];
    const int cv = static_cast<int>(s.mesh.vertex_count()), ct = static_cast<int>(s.mesh.triangles.cols()),
              cs = static_cast<int>(s.mesh.segments.cols()), cT = static_cast<int>(s.mesh.tetrahedra.cols());
    m.meshes.push_back({s.name, v0, cv, t0, ct, s0, cs, T0, cT});
    m.rest.middleCols(v0, cv) = s.mesh.positions;
    m.triangles.middleCols(t0, ct) = s.mesh.triangles.array() + v0;
    m.segments.middleCols(s0, cs) = s.mesh.segments.array() + v0;
    m.tetrahedra.middleCols(T0, cT) = s.mesh.tetrahedra.array() + v0;
    for (int t = 0; t < ct; ++t)
      for (int j = 0; j < 3; ++j) m.surface_vertex[static_cast<std::size_t>(v0 + s.mesh.triangles(j, t))] = 1;
    for (int e = 0; e < cs; ++e)
      for (int j = 0; j < 2; ++j) m.surface_vertex[static_cast<std::size_t>(v0 + s.mesh.segments(j, e))] = 1;
    if (cT > 0) std::fill_n(m.boundary_triangle.begin() + t0, ct, char{1});
    lump_masses(s, k, v0, m.mass);
    v0 += cv;
    t0 += ct;
    s0 += cs;
    T0 += cT;
  }
  const Eigen::Matrix2Xi tri_edges = unique_edges(m.triangles);
  m.edges.resize(2, tri_edges.cols() + m.segments.cols());
  m.edges << tri_edges, m.segments;
  return m;
}

Model restrict_to_meshes(const Model& model, const std::vector<std::string>& meshes) {
  if (meshes.empty()) throw ArgumentError("meshes", "expected at least one mesh name");
  std::vector<char> keep(model.meshes.size(), 0);
  for (const std::string& name : meshes) {
    const MeshRange* r = find_named(model.meshes, name);
    if (!r)
      throw ArgumentError("meshes",
                          "unknown mesh \"" + name + "\" (the model's meshes: " + names_of(model.meshes, "") + ")");
    const std::size_t k = static_cast<std::size_t>(r - model.meshes.data());
    if (keep[k]) throw ArgumentError("meshes", "mesh \"" + name + "\" is named twice");
    keep[k] = 1;
  }
  Model v;
  v.rest = model.rest;
  v.mass = model.mass;
  v.surface_vertex = model.surface_vertex;
  if (v.surface_vertex.empty()) v.surface_vertex.assign(static_cast<std::size_t>(model.vertex_count()), 1);
  int nt = 0, ns = 0, nT = 0;
  for (std::size_t k = 0; k < model.meshes.size(); ++k)
    if (keep[k]) {
      nt += model.meshes[k].triangle_count;
      ns += model.meshes[k].segment_count;
      nT += model.meshes[k].tetrahedron_count;
    }
  v.triangles.resize(3, nt);
  v.segments.resize(2, ns);
  v.tetrahedra.resize(4, nT);
  const bool boundary = !model.boundary_triangle.empty();
  int t0 = 0, s0 = 0, T0 = 0;
  for (std::size_t k = 0; k < model.meshes.size(); ++k) {
    MeshRange r = model.meshes[k];
    if (keep[k]) {
      v.triangles.middleCols(t0, r.triangle_count) = model.triangles.middleCols(r.first_triangle, r.triangle_count);
      v.segments.middleCols(s0, r.segment_count) = model.segments.middleCols(r.first_segment, r.segment_count);
      v.tetrahedra.middleCols(T0, r.tetrahedron_count) =
          model.tetrahedra.middleCols(r.first_tetrahedron, r.tetrahedron_count);
      if (boundary)
        v.boundary_triangle.insert(v.boundary_triangle.end(), model.boundary_triangle.begin() + r.first_triangle,
                                   model.boundary_triangle.begin() + r.first_triangle + r.triangle_count);
    } else {
      r.triangle_count = r.segment_count = r.tetrahedron_count = 0;
      v.mass.segment(r.first_vertex, r.vertex_count).setZero();
      std::fill_n(v.surface_vertex.begin() + r.first_vertex, r.vertex_count, char{0});
    }
    r.first_triangle = t0;
    r.first_segment = s0;
    r.first_tetrahedron = T0;
    t0 += r.triangle_count;
    s0 += r.segment_count;
    T0 += r.tetrahedron_count;
    v.meshes.push_back(r);
  }
  const Eigen::Matrix2Xi tri_edges = unique_edges(v.triangles);
  v.edges.resize(2, tri_edges.cols() + v.segments.cols());
  v.edges << tri_edges, v.segments;
  return v;
}

RestAreas rest_areas(const Model& model) {
  RestAreas a;
  const auto nt = model.triangles.cols();
  a.vertex = Eigen::VectorXd::Zero(model.rest.cols());
  a.triangle = Eigen::VectorXd::Zero(nt);
  a.edge = Eigen::VectorXd::Zero(model.edges.cols());
  std::map<std::pair<int, int>, Eigen::Index> edge_of;
  for (Eigen::Index e = 0; e < model.edges.cols(); ++e)
    edge_of.emplace(std::minmax(model.edges(0, e), model.edges(1, e)), e);
  for (Eigen::Index t = 0; t < nt; ++t) {
    const auto tri = model.triangles.col(t);
    const double area =
        0.5 *
        (model.rest.col(tri[1]) - model.rest.col(tri[0])).cross(model.rest.col(tri[2]) - model.rest.col(tri[0])).norm();
    a.triangle[t] = area;
    for (int j = 0; j < 3; ++j) {
      a.vertex[tri[j]] += area / 3.0;
      const auto it = edge_of.find(std::minmax(tri[j], tri[(j + 1) % 3]));
      if (it != edge_of.end()) a.edge[it->second] += area / 3.0;
    }
  }
  return a;
}

}  // namespace pce::sim

// SPDX-License-Identifier: MIT
/// @file
/// The FCL broad phase: one `fcl::DynamicAABBTreeCollisionManager` per primitive kind
/// (vertices, triangles, edges), kept between queries. While the topology is unchanged a
/// query only rewrites the objects' boxes and refits the tree (`update()`); a new topology
/// (primitive count or indices) rebuilds it.
///
/// **Why the result is exactly `brute_force_candidates`'s.** The brute-force rule grows one
/// box by the full distance d; two boxes each grown by d/2 overlap under the same exact
/// comparison, but not after rounding. So FCL sees boxes grown by h = d/2 + pad, with
/// pad = 4 ε (M + d) (M the largest |coordinate|), large enough to absorb every rounding of
/// either test: every pair the brute force accepts overlaps in FCL (a superset). Each pair
/// FCL reports is then tested with the brute force's own expressions (`vertex_in_box`,
/// `edges_close`) — the same floating-point operations in the same order — which removes
/// the extra pairs; sorting gives the brute force's order. The bound: the brute force's
/// fl(lo − d) and FCL's fl(x − h), fl(hi + h) each err by at most ½ ulp(M + d) ≤ ε (M + d)/2,
/// so a margin of 2·pad = 8 ε (M + d) on the exact comparison covers all three.
///
/// FCL 0.7's `CollisionObject::aabb` is a protected member, and the manager reads boxes
/// only through `getAABB()`: a small subclass assigns it directly, so the shared
/// collision geometry (a zero box) never matters.
#include <pce/sim/broad_phase.hpp>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision_object.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace pce::sim {

namespace {

/// One primitive (vertex, triangle or edge) with a box we set ourselves.
class Primitive final : public fcl::CollisionObject<double> {
 public:
  Primitive(const std::shared_ptr<fcl::CollisionGeometry<double>>& geometry, int index)
      : fcl::CollisionObject<double>(geometry), index_(index) {}
  void set_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    aabb.min_ = lo;
    aabb.max_ = hi;
  }
  int index() const { return index_; }

 private:
  int index_;
};

/// A tree over one kind of primitive, refitted while the count stays the same.
class Tree {
 public:
  /// Creates `count` objects when the count differs from the last call (or `force`);
  /// returns true when it did (the caller must then set the boxes and call `build`).
  bool resize(int count, bool force) {
    if (!force && static_cast<int>(objects_.size()) == count && built_) return false;
    manager_ = std::make_unique<fcl::DynamicAABBTreeCollisionManager<double>>();
    objects_.clear();
    objects_.reserve(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) objects_.emplace_back(geometry(), i);
    built_ = false;
    return true;
  }
  Primitive& object(int i) { return objects_[static_cast<std::size_t>(i)]; }
  /// Registers the objects (first time) or refits the tree to their new boxes.
  void commit() {
    if (!built_) {
      std::vector<fcl::CollisionObject<double>*> pointers;
      pointers.reserve(objects_.size());
      for (Primitive& o : objects_) pointers.push_back(&o);
      manager_->registerObjects(pointers);
      manager_->setup();
      built_ = true;
    } else {
      manager_->update();
    }
  }
  fcl::DynamicAABBTreeCollisionManager<double>* manager() { return manager_.get(); }
  bool empty() const { return objects_.empty(); }

 private:
  static const std::shared_ptr<fcl::CollisionGeometry<double>>& geometry() {
    static const std::shared_ptr<fcl::CollisionGeometry<double>> g = [] {
      auto box = std::make_shared<fcl::Box<double>>(0.0, 0.0, 0.0);
      box->computeLocalAABB();
      return std::shared_ptr<fcl::CollisionGeometry<double>>(box);
    }();
    return g;
  }
  std::unique_ptr<fcl::DynamicAABBTreeCollisionManager<double>> manager_;
  std::vector<Primitive> objects_;  // never reallocated after registration (the manager keeps pointers)
  bool built_ = false;
};

/// The margin h − d/2 that makes FCL's overlap test accept every brute-force pair.
double padding(const Eigen::Matrix3Xd& x, double distance) {
  double m = 0;  // non-finite coordinates fail both tests alike and must not spoil the margin
  for (Eigen::Index k = 0; k < x.size(); ++k)
    if (std::isfinite(x.data()[k])) m = std::max(m, std::abs(x.data()[k]));
  return 4 * std::numeric_limits<double>::epsilon() * (m + distance);
}

/// The brute force's vertex-face test, same operations (`broad_phase/brute_force.cpp`).
bool vertex_in_box(const Eigen::Matrix3Xd& x, int v, const Eigen::Vector3i& tri, double distance) {
  const Eigen::Vector3d lo = x.col(tri[0]).cwiseMin(x.col(tri[1])).cwiseMin(x.col(tri[2])).array() - distance;
  const Eigen::Vector3d hi = x.col(tri[0]).cwiseMax(x.col(tri[1])).cwiseMax(x.col(tri[2])).array() + distance;
  return (x.col(v).array() >= lo.array()).all() && (x.col(v).array() <= hi.array()).all();
}

/// The brute force's edge-edge test, same operations.
bool edges_close(const Eigen::Matrix3Xd& x, int a0, int a1, int b0, int b1, double distance) {
  const Eigen::Vector3d alo = x.col(a0).cwiseMin(x.col(a1)), ahi = x.col(a0).cwiseMax(x.col(a1));
  const Eigen::Vector3d blo = x.col(b0).cwiseMin(x.col(b1)), bhi = x.col(b0).cwiseMax(x.col(b1));
  return ((blo - ahi).array() <= distance).all() && ((alo - bhi).array() <= distance).all();
}

/// Sorts pairs lexicographically: a counting sort on the first index (bounded by `n`),
/// then each bucket — a few dozen pairs — by the second. Linear in the pair count where
/// `std::sort` of a million pairs costs tens of milliseconds.
void sort_pairs(std::vector<std::array<int, 2>>& pairs, int n, std::vector<std::array<int, 2>>& scratch,
                std::vector<int>& start) {
  start.assign(static_cast<std::size_t>(n) + 1, 0);
  for (const auto& p : pairs) ++start[static_cast<std::size_t>(p[0]) + 1];
  for (int i = 0; i < n; ++i) start[static_cast<std::size_t>(i) + 1] += start[static_cast<std::size_t>(i)];
  scratch.resize(pairs.size());
  for (const auto& p : pairs) scratch[static_cast<std::size_t>(start[static_cast<std::size_t>(p[0])]++)] = p;
  // start[i] is now the end of bucket i (the beginning of bucket i + 1).
  auto first = scratch.begin();
  for (int i = 0; i < n; ++i) {
    const auto last = scratch.begin() + start[static_cast<std::size_t>(i)];
    if (last - first > 1) std::sort(first, last);
    first = last;
  }
  pairs.swap(scratch);
}

struct VertexFaceQuery {
  const Eigen::Matrix3Xd* x;
  const Eigen::Matrix3Xi* triangles;
  double distance;
  std::vector<std::array<int, 2>>* out;
};

struct EdgeEdgeQuery {
  const Eigen::Matrix3Xd* x;
  const Eigen::Matrix2Xi* edges;
  double distance;
  std::vector<std::array<int, 2>>* out;
};

/// Called for every (triangle, vertex) leaf pair whose grown boxes overlap.
bool vertex_face_pair(fcl::CollisionObject<double>* a, fcl::CollisionObject<double>* b, void* data) {
  const auto& q = *static_cast<VertexFaceQuery*>(data);
  const int t = static_cast<Primitive*>(a)->index(), v = static_cast<Primitive*>(b)->index();
  const Eigen::Vector3i tri = q.triangles->col(t);
  if (tri[0] == v || tri[1] == v || tri[2] == v) return false;
  if (vertex_in_box(*q.x, v, tri, q.distance)) q.out->push_back({v, t});
  return false;  // never stop early
}

/// Called once for every unordered pair of edges whose grown boxes overlap.
bool edge_edge_pair(fcl::CollisionObject<double>* a, fcl::CollisionObject<double>* b, void* data) {
  const auto& q = *static_cast<EdgeEdgeQuery*>(data);
  int i = static_cast<Primitive*>(a)->index(), j = static_cast<Primitive*>(b)->index();
  if (i > j) std::swap(i, j);
  const int a0 = (*q.edges)(0, i), a1 = (*q.edges)(1, i), b0 = (*q.edges)(0, j), b1 = (*q.edges)(1, j);
  if (a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1) return false;
  if (edges_close(*q.x, a0, a1, b0, b1, q.distance)) q.out->push_back({i, j});
  return false;
}

class FclBroadPhase final : public BroadPhase {
 public:
  void vertex_face(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles, double distance,
                   std::vector<std::array<int, 2>>& out) override {
    out.clear();
    if (x.cols() == 0 || triangles.cols() == 0) return;
    const bool new_topology = !same(triangles, vf_triangles_);
    if (new_topology) vf_triangles_ = triangles;
    const double h = distance / 2 + padding(x, distance);
    const int n = static_cast<int>(x.cols()), m = static_cast<int>(triangles.cols());
    vertices_.resize(n, new_topology);
    triangles_.resize(m, new_topology);
    for (int v = 0; v < n; ++v) vertices_.object(v).set_box(x.col(v).array() - h, x.col(v).array() + h);
    for (int t = 0; t < m; ++t) {
      const Eigen::Vector3d a = x.col(triangles(0, t)), b = x.col(triangles(1, t)), c = x.col(triangles(2, t));
      triangles_.object(t).set_box(a.cwiseMin(b).cwiseMin(c).array() - h, a.cwiseMax(b).cwiseMax(c).array() + h);
    }
    vertices_.commit();
    triangles_.commit();
    VertexFaceQuery q{&x, &triangles, distance, &out};
    triangles_.manager()->collide(vertices_.manager(), &q, vertex_face_pair);
    sort_pairs(out, n, scratch_, start_);
  }

  void edge_edge(const Eigen::Matrix3Xd& x, const Eigen::Matrix2Xi& edges, double distance,
                 std::vector<std::array<int, 2>>& out) override {
    out.clear();
    if (edges.cols() < 2) return;
    const bool new_topology = !same(edges, ee_edges_);
    if (new_topology) ee_edges_ = edges;
    const double h = distance / 2 + padding(x, distance);
    const int m = static_cast<int>(edges.cols());
    edges_.resize(m, new_topology);
    for (int e = 0; e < m; ++e) {
      const Eigen::Vector3d a = x.col(edges(0, e)), b = x.col(edges(1, e));
      edges_.object(e).set_box(a.cwiseMin(b).array() - h, a.cwiseMax(b).array() + h);
    }
    edges_.commit();
    EdgeEdgeQuery q{&x, &edges, distance, &out};
    edges_.manager()->collide(&q, edge_edge_pair);
    sort_pairs(out, m, scratch_, start_);
  }

 private:
  template <class M> static bool same(const M& a, const M& b) {
    return a.cols() == b.cols() && (a.array() == b.array()).all();
  }
  Eigen::Matrix3Xi vf_triangles_;
  Eigen::Matrix2Xi ee_edges_;
  Tree vertices_, triangles_, edges_;
  std::vector<std::array<int, 2>> scratch_;  // sort buffers, reused between queries
  std::vector<int> start_;
};

}  // namespace

std::unique_ptr<BroadPhase> make_fcl_broad_phase() { return std::make_unique<FclBroadPhase>(); }

}  // namespace pce::sim

// SPDX-License-Identifier: MIT
/// @file
/// The FCL broad phase: one `fcl::DynamicAABBTreeCollisionManager` per primitive kind
/// (vertices, triangles, edges), kept between queries. While the topology is unchanged a
/// query only rewrites the objects' boxes and refits the tree (`update()`); a new topology
/// (primitive count or indices) rebuilds it.
///
/// **Threads:** a query splits the traversal of the two trees (vertex-face) or of one tree
/// with itself (edge-edge) as FCL's recursion does, into 64 pieces per thread that partition
/// the leaf pairs, and the threads take pieces as they come free, each with its own list;
/// the lists are joined and sorted, so the result is the same for any thread count.
///
/// **Why the result is exactly `brute_force_candidates`'s:** FCL sees boxes grown by
/// h = d/2 + pad (a superset of the brute-force pairs whatever the rounding), each reported
/// pair is re-tested with the brute force's own expressions and the result is sorted — the
/// rule and its rounding bound are written once in `box_rule.hpp`, shared with Bullet.
/// Coordinates that are not all finite (FCL's tree crashes on a NaN or infinite box) are
/// answered by `brute_force_candidates` itself.
///
/// FCL 0.7's `CollisionObject::aabb` is a protected member, and the manager reads boxes
/// only through `getAABB()`: a small subclass assigns it directly, so the shared
/// collision geometry (a zero box) never matters.
#include <pce/sim/broad_phase.hpp>
#include <pce/sim/candidates.hpp>

#include "broad_phase/box_rule.hpp"

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision_object.h>

#include <omp.h>

#include <algorithm>
#include <memory>
#include <utility>
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

using Node = fcl::DynamicAABBTreeCollisionManager<double>::DynamicAABBNode;

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
  /// The tree's root (after commit; the manager keeps the tree, this only reads it).
  Node* root() const { return manager_->getTree().getRoot(); }
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

struct VertexFaceQuery {
  const Eigen::Matrix3Xd* x0;
  const Eigen::Matrix3Xd* x1;
  const Eigen::Matrix3Xi* triangles;
  double distance;
  std::vector<std::array<int, 2>>* out;
};

struct EdgeEdgeQuery {
  const Eigen::Matrix3Xd* x0;
  const Eigen::Matrix3Xd* x1;
  const Eigen::Matrix2Xi* edges;
  double distance;
  std::vector<std::array<int, 2>>* out;
};

/// Called for every (triangle, vertex) leaf pair whose grown boxes overlap.
bool vertex_face_pair(fcl::CollisionObject<double>* a, fcl::CollisionObject<double>* b, void* data) {
  const auto& q = *static_cast<VertexFaceQuery*>(data);
  const int t = static_cast<Primitive*>(a)->index(), v = static_cast<Primitive*>(b)->index();
  if (box_rule::accept_vertex_face(*q.x0, *q.x1, *q.triangles, v, t, q.distance)) q.out->push_back({v, t});
  return false;  // never stop early
}

/// Called once for every unordered pair of edges whose grown boxes overlap.
bool edge_edge_pair(fcl::CollisionObject<double>* a, fcl::CollisionObject<double>* b, void* data) {
  const auto& q = *static_cast<EdgeEdgeQuery*>(data);
  int i = static_cast<Primitive*>(a)->index(), j = static_cast<Primitive*>(b)->index();
  if (i > j) std::swap(i, j);
  if (box_rule::accept_edge_edge(*q.x0, *q.x1, *q.edges, i, j, q.distance)) q.out->push_back({i, j});
  return false;
}

/// One piece of a tree traversal: the leaf pairs of two subtrees (`b` set), or of one
/// subtree with itself (`b` null).
struct Task {
  Node* a;
  Node* b;
};

/// Splits a traversal (two trees, or one with itself) into at least `want` pieces (fewer
/// only when the leaves are reached), each split as FCL's own recursion splits it
/// (`collisionRecurse`, `selfCollisionRecurse`): the pieces partition the leaf pairs, so
/// each overlapping pair is visited exactly once, whichever piece and thread visits it.
std::vector<Task> split(Node* a, Node* b, std::size_t want) {
  std::vector<Task> tasks{{a, b}}, next;
  for (bool split_any = true; split_any && tasks.size() < want;) {
    split_any = false;
    next.clear();
    for (const Task& t : tasks) {
      if (t.b == nullptr) {  // self: both halves with themselves, and with each other
        if (t.a->isLeaf()) continue;
        next.push_back({t.a->children[0], nullptr});
        next.push_back({t.a->children[1], nullptr});
        next.push_back({t.a->children[0], t.a->children[1]});
        split_any = true;
      } else if (!t.a->bv.overlap(t.b->bv)) {
        continue;
      } else if (t.a->isLeaf() && t.b->isLeaf()) {
        next.push_back(t);
      } else if (t.b->isLeaf() || (!t.a->isLeaf() && t.a->bv.size() > t.b->bv.size())) {
        next.push_back({t.a->children[0], t.b});
        next.push_back({t.a->children[1], t.b});
        split_any = true;
      } else {
        next.push_back({t.a, t.b->children[0]});
        next.push_back({t.a, t.b->children[1]});
        split_any = true;
      }
    }
    tasks.swap(next);
  }
  return tasks;
}

/// Runs the pieces of a traversal on every thread (dynamic schedule), each thread
/// reporting through `callback` with its own copy of `query` (whose `out` it fills); the
/// threads' pairs are gathered into `out` (unsorted).
template <class Query> void traverse(const std::vector<Task>& tasks, const Query& query,
                                     fcl::CollisionCallBack<double> callback, std::vector<std::array<int, 2>>& out) {
  const int threads = omp_get_max_threads();
  std::vector<std::vector<std::array<int, 2>>> found(static_cast<std::size_t>(threads));
  const long count = static_cast<long>(tasks.size());
#pragma omp parallel if (threads > 1 && count > 1)
  {
    Query q = query;
    q.out = &found[static_cast<std::size_t>(omp_get_thread_num())];
#pragma omp for schedule(dynamic, 1)
    for (long k = 0; k < count; ++k) {
      const Task& t = tasks[static_cast<std::size_t>(k)];
      if (t.b == nullptr)
        fcl::detail::dynamic_AABB_tree::selfCollisionRecurse<double>(t.a, &q, callback);
      else
        fcl::detail::dynamic_AABB_tree::collisionRecurse<double>(t.a, t.b, &q, callback);
    }
  }
  for (const auto& f : found) out.insert(out.end(), f.begin(), f.end());
}

/// Enough pieces for the threads to share a traversal evenly (64 per thread).
std::size_t pieces() { return 64 * static_cast<std::size_t>(omp_get_max_threads()); }

class FclBroadPhase final : public BroadPhase {
 public:
  using BroadPhase::edge_edge;
  using BroadPhase::vertex_face;
  void vertex_face(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix3Xi& triangles,
                   double distance, std::vector<std::array<int, 2>>& out) override {
    out.clear();
    if (x0.cols() == 0 || triangles.cols() == 0) return;
    double h = 0;
    bool new_topology = false;
    if (!box_rule::begin_query(x0, x1, distance, triangles, vf_triangles_, h, new_topology)) {  // the reference
      out = brute_force_candidates(x0, x1, triangles, Eigen::Matrix2Xi(2, 0), distance).vertex_face;
      return;
    }
    const int n = static_cast<int>(x0.cols()), m = static_cast<int>(triangles.cols());
    vertices_.resize(n, new_topology);
    triangles_.resize(m, new_topology);
    Eigen::Vector3d lo, hi;
    for (int v = 0; v < n; ++v) {
      box_rule::vertex_box(x0, x1, v, h, lo, hi);
      vertices_.object(v).set_box(lo, hi);
    }
    for (int t = 0; t < m; ++t) {
      box_rule::triangle_box(x0, x1, triangles, t, h, lo, hi);
      triangles_.object(t).set_box(lo, hi);
    }
    vertices_.commit();
    triangles_.commit();
    const VertexFaceQuery q{&x0, &x1, &triangles, distance, nullptr};
    traverse(split(triangles_.root(), vertices_.root(), pieces()), q, vertex_face_pair, out);
    box_rule::sort_pairs(out, n, scratch_, start_);
  }

  void edge_edge(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix2Xi& edges, double distance,
                 std::vector<std::array<int, 2>>& out) override {
    out.clear();
    if (edges.cols() < 2) return;
    double h = 0;
    bool new_topology = false;
    if (!box_rule::begin_query(x0, x1, distance, edges, ee_edges_, h, new_topology)) {
      out = brute_force_candidates(x0, x1, Eigen::Matrix3Xi(3, 0), edges, distance).edge_edge;
      return;
    }
    const int m = static_cast<int>(edges.cols());
    edges_.resize(m, new_topology);
    Eigen::Vector3d lo, hi;
    for (int e = 0; e < m; ++e) {
      box_rule::edge_box(x0, x1, edges, e, h, lo, hi);
      edges_.object(e).set_box(lo, hi);
    }
    edges_.commit();
    const EdgeEdgeQuery q{&x0, &x1, &edges, distance, nullptr};
    traverse(split(edges_.root(), nullptr, pieces()), q, edge_edge_pair, out);
    box_rule::sort_pairs(out, m, scratch_, start_);
  }

 private:
  Eigen::Matrix3Xi vf_triangles_;
  Eigen::Matrix2Xi ee_edges_;
  Tree vertices_, triangles_, edges_;
  std::vector<std::array<int, 2>> scratch_;  // sort buffers, reused between queries
  std::vector<int> start_;
};

}  // namespace

std::unique_ptr<BroadPhase> make_fcl_broad_phase() { return std::make_unique<FclBroadPhase>(); }

}  // namespace pce::sim

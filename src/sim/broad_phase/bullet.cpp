// SPDX-License-Identifier: MIT
/// @file
/// The Bullet broad phase: one `btDbvt` (Bullet's dynamic bounding-volume tree of boxes) per
/// primitive kind (vertices, triangles, edges), kept between queries. Vertex-face pairs come
/// from `collideTT(triangles, vertices)`, edge-edge pairs from the edge tree against itself
/// (`collideTT(root, root)` visits every unordered leaf pair once).
///
/// **Keeping the tree.** A new topology (a different primitive count, or different
/// triangle or edge indices) rebuilds the tree: every leaf is inserted (in a shuffled
/// order), then `optimizeTopDown` rebuilds the hierarchy top-down. While the topology is
/// unchanged a query *refits*: it writes the leaves' new boxes and recomputes every
/// internal box from its two children, children before parents (an order recorded at the
/// rebuild), keeping the hierarchy as built — as FCL's broad phase does. The alternative
/// Bullet offers, `btDbvt::update(leaf, volume)` for every leaf (remove and reinsert, with
/// or without `optimizeIncremental`), made a whole query (both kinds) about 1.6× slower
/// on crumpled 200 × 200 cloths moved by up to 0.05 spacing (≈ 240 ms against ≈ 150 ms,
/// pce-broad-phase-bench), for no faster traversal.
///
/// **Why the result is exactly `brute_force_candidates`'s:** the tree holds boxes grown by
/// h = d/2 + pad (a superset of the brute-force pairs whatever the rounding), each reported
/// pair is re-tested with the brute force's own expressions and the result is sorted — the
/// rule and its rounding bound are in `box_rule.hpp`, shared with FCL. Coordinates that
/// are not all finite are answered by `brute_force_candidates` (`box_rule::padding`).
///
/// Built in double precision (`BT_USE_DOUBLE_PRECISION`, Debian's `bullet-float64`): the
/// tree compares the same doubles the rounding bound is about.
#include <pce/sim/broad_phase.hpp>
#include <pce/sim/candidates.hpp>

#include "broad_phase/box_rule.hpp"

#include <BulletCollision/BroadphaseCollision/btDbvt.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <random>
#include <utility>
#include <vector>

namespace pce::sim {

namespace {

/// A leaf's primitive index, kept in `btDbvtNode::data`.
void* as_data(int index) { return reinterpret_cast<void*>(static_cast<std::intptr_t>(index)); }
int index_of(const btDbvtNode* leaf) { return static_cast<int>(reinterpret_cast<std::intptr_t>(leaf->data)); }

/// The tree's volume for [lo, hi].
btDbvtVolume volume(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return btDbvtVolume::FromMM(btVector3(lo.x(), lo.y(), lo.z()), btVector3(hi.x(), hi.y(), hi.z()));
}

/// A `btDbvt` over one kind of primitive whose leaf i holds primitive i.
class Tree {
 public:
  /// Gives leaf i the box `box(i, lo, hi)` writes, for i < count: rebuilds the tree when
  /// `rebuild` or the count changed, refits it otherwise.
  template <class Box> void set(int count, bool rebuild, const Box& box) {
    Eigen::Vector3d lo, hi;
    if (rebuild || count != static_cast<int>(leaves_.size())) {
      tree_.clear();
      leaves_.resize(static_cast<std::size_t>(count));
      // Insert in a shuffled order: `insert` descends from the root, and leaves inserted
      // in mesh order (spatially sorted) make a deep, list-like tree whose insertion is
      // quadratic (n = 140: 0.6 s against 0.15 s shuffled).
      order_.resize(static_cast<std::size_t>(count));
      for (int i = 0; i < count; ++i) order_[static_cast<std::size_t>(i)] = i;
      std::shuffle(order_.begin(), order_.end(), std::mt19937(12345));
      for (int i : order_) {
        box(i, lo, hi);
        leaves_[static_cast<std::size_t>(i)] = tree_.insert(volume(lo, hi), as_data(i));
      }
      // Then a top-down rebuild of the hierarchy, split to single leaves (bu_treshold 2:
      // Bullet's default 128 finishes each group of ≤ 128 leaves bottom-up, cubic in the
      // group, 1.3 s at n = 140).
      tree_.optimizeTopDown(2);
      record_internal_order();
      return;
    }
    for (int i = 0; i < count; ++i) {
      box(i, lo, hi);
      leaves_[static_cast<std::size_t>(i)]->volume = volume(lo, hi);
    }
    for (auto it = internal_.rbegin(); it != internal_.rend(); ++it)
      Merge((*it)->childs[0]->volume, (*it)->childs[1]->volume, (*it)->volume);
  }
  btDbvt& tree() { return tree_; }
  const btDbvtNode* root() const { return tree_.m_root; }

 private:
  /// Internal nodes, parents before children (a refit walks it backwards).
  void record_internal_order() {
    internal_.clear();
    if (tree_.m_root && tree_.m_root->isinternal()) internal_.push_back(tree_.m_root);
    for (std::size_t k = 0; k < internal_.size(); ++k)
      for (btDbvtNode* child : internal_[k]->childs)
        if (child->isinternal()) internal_.push_back(child);
  }
  btDbvt tree_;
  std::vector<btDbvtNode*> leaves_;    // leaf i holds primitive i
  std::vector<btDbvtNode*> internal_;  // breadth first from the root
  std::vector<int> order_;             // insertion order at a rebuild
};

/// Receives every (triangle leaf, vertex leaf) pair whose boxes overlap.
class VertexFacePairs final : public btDbvt::ICollide {
 public:
  VertexFacePairs(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix3Xi& triangles,
                  double distance, std::vector<std::array<int, 2>>& out)
      : x0_(x0), x1_(x1), triangles_(triangles), distance_(distance), out_(out) {}
  using btDbvt::ICollide::Process;
  void Process(const btDbvtNode* triangle, const btDbvtNode* vertex) override {
    const int t = index_of(triangle), v = index_of(vertex);
    if (box_rule::accept_vertex_face(x0_, x1_, triangles_, v, t, distance_)) out_.push_back({v, t});
  }

 private:
  const Eigen::Matrix3Xd& x0_;
  const Eigen::Matrix3Xd& x1_;
  const Eigen::Matrix3Xi& triangles_;
  double distance_;
  std::vector<std::array<int, 2>>& out_;
};

/// Receives every unordered pair of distinct edge leaves whose boxes overlap.
class EdgeEdgePairs final : public btDbvt::ICollide {
 public:
  EdgeEdgePairs(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix2Xi& edges, double distance,
                std::vector<std::array<int, 2>>& out)
      : x0_(x0), x1_(x1), edges_(edges), distance_(distance), out_(out) {}
  using btDbvt::ICollide::Process;
  void Process(const btDbvtNode* a, const btDbvtNode* b) override {
    int i = index_of(a), j = index_of(b);
    if (i > j) std::swap(i, j);
    if (box_rule::accept_edge_edge(x0_, x1_, edges_, i, j, distance_)) out_.push_back({i, j});
  }

 private:
  const Eigen::Matrix3Xd& x0_;
  const Eigen::Matrix3Xd& x1_;
  const Eigen::Matrix2Xi& edges_;
  double distance_;
  std::vector<std::array<int, 2>>& out_;
};

class BulletBroadPhase final : public BroadPhase {
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
    vertices_.set(n, false,
                  [&](int v, Eigen::Vector3d& lo, Eigen::Vector3d& hi) { box_rule::vertex_box(x0, x1, v, h, lo, hi); });
    triangles_.set(m, new_topology, [&](int t, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
      box_rule::triangle_box(x0, x1, triangles, t, h, lo, hi);
    });
    VertexFacePairs pairs(x0, x1, triangles, distance, out);
    triangles_.tree().collideTTpersistentStack(triangles_.root(), vertices_.root(), pairs);
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
    edges_.set(m, new_topology, [&](int e, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
      box_rule::edge_box(x0, x1, edges, e, h, lo, hi);
    });
    EdgeEdgePairs pairs(x0, x1, edges, distance, out);
    edges_.tree().collideTTpersistentStack(edges_.root(), edges_.root(), pairs);
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

std::unique_ptr<BroadPhase> make_bullet_broad_phase() { return std::make_unique<BulletBroadPhase>(); }

}  // namespace pce::sim

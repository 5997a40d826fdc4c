// SPDX-License-Identifier: MIT
// pce::sim broad phases (src/sim/broad_phase/fcl.cpp, bullet.cpp): FCL's dynamic AABB tree
// and Bullet's btDbvt each return exactly the brute-force reference's vectors (same pairs,
// same order) for vertex-face and edge-edge on crumpled cloths, overlapping sheets,
// strands, flat grids whose pairs sit exactly on the box boundary, after the vertices move
// (refit), after the topology changes (rebuild), with a non-finite vertex, and on the
// initial state of every shipped scene (examples/scenes/*.json), and over sweeps between two
// states (boxes over both; a sweep to the same state is the one-state query bit for bit).
// Every test body runs for both kinds (TEST_P over fcl and bullet). SweptCandidatesCover
// checks the guarantee a contact effect builds on: a pair that is not a candidate of the
// sweep x0 → x1 with distance d + m stays more than d apart at every state whose vertices
// lie within m/2 of their swept boxes on every axis.
//
// DISABLED_Timing (run with --gtest_also_run_disabled_tests --gtest_filter=*Timing*) prints
// the query times of each kind and of the brute force on a crumpled 100×100 cloth; it
// asserts nothing about speed. The full comparison is the pce-broad-phase-bench program.
#include <pce/energy/closest_feature.hpp>
#include <pce/penalties/quadratic.hpp>
#include <pce/sim/broad_phase.hpp>
#include <pce/sim/candidates.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/scene.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <ostream>
#include <limits>
#include <random>
#include <set>

namespace pce::sim {
/// gtest prints a kind by its name ("fcl", "bullet") in failure messages.
inline void PrintTo(BroadPhaseKind kind, std::ostream* os) { *os << to_string(kind); }
}  // namespace pce::sim

namespace {

using Pairs = std::vector<std::array<int, 2>>;

using pce::sim::BroadPhaseKind;

pce::sim::Mesh crumpled(int n, unsigned seed, double fold = 0.05, double jitter = 0.4) {
  return pce::sim::crumpled_grid(n, seed, fold, jitter);
}

Pairs brute_vf(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& t, double d) {
  return pce::sim::brute_force_candidates(x, t, Eigen::Matrix2Xi(2, 0), d).vertex_face;
}
Pairs brute_ee(const Eigen::Matrix3Xd& x, const Eigen::Matrix2Xi& e, double d) {
  return pce::sim::brute_force_candidates(x, Eigen::Matrix3Xi(3, 0), e, d).edge_edge;
}

/// Runs both queries on `bp` and compares the vectors exactly; returns the pair counts.
std::array<std::size_t, 2> expect_same(pce::sim::BroadPhase& bp, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& t,
                                       const Eigen::Matrix2Xi& e, double d, const std::string& what) {
  Pairs vf, ee;
  bp.vertex_face(x, t, d, vf);
  bp.edge_edge(x, e, d, ee);
  const Pairs bvf = brute_vf(x, t, d), bee = brute_ee(x, e, d);
  EXPECT_EQ(vf.size(), bvf.size()) << what << ", vertex-face, distance " << d;
  EXPECT_TRUE(vf == bvf) << what << ", vertex-face, distance " << d;
  EXPECT_EQ(ee.size(), bee.size()) << what << ", edge-edge, distance " << d;
  EXPECT_TRUE(ee == bee) << what << ", edge-edge, distance " << d;
  return {bvf.size(), bee.size()};
}

/// Every test body below runs once per tree-based kind.
class TreeBroadPhase : public ::testing::TestWithParam<BroadPhaseKind> {
 protected:
  std::unique_ptr<pce::sim::BroadPhase> make() const { return pce::sim::make_broad_phase(GetParam()); }
};

TEST_P(TreeBroadPhase, CrumpledClothEqualsBruteForce) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const pce::sim::Mesh m = crumpled(20, seed);
    const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
    auto bp = make();
    for (double d : {0.0, 0.005, 0.02, 0.08}) {
      const auto counts = expect_same(*bp, m.positions, m.triangles, edges, d, "crumpled seed " + std::to_string(seed));
      EXPECT_GT(counts[0], 0u);
      EXPECT_GT(counts[1], 0u);
    }
  }
}

TEST_P(TreeBroadPhase, TwoOverlappingSheets) {
  // A second sheet 0.004 above the first, rotated by 30° and shifted, both crumpled a little.
  const pce::sim::Mesh a = crumpled(15, 7, 0.0, 0.1), b0 = crumpled(12, 8, 0.0, 0.1);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pce::sim::Mesh both;
  const Eigen::Index na = a.vertex_count(), nb = b0.vertex_count();
  both.positions.resize(3, na + nb);
  both.positions.leftCols(na) = a.positions;
  for (Eigen::Index v = 0; v < nb; ++v)
    both.positions.col(na + v) = R * b0.positions.col(v) + Eigen::Vector3d(0.2, 0.1, 0.004);
  both.triangles.resize(3, a.triangles.cols() + b0.triangles.cols());
  both.triangles << a.triangles, (b0.triangles.array() + static_cast<int>(na)).matrix();
  const Eigen::Matrix2Xi edges = pce::sim::unique_edges(both.triangles);
  auto bp = make();
  for (double d : {0.0, 0.002, 0.01}) {
    const auto counts = expect_same(*bp, both.positions, both.triangles, edges, d, "two sheets");
    EXPECT_GT(counts[0], 0u);
  }
}

TEST_P(TreeBroadPhase, StrandsEdgeEdge) {
  const pce::sim::Mesh m = pce::sim::strands(25, 30, 1.0, 0.02, 0.012);
  auto bp = make();
  for (double d : {0.0, 0.003, 0.01, 0.03}) {
    Pairs ee;
    bp->edge_edge(m.positions, m.segments, d, ee);
    const Pairs bee = brute_ee(m.positions, m.segments, d);
    EXPECT_TRUE(ee == bee) << "strands, distance " << d << ": " << ee.size() << " vs " << bee.size();
    EXPECT_GT(bee.size(), 0u);
  }
}

TEST_P(TreeBroadPhase, FlatGridPairsExactlyOnTheBoundary) {
  // Grid coordinates (i/n − ½)·w are not exact binary fractions, and the distances equal
  // the spacing: many pairs sit on the brute force's `<=` boundary up to one rounding.
  for (int n : {7, 10, 13}) {
    const pce::sim::Mesh m = pce::sim::grid(1.3, 0.7, n, n + 2);
    const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
    auto bp = make();
    for (double d : {0.0, 1.3 / n, 0.7 / (n + 2), 2 * 1.3 / n, 0.1})
      expect_same(*bp, m.positions, m.triangles, edges, d, "flat grid " + std::to_string(n));
  }
}

TEST_P(TreeBroadPhase, RefitAfterTheVerticesMove) {
  pce::sim::Mesh m = crumpled(16, 11);
  const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
  auto bp = make();
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int step = 0; step < 5; ++step) {
    expect_same(*bp, m.positions, m.triangles, edges, 0.015, "refit step " + std::to_string(step));
    // Large moves, so the old tree's boxes are far from right: a missing refit would show.
    for (Eigen::Index v = 0; v < m.vertex_count(); ++v)
      m.positions.col(v) += Eigen::Vector3d(0.03 * u(rng), 0.03 * u(rng), 0.1 * u(rng));
  }
}

TEST_P(TreeBroadPhase, RebuildAfterTheTopologyChanges) {
  auto bp = make();
  // Different sizes: 12×12, then 9×14, then back.
  for (int k = 0; k < 3; ++k) {
    const pce::sim::Mesh m = k == 1 ? crumpled(9, 20 + k) : crumpled(12, 20 + k);
    expect_same(*bp, m.positions, m.triangles, pce::sim::unique_edges(m.triangles), 0.02,
                "size change " + std::to_string(k));
  }
  // Same counts, different indices: the triangles and edges of one cloth reversed in
  // order and the vertex numbering mirrored.
  pce::sim::Mesh m = crumpled(12, 30);
  const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
  expect_same(*bp, m.positions, m.triangles, edges, 0.02, "before renumbering");
  const int n = static_cast<int>(m.vertex_count());
  Eigen::Matrix3Xd mirrored = m.positions.rowwise().reverse();
  Eigen::Matrix3Xi tris = (n - 1 - m.triangles.rowwise().reverse().array()).matrix();
  Eigen::Matrix2Xi redges = (n - 1 - edges.rowwise().reverse().array()).matrix();
  expect_same(*bp, mirrored, tris, redges, 0.02, "after renumbering");
  // And a strand set through the same object (edges only, no triangles).
  const pce::sim::Mesh s = pce::sim::strands(9, 12, 0.5, 0.03, 0.02);
  expect_same(*bp, s.positions, Eigen::Matrix3Xi(3, 0), s.segments, 0.01, "strands after cloth");
}

TEST_P(TreeBroadPhase, DegenerateInputs) {
  auto bp = make();
  const pce::sim::Mesh m = pce::sim::grid(1, 1, 1, 1);  // 4 vertices, 2 triangles sharing an edge
  expect_same(*bp, m.positions, m.triangles, pce::sim::unique_edges(m.triangles), 0.1, "one quad");
  Pairs out{{1, 2}};
  bp->vertex_face(m.positions, Eigen::Matrix3Xi(3, 0), 1.0, out);
  EXPECT_TRUE(out.empty());
  out = {{1, 2}};
  bp->edge_edge(m.positions, Eigen::Matrix2Xi(2, 0), 1.0, out);
  EXPECT_TRUE(out.empty());
}

TEST_P(TreeBroadPhase, NonFiniteVertex) {
  // One vertex NaN, one at +inf: neither tree survives such boxes, so the query falls back
  // to the brute force (box_rule::padding), and the next finite query uses the tree again.
  pce::sim::Mesh m = crumpled(10, 40);
  const pce::sim::Mesh finite = m;
  const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
  m.positions(2, 17) = std::numeric_limits<double>::quiet_NaN();
  m.positions(0, 60) = std::numeric_limits<double>::infinity();
  auto bp = make();
  for (double d : {0.0, 0.02}) {
    const auto counts = expect_same(*bp, m.positions, m.triangles, edges, d, "non-finite vertex");
    EXPECT_GT(counts[0], 0u);
    expect_same(*bp, finite.positions, m.triangles, edges, d, "finite again");
  }
}

TEST_P(TreeBroadPhase, HugeOrInvalidDistance) {
  // A query distance of 1e308 grew the boxes to ±inf (h = d/2 + 4ε(M + d)), whose NaN
  // volumes crashed FCL's tree build (a segmentation fault from pce-sim with a contact
  // distance of 1e308). Beyond box_rule::kTreeLimit, and for a NaN or negative distance,
  // the query is answered by the brute force: every pair within a huge distance, none for
  // NaN. The next ordinary query uses the tree again.
  const pce::sim::Mesh m = crumpled(6, 3);
  const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
  auto bp = make();
  const std::size_t all_vf =
      static_cast<std::size_t>(m.positions.cols()) * static_cast<std::size_t>(m.triangles.cols());
  for (double d : {1e308, std::numeric_limits<double>::max(), std::numeric_limits<double>::infinity(), 1e200, 1e101}) {
    const auto counts = expect_same(*bp, m.positions, m.triangles, edges, d, "huge distance");
    EXPECT_EQ(counts[0], all_vf - 3 * static_cast<std::size_t>(m.triangles.cols())) << d;  // all but the corners
    expect_same(*bp, m.positions, m.triangles, edges, 0.02, "ordinary distance again");
  }
  for (double d : {std::numeric_limits<double>::quiet_NaN(), -1.0}) {
    expect_same(*bp, m.positions, m.triangles, edges, d, "NaN or negative distance");
    expect_same(*bp, m.positions, m.triangles, edges, 0.02, "ordinary distance again");
  }
  // Coordinates near the limit with an ordinary distance: also the brute force's answer.
  const Eigen::Matrix3Xd far = (m.positions.array() * 1e99).matrix();
  expect_same(*bp, far, m.triangles, edges, 1e98, "coordinates of 1e99");
}

/// The self-contact distances a scene's `self_vertex_face` / `self_edge_edge` effects declare.
std::set<double> self_contact_distances(const std::filesystem::path& file) {
  std::ifstream in(file);
  const nlohmann::json j = nlohmann::json::parse(in);
  std::set<double> d;
  for (const auto& e : j.value("effects", nlohmann::json::array()))
    if (e.value("type", "").rfind("self_", 0) == 0 && e.contains("penalty"))
      d.insert(e["penalty"].value("distance", 0.0));
  return d;
}

TEST(BroadPhases, ShippedScenesInitialStateAllKindsAgree) {
  // For every shipped scene: its initial positions, triangles and edges, queried by FCL,
  // Bullet and the brute force at 0, each self-contact distance d, the query radius 2d
  // (distance + margin, docs/simulation.md §4.2) and 0.05: identical vectors.
  const std::filesystem::path dir = std::filesystem::path(PCE_SOURCE_DIR) / "examples" / "scenes";
  std::set<std::string> seen;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const auto scene = pce::sim::load_scene(entry.path());
    const pce::sim::Simulation& sim = scene->simulation;
    seen.insert(entry.path().stem().string());
    if (sim.model.vertex_count() > 20000) continue;  // the brute force is quadratic (drop_130k)
    std::set<double> distances{0.0, 0.05};
    for (double d : self_contact_distances(entry.path())) distances.insert({d, 2 * d});
    auto fcl = pce::sim::make_broad_phase(BroadPhaseKind::fcl);
    auto bullet = pce::sim::make_broad_phase(BroadPhaseKind::bullet);
    std::size_t total = 0;
    for (double d : distances) {
      const std::string what = entry.path().filename().string() + ", distance " + std::to_string(d);
      const Pairs bvf = brute_vf(sim.x, sim.model.triangles, d), bee = brute_ee(sim.x, sim.model.edges, d);
      for (auto* bp : {fcl.get(), bullet.get()}) {
        Pairs vf, ee;
        bp->vertex_face(sim.x, sim.model.triangles, d, vf);
        bp->edge_edge(sim.x, sim.model.edges, d, ee);
        EXPECT_TRUE(vf == bvf) << what << ", vertex-face, " << (bp == fcl.get() ? "fcl" : "bullet") << ": " << vf.size()
                               << " vs " << bvf.size();
        EXPECT_TRUE(ee == bee) << what << ", edge-edge, " << (bp == fcl.get() ? "fcl" : "bullet") << ": " << ee.size()
                               << " vs " << bee.size();
      }
      total += bvf.size() + bee.size();
    }
    EXPECT_GT(total, 0u);
  }
  for (const char* name : {"hammock", "drape", "strands", "twist"}) EXPECT_EQ(seen.count(name), 1u) << name;
}

TEST(BroadPhases, NamesAndSceneKey) {
  for (BroadPhaseKind k : {BroadPhaseKind::fcl, BroadPhaseKind::bullet, BroadPhaseKind::brute})
    EXPECT_EQ(pce::sim::broad_phase_kind(pce::sim::to_string(k)), k);
  EXPECT_STREQ(pce::sim::to_string(BroadPhaseKind::bullet), "bullet");
  EXPECT_FALSE(pce::sim::broad_phase_kind("bvh").has_value());
  // `solver.broad_phase: "bullet"` loads; an unknown name is an error listing all three.
  nlohmann::json j = nlohmann::json::parse(R"({
    "dt": 0.025, "frames": 1,
    "meshes": [{"name": "cloth", "generator": {"type": "grid", "width": 1, "height": 1, "nx": 4, "ny": 4}}],
    "effects": [{"type": "gravity"}], "solver": {"broad_phase": "bullet"}
  })");
  EXPECT_NO_THROW(pce::sim::load_scene_text(j.dump(), "scene.json", PCE_TEST_TMP));
  j["solver"]["broad_phase"] = "bvh";
  try {
    pce::sim::load_scene_text(j.dump(), "scene.json", PCE_TEST_TMP);
    ADD_FAILURE() << "an unknown broad phase loaded";
  } catch (const pce::sim::InputError& e) {
    EXPECT_EQ(e.where(), "solver.broad_phase");
    EXPECT_NE(std::string(e.what()).find(R"("fcl", "bullet", "brute")"), std::string::npos) << e.what();
  }
}

TEST(BroadPhases, CrumpledGridIsReproducible) {
  // The generator the tests and pce-broad-phase-bench share: same seed, same cloth.
  const pce::sim::Mesh a = pce::sim::crumpled_grid(8, 3), b = pce::sim::crumpled_grid(8, 3);
  const pce::sim::Mesh c = pce::sim::crumpled_grid(8, 4), flat = pce::sim::grid(1, 1, 8, 8);
  EXPECT_TRUE((a.positions.array() == b.positions.array()).all());
  EXPECT_FALSE((a.positions.array() == c.positions.array()).all());
  EXPECT_TRUE((a.triangles.array() == flat.triangles.array()).all());
  EXPECT_LE((a.positions - flat.positions).topRows(2).cwiseAbs().maxCoeff(), 0.4 / 8);
  EXPECT_THROW(pce::sim::crumpled_grid(8, 3, -1.0), pce::sim::InputError);
}

double milliseconds(const std::function<void()>& f, int repeat) {
  const auto t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < repeat; ++r) f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeat;
}

TEST_P(TreeBroadPhase, DISABLED_Timing) {
  const pce::sim::Mesh m = crumpled(100, 5);
  const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
  const double d = 0.02;  // 2% of the 1 m sheet
  auto bp = make();
  const char* kind = pce::sim::to_string(GetParam());
  Pairs vf, ee;
  const double first_vf = milliseconds([&] { bp->vertex_face(m.positions, m.triangles, d, vf); }, 1);
  const double first_ee = milliseconds([&] { bp->edge_edge(m.positions, edges, d, ee); }, 1);
  // Refit path: move every vertex a little between queries, as a time step would.
  Eigen::Matrix3Xd x = m.positions;
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  const double refit_vf = milliseconds(
      [&] {
        x = x.unaryExpr([&](double c) { return c + u(rng); });
        bp->vertex_face(x, m.triangles, d, vf);
      },
      5);
  const double refit_ee = milliseconds([&] { bp->edge_edge(x, edges, d, ee); }, 5);
  Pairs bvf, bee;
  const double brute_vf_ms = milliseconds([&] { bvf = brute_vf(x, m.triangles, d); }, 1);
  const double brute_ee_ms = milliseconds([&] { bee = brute_ee(x, edges, d); }, 1);
  EXPECT_TRUE(vf == bvf);
  EXPECT_TRUE(ee == bee);
  std::printf("crumpled 100x100 cloth: %td vertices, %td triangles, %td edges, distance %g\n", m.vertex_count(),
              m.triangles.cols(), edges.cols(), d);
  std::printf("vertex-face: %zu pairs; %s first (build) %.1f ms, refit %.1f ms, brute force %.1f ms\n", bvf.size(),
              kind, first_vf, refit_vf, brute_vf_ms);
  std::printf("edge-edge:   %zu pairs; %s first (build) %.1f ms, refit %.1f ms, brute force %.1f ms\n", bee.size(),
              kind, first_ee, refit_ee, brute_ee_ms);
}

/// A crumpled cloth and a second state: every vertex moved by a smooth field (a fall, a
/// shear and a wave), so primitives sweep across each other.
Eigen::Matrix3Xd moved(const Eigen::Matrix3Xd& x, double amount) {
  Eigen::Matrix3Xd y = x;
  for (Eigen::Index v = 0; v < x.cols(); ++v) {
    const Eigen::Vector3d p = x.col(v);
    y.col(v) += amount * Eigen::Vector3d(0.3 * p.y(), std::sin(7 * p.x()), -1.0 + std::cos(5 * p.y()));
  }
  return y;
}

TEST_P(TreeBroadPhase, SweepEqualsBruteForceAndSameStateIsTheOneStateQuery) {
  const pce::sim::Mesh m = crumpled(18, 4);
  const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
  auto bp = make();
  for (double amount : {0.0, 0.01, 0.05})
    for (double d : {0.0, 0.01, 0.04}) {
      const Eigen::Matrix3Xd x1 = moved(m.positions, amount);
      Pairs vf, ee;
      bp->vertex_face(m.positions, x1, m.triangles, d, vf);
      bp->edge_edge(m.positions, x1, edges, d, ee);
      const pce::sim::Candidates b = pce::sim::brute_force_candidates(m.positions, x1, m.triangles, edges, d);
      EXPECT_TRUE(vf == b.vertex_face) << "sweep " << amount << ", distance " << d;
      EXPECT_TRUE(ee == b.edge_edge) << "sweep " << amount << ", distance " << d;
      // The sweep holds every pair of either end state.
      for (const Eigen::Matrix3Xd* x : {&m.positions, &x1}) {
        const std::set<std::array<int, 2>> all_vf(b.vertex_face.begin(), b.vertex_face.end()),
            all_ee(b.edge_edge.begin(), b.edge_edge.end());
        for (const auto& p : brute_vf(*x, m.triangles, d)) EXPECT_TRUE(all_vf.count(p)) << "sweep " << amount;
        for (const auto& p : brute_ee(*x, edges, d)) EXPECT_TRUE(all_ee.count(p)) << "sweep " << amount;
      }
      if (amount == 0.0) {
        EXPECT_TRUE(vf == brute_vf(m.positions, m.triangles, d));
        EXPECT_TRUE(ee == brute_ee(m.positions, edges, d));
      }
    }
  Pairs out;
  EXPECT_THROW(pce::sim::brute_force_candidates(m.positions, m.positions.leftCols(3), m.triangles, edges, 0.1),
               std::invalid_argument);
  EXPECT_THROW(bp->vertex_face(m.positions, m.positions.leftCols(3), m.triangles, 0.1, out), std::invalid_argument);
}

TEST_P(TreeBroadPhase, SweptCandidatesCover) {
  // Random states y with every vertex within m/2 of its swept box on every axis: every pair
  // closer than d at y is a candidate of the sweep (distance d + m).
  const pce::sim::Mesh m = crumpled(12, 9);
  const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
  const double d = 0.02, margin = 0.02;
  const Eigen::Matrix3Xd x0 = m.positions, x1 = moved(x0, 0.04);
  auto bp = make();
  Pairs vf, ee;
  bp->vertex_face(x0, x1, m.triangles, d + margin, vf);
  bp->edge_edge(x0, x1, edges, d + margin, ee);
  const std::set<std::array<int, 2>> cvf(vf.begin(), vf.end()), cee(ee.begin(), ee.end());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  long close_pairs = 0;
  for (int trial = 0; trial < 6; ++trial) {
    Eigen::Matrix3Xd y(3, x0.cols());
    for (Eigen::Index v = 0; v < x0.cols(); ++v)
      for (int c = 0; c < 3; ++c) {
        const double lo = std::min(x0(c, v), x1(c, v)) - margin / 2, hi = std::max(x0(c, v), x1(c, v)) + margin / 2;
        y(c, v) = trial % 2 ? (u(rng) < 0.5 ? lo : hi) : lo + u(rng) * (hi - lo);  // extremes or inside
      }
    for (const auto& p : brute_vf(y, m.triangles, d)) {  // box-close at y: measure the distance
      const Eigen::Vector3i t = m.triangles.col(p[1]);
      pce::Vec12<double> xp;
      xp << y.col(p[0]), y.col(t[0]), y.col(t[1]), y.col(t[2]);
      pce::ClosestFeatureEnergy<double> ce;
      if (pce::closest_feature_energy<pce::VertexFace>(xp, pce::UnsignedLength{}, pce::QuadraticPenalty{1.0, 0.0},
                                                       ce) != pce::Status::ok ||
          ce.length >= d)
        continue;
      ++close_pairs;
      EXPECT_TRUE(cvf.count(p)) << "vertex " << p[0] << ", triangle " << p[1] << " at distance " << ce.length;
    }
    for (const auto& p : brute_ee(y, edges, d)) {
      pce::Vec12<double> xp;
      xp << y.col(edges(0, p[0])), y.col(edges(1, p[0])), y.col(edges(0, p[1])), y.col(edges(1, p[1]));
      pce::ClosestFeatureEnergy<double> ce;
      if (pce::closest_feature_energy<pce::EdgeEdge>(xp, pce::UnsignedLength{}, pce::QuadraticPenalty{1.0, 0.0}, ce) !=
              pce::Status::ok ||
          ce.length >= d)
        continue;
      ++close_pairs;
      EXPECT_TRUE(cee.count(p)) << "edges " << p[0] << ", " << p[1] << " at distance " << ce.length;
    }
  }
  EXPECT_GT(close_pairs, 100);  // the states do bring pairs within d
}

INSTANTIATE_TEST_SUITE_P(Kinds, TreeBroadPhase, ::testing::Values(BroadPhaseKind::fcl, BroadPhaseKind::bullet),
                         [](const ::testing::TestParamInfo<BroadPhaseKind>& info) {
                           return std::string(pce::sim::to_string(info.param));
                         });

}  // namespace

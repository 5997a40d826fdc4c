// SPDX-License-Identifier: MIT
// pce-broad-phase-bench: FCL's dynamic AABB tree, Bullet's btDbvt and the brute force
// (pce::sim broad phases, docs/simulation.md §4.1) on crumpled 1 m cloths of n × n quads
// (`pce::sim::crumpled_grid`, the generator test_broad_phase.cpp uses).
//
//   pce-broad-phase-bench [--sizes 10,20,40,80,140,200,280] [--repetitions 5] [--quick]
//                         [--broad-phases fcl,bullet,brute] [--brute-limit-ms 4000]
//                         [--seed 5] [--out FILE.json]
//
// Query distance d = 0.5 / n: half the grid spacing. Every time is one vertex-face query
// plus one edge-edge query on the same object, wall clock, the median over the
// repetitions (all of them for n ≤ 140, half as many above):
//   build_ms   the first queries of a fresh broad phase (the trees are built);
//   update_ms  the vertices moved by up to 0.05 spacing per coordinate, queried again
//              (the trees refit their boxes, then traverse);
//   query_ms   the same positions queried again. The interface has no "unchanged" flag,
//              so the trees still rewrite and refit every box: query_ms is refit +
//              traversal at unchanged boxes, not traversal alone (the tree time is not
//              exposed separately).
// The brute force is O(n⁴) in n; it runs while its estimated call time (its last
// measured call — a 16 × 16 calibration before the first size — scaled by the pair
// count) stays under --brute-limit-ms, and prints what it skips.
// At every size the three broad phases' vectors must be identical (after the build and
// after the update); a mismatch prints the counts and the exit code is 1.
#include <pce/sim/broad_phase.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/mesh.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>
#include <string>
#include <vector>

namespace {

using Pairs = std::vector<std::array<int, 2>>;
using pce::sim::BroadPhaseKind;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t k = v.size() / 2;
  return v.size() % 2 ? v[k] : 0.5 * (v[k - 1] + v[k]);
}

/// The pairs of one vertex-face and one edge-edge query.
struct Result {
  Pairs vf, ee;
  bool operator==(const Result& o) const { return vf == o.vf && ee == o.ee; }
};

/// One vertex-face plus one edge-edge query on `bp`; returns milliseconds.
double query(pce::sim::BroadPhase& bp, const Eigen::Matrix3Xd& x, const pce::sim::Mesh& m,
             const Eigen::Matrix2Xi& edges, double d, Result& r) {
  const auto t0 = std::chrono::steady_clock::now();
  bp.vertex_face(x, m.triangles, d, r.vf);
  bp.edge_edge(x, edges, d, r.ee);
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

struct Row {
  BroadPhaseKind kind;
  int n;
  Eigen::Index vertices, triangles, edges;
  double distance, build_ms, update_ms, query_ms;
  std::size_t vertex_face, edge_edge;
  int repetitions;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pce-broad-phase-bench: FCL vs Bullet vs brute force on crumpled cloths"};
  std::vector<int> sizes{10, 20, 40, 80, 140, 200, 280};
  int repetitions = 5;
  bool quick = false;
  double brute_limit_ms = 4000;
  unsigned seed = 5;
  std::string out_file;
  std::vector<std::string> names{"fcl", "bullet", "brute"};
  app.add_option("--sizes", sizes, "cloth resolutions n (n x n quads)")->delimiter(',')->check(CLI::Range(1, 4096));
  app.add_option("--repetitions", repetitions, "repetitions per size (n > 140: half as many)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--broad-phases", names, "broad phases to run, the first is the reference")
      ->delimiter(',')
      ->check(CLI::IsMember({"fcl", "bullet", "brute"}));
  app.add_flag("--quick", quick, "smoke test: sizes 10,20, one repetition");
  app.add_option("--brute-limit-ms", brute_limit_ms, "skip the brute force above this estimated call time")
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "crumpling seed");
  app.add_option("--out", out_file, "also write the results as JSON");
  CLI11_PARSE(app, argc, argv);
  if (quick) {
    sizes = {10, 20};
    repetitions = 1;
  }
  const double fold = 0.05, jitter = 0.4, move = 0.05;
  std::vector<BroadPhaseKind> kinds;
  for (const std::string& name : names) kinds.push_back(*pce::sim::broad_phase_kind(name));

  std::vector<Row> rows;
  nlohmann::json skipped = nlohmann::json::array();
  bool mismatch = false;
  // The last brute-force call and its pair-test count (V·T + E²/2), first a small calibration.
  double brute_last_ms = 0, brute_last_work = 0;
  const auto work_of = [](const pce::sim::Mesh& m, const Eigen::Matrix2Xi& edges) {
    return double(m.vertex_count()) * double(m.triangles.cols()) + 0.5 * double(edges.cols()) * double(edges.cols());
  };
  {
    const pce::sim::Mesh m = pce::sim::crumpled_grid(16, seed, fold, jitter);
    const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
    auto brute = pce::sim::make_broad_phase(BroadPhaseKind::brute);
    Result r;
    brute_last_ms = query(*brute, m.positions, m, edges, 0.5 / 16, r);
    brute_last_work = work_of(m, edges);
  }
  std::printf("%-7s %5s %8s %9s %9s %9s %10s %10s %10s %10s %10s %4s\n", "phase", "n", "vertices", "triangles", "edges",
              "distance", "build_ms", "update_ms", "query_ms", "vf_pairs", "ee_pairs", "reps");
  for (int n : sizes) {
    const pce::sim::Mesh m = pce::sim::crumpled_grid(n, seed, fold, jitter);
    const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
    const double spacing = 1.0 / n, d = 0.5 * spacing;
    Eigen::Matrix3Xd moved = m.positions;
    std::mt19937_64 rng(seed + 1000u * static_cast<unsigned>(n));
    std::uniform_real_distribution<double> u(-move * spacing, move * spacing);
    for (Eigen::Index k = 0; k < moved.size(); ++k) moved.data()[k] += u(rng);
    const int reps = n <= 140 ? repetitions : std::max(1, repetitions / 2);
    const double work = work_of(m, edges);

    Result reference_built, reference_moved;
    bool have_reference = false;
    for (BroadPhaseKind kind : kinds) {
      const char* name = pce::sim::to_string(kind);
      int kind_reps = reps;
      if (kind == BroadPhaseKind::brute) {
        const double estimate = brute_last_ms * work / brute_last_work;
        if (estimate > brute_limit_ms) {
          std::printf("%-7s %5d  skipped: estimated %.0f ms per call > --brute-limit-ms %.0f\n", name, n, estimate,
                      brute_limit_ms);
          skipped.push_back({{"broad_phase", name}, {"n", n}, {"estimated_call_ms", estimate}});
          continue;
        }
        if (estimate * 3 * reps > 4 * brute_limit_ms) kind_reps = 1;  // slow: one repetition is enough
      }
      std::vector<double> build, update, again;
      Result built, updated, queried;
      for (int r = 0; r < kind_reps; ++r) {
        auto bp = pce::sim::make_broad_phase(kind);
        build.push_back(query(*bp, m.positions, m, edges, d, built));
        update.push_back(query(*bp, moved, m, edges, d, updated));
        again.push_back(query(*bp, moved, m, edges, d, queried));
      }
      if (kind == BroadPhaseKind::brute) {
        brute_last_ms = std::min({median(build), median(update), median(again)});
        brute_last_work = work;
      }
      if (!(updated == queried)) {
        std::fprintf(stderr, "pce-broad-phase-bench: %s, n = %d: the repeated query differs from the update\n", name,
                     n);
        mismatch = true;
      }
      if (!have_reference) {
        reference_built = built;
        reference_moved = updated;
        have_reference = true;
      } else if (!(built == reference_built) || !(updated == reference_moved)) {
        std::fprintf(stderr,
                     "pce-broad-phase-bench: %s, n = %d: candidates differ from %s's (vertex-face %zu vs %zu, "
                     "edge-edge %zu vs %zu after the build; %zu vs %zu, %zu vs %zu after the update)\n",
                     name, n, names.front().c_str(), built.vf.size(), reference_built.vf.size(), built.ee.size(),
                     reference_built.ee.size(), updated.vf.size(), reference_moved.vf.size(), updated.ee.size(),
                     reference_moved.ee.size());
        mismatch = true;
      }
      const Row row{kind,
                    n,
                    m.vertex_count(),
                    m.triangles.cols(),
                    edges.cols(),
                    d,
                    median(build),
                    median(update),
                    median(again),
                    updated.vf.size(),
                    updated.ee.size(),
                    kind_reps};
      rows.push_back(row);
      std::printf("%-7s %5d %8td %9td %9td %9.5f %10.2f %10.2f %10.2f %10zu %10zu %4d\n", name, n, row.vertices,
                  row.triangles, row.edges, d, row.build_ms, row.update_ms, row.query_ms, row.vertex_face,
                  row.edge_edge, row.repetitions);
      std::fflush(stdout);
    }
  }
  std::printf(
      "times: one vertex-face + one edge-edge query, medians, wall clock; distance 0.5/n; "
      "update = vertices moved by <= %.2f spacing; pair counts after the update\n",
      move);
  std::printf(mismatch ? "MISMATCH between broad phases (see stderr)\n"
                       : "all broad phases returned identical candidates\n");

  if (!out_file.empty()) {
    nlohmann::json j;
    j["settings"] = {{"sizes", sizes},
                     {"broad_phases", names},
                     {"repetitions", repetitions},
                     {"repetitions_above_140", std::max(1, repetitions / 2)},
                     {"seed", seed},
                     {"fold", fold},
                     {"jitter", jitter},
                     {"cloth_size_m", 1.0},
                     {"distance", "0.5 / n (half the grid spacing)"},
                     {"update_move", "uniform in [-0.05, 0.05] spacing per coordinate"},
                     {"brute_limit_ms", brute_limit_ms},
                     {"timing", "wall-clock ms of one vertex_face + one edge_edge call, median over repetitions"},
                     {"identical_candidates", !mismatch}};
    j["skipped"] = skipped;
    j["rows"] = nlohmann::json::array();
    for (const Row& r : rows)
      j["rows"].push_back({{"broad_phase", pce::sim::to_string(r.kind)},
                           {"n", r.n},
                           {"vertices", r.vertices},
                           {"triangles", r.triangles},
                           {"edges", r.edges},
                           {"distance", r.distance},
                           {"build_ms", r.build_ms},
                           {"update_ms", r.update_ms},
                           {"query_ms", r.query_ms},
                           {"vertex_face", r.vertex_face},
                           {"edge_edge", r.edge_edge},
                           {"repetitions", r.repetitions}});
    std::ofstream f(out_file);
    f << j.dump(1) << "\n";
    if (!f) {
      std::cerr << "pce-broad-phase-bench: cannot write " << out_file << "\n";
      return 1;
    }
  }
  return mismatch ? 1 : 0;
}

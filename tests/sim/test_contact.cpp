// SPDX-License-Identifier: MIT
// Self contact effects: gradients against central differences, PSD Hessians for every
// strategy, signed sides recorded at entry and kept while tracked, barrier step limits, a
// landing sheet covered by one query over its sweep, and trajectories independent of the
// thread count.
#include <pce/energy/closest_feature.hpp>
#include <pce/penalties/quadratic.hpp>
#include <pce/sim/candidates.hpp>
#include <pce/sim/contact_effect.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/instrumentation.hpp>
#include <pce/sim/intersections.hpp>
#include <pce/sim/scene.hpp>

#include "two_sheets.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Eigenvalues>

#include <atomic>
#include <cstring>
#include <filesystem>

using namespace pce::sim;
using nlohmann::json;

namespace {

using fixtures::contact_of;
using fixtures::dense_hessian;
using fixtures::two_sheets;

json contact(const char* type, const char* length, const char* hessian, bool closest,
             const char* penalty = "quadratic") {
  json c = {{"type", type}, {"length", length}, {"hessian", hessian}, {"closest_features", closest}};
  c["penalty"] = {{"type", penalty}, {"stiffness", 50.0}, {"distance", 0.02}};
  return c;
}

/// Starts a step at the scene's positions (zero velocity) so the effect queries its pairs.
void begin(Scene& s) { fixtures::begin_at(s, s.simulation.x); }

/// A step for two_sheets placed 4 mm apart: every vertex moves randomly by up to 2 mm per
/// axis, every (5 + seed % 3)-th four times that, and sheet b comes down 12 mm (through a,
/// were it not stopped), so pairs of the two sheets close in and bind the step below the
/// candidate set's validity limit (random motion alone does not).
Eigen::Matrix3Xd closing_motion(const Eigen::Matrix3Xd& x, int seed) {
  std::srand(static_cast<unsigned>(seed) + 1u);
  Eigen::Matrix3Xd dx = Eigen::Matrix3Xd::Random(3, x.cols()) * 0.002;
  for (Eigen::Index i = 0; i < x.cols(); i += 5 + seed % 3) dx.col(i) *= 4.0;
  dx.row(2).tail(x.cols() / 2).array() -= 0.012;
  return dx;
}

/// The broad-phase queries the effect made since its last begin_step.
double queries_of(const Effect& e) {
  EffectCounters c;
  e.report(c);
  return c.at("broad_phase_queries");
}

/// Two copies of the same one-effect scene, each past begin(), and a state with a little
/// out-of-plane noise (so edge-edge pairs have frames): one copy takes a pass under test,
/// the other the full pass it must agree with.
struct Twins {
  std::unique_ptr<Scene> a, b;
  ContactEffect& ea;
  ContactEffect& eb;
  Eigen::Matrix3Xd x;
  Twins(const json& effect, double gap)
      : a(two_sheets(effect, gap)),
        b(two_sheets(effect, gap)),
        ea((begin(*a), contact_of(a->simulation.effects[0]))),
        eb((begin(*b), contact_of(b->simulation.effects[0]))),
        x(a->simulation.x) {
    for (Eigen::Index i = 0; i < x.cols(); ++i) x(2, i) += 1e-3 * std::sin(1.7 * static_cast<double>(i));
  }
};

/// Moves sheet b's vertices (the second half) up by dz.
Eigen::Matrix3Xd lift_b(const Eigen::Matrix3Xd& x, double dz) {
  Eigen::Matrix3Xd y = x;
  const Eigen::Index half = x.cols() / 2;
  y.row(2).tail(half).array() += dz;
  return y;
}

}  // namespace

class ContactDerivatives : public ::testing::TestWithParam<std::tuple<const char*, const char*, bool>> {};

TEST_P(ContactDerivatives, GradientMatchesCentralDifferencesAndHessianIsPsd) {
  const auto [type, length, closest] = GetParam();
  for (const char* hessian : {"analytic", "exact", "numerical", "gauss_newton", "abs"}) {
    SCOPED_TRACE(std::string(type) + " " + length + " " + hessian + (closest ? " closest" : " plane"));
    auto s = two_sheets(contact(type, length, hessian, closest), 0.008);
    begin(*s);
    ContactEffect& e = contact_of(s->simulation.effects[0]);
    Eigen::Matrix3Xd x = s->simulation.x;
    // a little out-of-plane noise so edge-edge pairs have frames
    for (Eigen::Index i = 0; i < x.cols(); ++i) x(2, i) += 1e-3 * std::sin(1.7 * static_cast<double>(i));
    Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, x.cols());
    const double E = e.evaluate(x, &g, nullptr);
    EXPECT_GT(E, 0.0);
    EffectCounters c;
    e.report(c);
    const std::string kind = std::string(type) == "self_vertex_face" ? "vertex_face" : "edge_edge";
    EXPECT_GT(c.at(kind + "_contacts"), 0.0);
    const double h = 1e-7;
    double worst = 0, scale = g.cwiseAbs().maxCoeff();
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      Eigen::Matrix3Xd xp = x, xm = x;
      xp.data()[i] += h;
      xm.data()[i] -= h;
      const double fd = (e.evaluate(xp, nullptr, nullptr) - e.evaluate(xm, nullptr, nullptr)) / (2 * h);
      worst = std::max(worst, std::abs(fd - g.data()[i]));
    }
    EXPECT_LT(worst, 1e-5 * scale);
    const Eigen::MatrixXd H = dense_hessian(e, x);
    const double lmin = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H).eigenvalues().minCoeff();
    EXPECT_GE(lmin, -1e-9 * H.cwiseAbs().maxCoeff());
  }
}

INSTANTIATE_TEST_SUITE_P(Kinds, ContactDerivatives,
                         ::testing::Values(std::make_tuple("self_vertex_face", "unsigned", false),
                                           std::make_tuple("self_vertex_face", "signed", false),
                                           std::make_tuple("self_vertex_face", "unsigned", true),
                                           std::make_tuple("self_edge_edge", "unsigned", false),
                                           std::make_tuple("self_edge_edge", "signed", false),
                                           std::make_tuple("self_edge_edge", "unsigned", true)));

TEST(Contact, PassesThatReuseAnEarlierPassAgreeWithAFullPass) {
  // The Newton evaluation after update_pattern visits only the pairs active there, and
  // update_pattern after a full evaluation at the same state reads that evaluation's record
  // instead of testing every candidate. Each must give exactly what a full pass gives.
  for (const auto& [type, length, closest] :
       {std::make_tuple("self_vertex_face", "signed", false), std::make_tuple("self_vertex_face", "unsigned", true),
        std::make_tuple("self_edge_edge", "unsigned", false), std::make_tuple("self_edge_edge", "unsigned", true)}) {
    SCOPED_TRACE(std::string(type) + " " + length + (closest ? " closest" : " plane"));
    Twins t(contact(type, length, "analytic", closest), 0.008);
    ContactEffect &ea = t.ea, &eb = t.eb;
    const Eigen::Matrix3Xd& x = t.x;
    const auto n = static_cast<int>(x.cols());
    // a: update_pattern tests every candidate; the evaluation then visits the active ones.
    ea.begin_iteration(x);
    Pattern pa;
    ea.declare(pa);
    BlockHessian H;
    H.set_pattern(n, pa);
    Eigen::Matrix3Xd ga = Eigen::Matrix3Xd::Zero(3, n);
    const double Ea = ea.evaluate(x, &ga, &H);
    // b: a full evaluation first, whose record update_pattern then reads.
    Eigen::Matrix3Xd gb = Eigen::Matrix3Xd::Zero(3, n);
    const double Eb = eb.evaluate(x, &gb, nullptr);
    eb.begin_iteration(x);
    Pattern pb;
    eb.declare(pb);
    EXPECT_GT(pa.pairs().size(), 0u);
    EXPECT_EQ(pa.pairs(), pb.pairs());
    EXPECT_GT(Ea, 0.0);
    EXPECT_EQ(Ea, Eb);
    EXPECT_EQ(ga, gb);
    EffectCounters ca, cb;
    ea.report(ca);
    eb.report(cb);
    const std::string kind = std::string(type) == "self_vertex_face" ? "vertex_face" : "edge_edge";
    EXPECT_EQ(ca.at(kind + "_contacts"), cb.at(kind + "_contacts"));
    EXPECT_EQ(ca.at(kind + "_declared"), cb.at(kind + "_declared"));
  }
}

TEST(Contact, LineSearchTrialsOnTheStepAgreeWithAFullPass) {
  // After max_step(x, dx), an evaluation at x + α dx (α up to the limit) visits only the
  // pairs max_step listed as possibly active on that segment; it must give exactly what a
  // full pass gives, and so must update_pattern reading its record. Sheet b starts 0.025
  // above a (beyond d = 0.02, within the query radius 1.5d) and the step lowers half of it
  // by 0.015, so pairs activate along the step while the other half's pairs stay out of
  // reach.
  for (const auto& [type, length, closest] :
       {std::make_tuple("self_vertex_face", "signed", false), std::make_tuple("self_vertex_face", "unsigned", false),
        std::make_tuple("self_vertex_face", "unsigned", true), std::make_tuple("self_edge_edge", "unsigned", false),
        std::make_tuple("self_edge_edge", "unsigned", true)}) {
    SCOPED_TRACE(std::string(type) + " " + length + (closest ? " closest" : " plane"));
    Twins twins(contact(type, length, "analytic", closest), 0.025);
    ContactEffect &ea = twins.ea, &eb = twins.eb;
    const Eigen::Matrix3Xd& x = twins.x;
    Eigen::Matrix3Xd dx = Eigen::Matrix3Xd::Zero(3, x.cols());
    const Eigen::Index half = x.cols() / 2;
    for (Eigen::Index i = half; i < x.cols(); ++i)
      if (x(0, i) < 0) dx(2, i) = -0.015, dx(1, i) = 0.004 * std::cos(2.3 * static_cast<double>(i));
    const double t = ea.begin_line_search(x, dx);
    ASSERT_GT(t, 0.4);
    const std::string kind = std::string(type) == "self_vertex_face" ? "vertex_face" : "edge_edge";
    std::atomic<long>& visited = kind == "vertex_face" ? instrumentation().vertex_face_pairs_evaluated
                                                       : instrumentation().edge_edge_pairs_evaluated;
    long fewer = 0;
    for (const double alpha : {t, 0.5 * t, 0.25 * t, 0.0}) {
      SCOPED_TRACE(alpha);
      const Eigen::Matrix3Xd y = x + alpha * dx;
      Eigen::Matrix3Xd ga = Eigen::Matrix3Xd::Zero(3, x.cols()), gb = ga;
      const long before = visited;
      const double Ea = ea.evaluate(y, &ga, nullptr);
      const long on_list = visited - before;
      const double Eb = eb.evaluate(y, &gb, nullptr);
      fewer += visited - before - on_list > on_list;  // the full pass visited more pairs
      EXPECT_EQ(Ea, Eb);
      EXPECT_EQ(ga, gb);
      EffectCounters ca, cb;
      ea.report(ca);
      eb.report(cb);
      EXPECT_EQ(ca.at(kind + "_contacts"), cb.at(kind + "_contacts"));
      EXPECT_EQ(ca.at(kind + "_min_distance"), cb.at(kind + "_min_distance"));
      // update_pattern at y reads the list pass's record (a) or its own full pass's (b).
      ea.begin_iteration(y);
      eb.begin_iteration(y);
      Pattern pa, pb;
      ea.declare(pa);
      eb.declare(pb);
      EXPECT_EQ(pa.pairs(), pb.pairs());
      if (alpha == t) {
        EXPECT_GT(ca.at(kind + "_contacts"), 0.0);
      }
    }
    if (!(std::string(type) == "self_vertex_face" && std::string(length) == "signed")) {
      EXPECT_GT(fewer, 0);  // (signed plane mode reaches 2d, beyond the query radius: every candidate is listed)
    }
    // A state off the segment is evaluated in full.
    const Eigen::Matrix3Xd off = lift_b(x, -0.03);
    EXPECT_EQ(ea.evaluate(off, nullptr, nullptr), eb.evaluate(off, nullptr, nullptr));
  }
}

TEST(Contact, SignedSideIsRecordedAtEntryAndKeptWhileTracked) {
  auto s = two_sheets(contact("self_vertex_face", "signed", "analytic", false), 0.008);
  begin(*s);
  ContactEffect& e = contact_of(s->simulation.effects[0]);
  const Eigen::Matrix3Xd above = s->simulation.x;
  const Eigen::Matrix3Xd below = lift_b(above, -0.016);  // b now 0.008 below a: it passed through
  const double E_above = e.evaluate(above, nullptr, nullptr);
  const double E_below = e.evaluate(below, nullptr, nullptr);
  // Same |l| both times; the signed length remembers b came from above and penalises the
  // crossing far more (L = −0.008 instead of +0.008).
  EXPECT_GT(E_below, 5.0 * E_above);
  e.refresh(below);  // a re-query keeps the sides of the pairs it still finds
  EXPECT_DOUBLE_EQ(e.evaluate(below, nullptr, nullptr), E_below);

  auto u = two_sheets(contact("self_vertex_face", "unsigned", "analytic", false), 0.008);
  begin(*u);
  ContactEffect& eu = contact_of(u->simulation.effects[0]);
  EXPECT_NEAR(eu.evaluate(below, nullptr, nullptr), eu.evaluate(above, nullptr, nullptr),
              1e-9 * eu.evaluate(above, nullptr, nullptr));
}

TEST(Contact, BarrierStepNeverReachesZeroDistance) {
  auto s = two_sheets(contact("self_vertex_face", "unsigned", "analytic", true, "log_barrier"), 0.008);
  begin(*s);
  ContactEffect& e = contact_of(s->simulation.effects[0]);
  const Eigen::Matrix3Xd x = s->simulation.x;
  const Eigen::Matrix3Xd dx = lift_b(x, -0.05) - x;  // straight through the other sheet
  const double t = e.begin_line_search(x, dx);
  EXPECT_GT(t, 0.0);
  EXPECT_LT(t, 0.16);  // the sheets touch at t = 0.16
  EXPECT_TRUE(std::isfinite(e.evaluate(x + t * dx, nullptr, nullptr)));
  EXPECT_FALSE(std::isfinite(e.evaluate(lift_b(x, -0.008), nullptr, nullptr)));  // touching: infinite
}

TEST(Contact, PairsAreCountedOnlyForDeclaredKinds) {
  auto s = two_sheets(contact("self_edge_edge", "unsigned", "analytic", false), 0.008);
  const long vf = instrumentation().vertex_face_pairs_evaluated, ee = instrumentation().edge_edge_pairs_evaluated;
  begin(*s);
  s->simulation.effects[0]->evaluate(s->simulation.x, nullptr, nullptr);
  EXPECT_EQ(instrumentation().vertex_face_pairs_evaluated, vf);
  EXPECT_GT(instrumentation().edge_edge_pairs_evaluated, ee);
}

TEST(Contact, DeclaresExactlyThePairsActiveAtTheIterate) {
  const std::tuple<const char*, const char*, bool> kinds[] = {
      {"self_vertex_face", "unsigned", false}, {"self_vertex_face", "signed", false},
      {"self_vertex_face", "unsigned", true},  {"self_edge_edge", "unsigned", false},
      {"self_edge_edge", "signed", false},     {"self_edge_edge", "unsigned", true}};
  for (const auto& [type, length, closest] : kinds) {
    SCOPED_TRACE(std::string(type) + " " + length + (closest ? " closest" : " plane"));
    auto s = two_sheets(contact(type, length, "analytic", closest), 0.008);
    begin(*s);
    ContactEffect& e = contact_of(s->simulation.effects[0]);
    Eigen::Matrix3Xd x = s->simulation.x;
    for (Eigen::Index i = 0; i < x.cols(); ++i) x(2, i) += 1e-3 * std::sin(1.7 * static_cast<double>(i));
    const std::string kind = std::string(type) == "self_vertex_face" ? "vertex_face" : "edge_edge";
    const auto counts = [&](const Eigen::Matrix3Xd& at) {
      e.evaluate(at, nullptr, nullptr);
      EffectCounters c;
      e.report(c);
      return std::make_pair(c.at(kind + "_declared"), c.at(kind + "_contacts"));
    };
    EXPECT_TRUE(e.begin_iteration(x));
    const auto [declared, active] = counts(x);
    EXPECT_GT(active, 0.0);
    EXPECT_EQ(declared, active);
    EXPECT_FALSE(e.begin_iteration(x));  // unchanged: the solver keeps its symbolic analysis
    // Sheet b leaves contact (0.038 apart, still candidates): the pattern shrinks to nothing.
    const Eigen::Matrix3Xd away = lift_b(x, 0.03);
    EXPECT_TRUE(e.begin_iteration(away));
    EXPECT_EQ(counts(away), std::make_pair(0.0, 0.0));
    EXPECT_TRUE(e.begin_iteration(x));  // and grows back
    EXPECT_EQ(counts(x), std::make_pair(declared, active));
  }
}

/// The conservative step bound over the documented candidate set, written out: the
/// candidate set's validity (below), then every
/// brute-force candidate at the query positions, minus same-mesh pairs closer than the
/// query radius at rest, each limiting t to where additive CCD, iterated, stops (from 0.9
/// D/(a + b); D its closest-feature distance, a and b the largest motion on each primitive
/// relative to the pair's mean motion).
template <class Kind> double reference_step(const Scene& s, const std::vector<std::array<int, 2>>& pairs,
                                            const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, double radius,
                                            double* validity = nullptr) {
  const Model& m = s.simulation.model;
  const auto verts = [&](const std::array<int, 2>& c) -> std::array<int, 4> {
    if constexpr (std::is_same_v<Kind, pce::VertexFace>)
      return {c[0], m.triangles(0, c[1]), m.triangles(1, c[1]), m.triangles(2, c[1])};
    else
      return {m.edges(0, c[0]), m.edges(1, c[0]), m.edges(0, c[1]), m.edges(1, c[1])};
  };
  const int first = std::is_same_v<Kind, pce::VertexFace> ? 1 : 2;
  const auto distance = [](const Eigen::Matrix3Xd& at, const std::array<int, 4>& v) {
    pce::Vec12<double> xp;
    for (int j = 0; j < 4; ++j) xp.segment<3>(3 * j) = at.col(v[static_cast<std::size_t>(j)]);
    pce::ClosestFeatureEnergy<double> ce;
    const bool ok = pce::closest_feature_energy<Kind>(xp, pce::UnsignedLength{}, pce::QuadraticPenalty{1.0, 0.0}, ce) ==
                    pce::Status::ok;
    return ok ? ce.length : -1.0;
  };
  // the candidate set stays valid (the query was made at x, so the drift is t dx): for the
  // two sheets (their boxes overlap here, so every budget is the margin m = radius − d),
  // each sheet's spread about its mean drift, and the pair's s_a + s_b + |c_a − c_b|,
  // within m
  const int half = static_cast<int>(x.cols() / 2);
  const auto spread = [&](int first) {
    const Eigen::Matrix3Xd part = dx.middleCols(first, half);
    const Eigen::Vector3d c = part.rowwise().mean();
    return std::make_pair(c, (part.colwise() - c).colwise().norm().maxCoeff());
  };
  const auto [ca, sa] = spread(0);
  const auto [cb, sb] = spread(half);
  const double budget = 0.5 * 0.02;  // m = d/2, d = 0.02 (contact())
  double t = 1.0;
  for (const double rel : {2 * sa, 2 * sb, sa + sb + (ca - cb).norm()})
    if (rel > 0) t = std::min(t, budget / rel);
  // or every vertex stays within m/2 (less a relative 1e-6) of where it was queried, on
  // every axis: up to (x + room − x)/|dx|, as rounded
  const double room = 0.5 * budget * (1 - 1e-6);
  double sweep = 1.0;
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    for (int k = 0; k < 3; ++k) {
      if (dx(k, i) > 0) sweep = std::min(sweep, (x(k, i) + room - x(k, i)) / dx(k, i));
      if (dx(k, i) < 0) sweep = std::min(sweep, (x(k, i) - room - x(k, i)) / dx(k, i));
    }
  const double valid = std::max(t, sweep);
  if (validity) *validity = valid;
  t = valid;
  for (const auto& c : pairs) {
    const auto v = verts(c);
    if ((v[0] < half) == (v[static_cast<std::size_t>(first)] < half) && distance(m.rest, v) < radius) continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();  // the pair's mean displacement
    for (int j = 0; j < 4; ++j) mean += dx.col(v[static_cast<std::size_t>(j)]) / 4.0;
    double a = 0, b = 0;
    for (int j = 0; j < 4; ++j)
      (j < first ? a : b) = std::max(j < first ? a : b, (dx.col(v[static_cast<std::size_t>(j)]) - mean).norm());
    const double D = distance(x, v);
    if (D < 0 || !(a + b > 0)) continue;
    // additive CCD, iterated: from a distance d at tk the pair stays ≥ D/10 apart for another
    // (d − D/10)/(a + b); advance 0.9 of that until the validity limit, a stall or 32 rounds
    double tk = 0.9 * D / (a + b);
    for (int round = 0; round < 32 && tk < valid; ++round) {
      const double d = distance(x + tk * dx, v);
      if (d < 0) break;
      const double advance = 0.9 * (d - 0.1 * D) / (a + b);
      if (!(advance > 1e-3 * tk)) break;
      tk += advance;
    }
    t = std::min(t, tk);
  }
  return t;
}

TEST(Contact, StepKeepsEveryCandidateATenthOfItsDistanceAlongTheWholeStep) {
  // The guarantee behind the step bound, checked by sampling the step: for t = max_step, every
  // pair within the query radius at x stays at least a tenth of its distance at x apart at
  // x + s dx for every sampled s in [0, t] (so no pair crosses), however far the iterated
  // additive CCD advanced.
  for (const char* type : {"self_vertex_face", "self_edge_edge"}) {
    for (int seed = 0; seed < 8; ++seed) {
      SCOPED_TRACE(std::string(type) + " seed " + std::to_string(seed));
      auto s = two_sheets(contact(type, "unsigned", "analytic", true), 0.004);
      begin(*s);
      ContactEffect& e = contact_of(s->simulation.effects[0]);
      const Eigen::Matrix3Xd x = s->simulation.x;
      const Eigen::Matrix3Xd dx = closing_motion(x, seed + 100);
      const double t = e.begin_line_search(x, dx);
      ASSERT_GT(t, 0.0);
      const Model& m = s->simulation.model;
      const Candidates c = brute_force_candidates(x, m.triangles, m.edges, 0.03);
      const bool vf = std::string(type) == "self_vertex_face";
      const auto& pairs = vf ? c.vertex_face : c.edge_edge;
      const auto distance = [&](const Eigen::Matrix3Xd& at, const std::array<int, 2>& p) {
        pce::Vec12<double> xp;
        const std::array<int, 4> v =
            vf ? std::array<int, 4>{p[0], m.triangles(0, p[1]), m.triangles(1, p[1]), m.triangles(2, p[1])}
               : std::array<int, 4>{m.edges(0, p[0]), m.edges(1, p[0]), m.edges(0, p[1]), m.edges(1, p[1])};
        for (int j = 0; j < 4; ++j) xp.segment<3>(3 * j) = at.col(v[static_cast<std::size_t>(j)]);
        pce::ClosestFeatureEnergy<double> ce;
        const pce::Status st = vf ? pce::closest_feature_energy<pce::VertexFace>(xp, pce::UnsignedLength{},
                                                                                 pce::QuadraticPenalty{1.0, 0.0}, ce)
                                  : pce::closest_feature_energy<pce::EdgeEdge>(xp, pce::UnsignedLength{},
                                                                               pce::QuadraticPenalty{1.0, 0.0}, ce);
        return st == pce::Status::ok ? ce.length : -1.0;
      };
      std::vector<double> d0(pairs.size());
      for (std::size_t k = 0; k < pairs.size(); ++k) d0[k] = distance(x, pairs[k]);
      double closest = std::numeric_limits<double>::infinity();  // smallest distance / d0 seen
      for (int i = 1; i <= 48; ++i) {
        const Eigen::Matrix3Xd at = x + (t * i / 48.0) * dx;
        for (std::size_t k = 0; k < pairs.size(); ++k) {
          if (!(d0[k] > 0)) continue;
          const double d = distance(at, pairs[k]);
          if (d >= 0) closest = std::min(closest, d / d0[k]);
        }
      }
      EXPECT_GE(closest, 0.1 * (1 - 1e-9));
      EXPECT_LT(closest, 0.5);  // a closing pair bound the step, well past half its distance
    }
  }
}

TEST(Contact, StepBoundFollowsASlidingPairToTheEndOfTheStep) {
  // Both sheets are 8 mm apart; the upper one slides 8 mm along x (within the candidate
  // set's budget m = 1 cm). No pair comes closer, but a vertex of the lower sheet and a
  // triangle of the upper one move 8 mm relative to each other: the one-shot bound
  // 0.9 d/(a + b) stops at 0.9; iterated additive CCD finds the pair still 8 mm apart and
  // goes on to the whole step.
  auto s = two_sheets(contact("self_vertex_face", "unsigned", "analytic", true), 0.008);
  begin(*s);
  ContactEffect& e = contact_of(s->simulation.effects[0]);
  const Eigen::Matrix3Xd x = s->simulation.x;
  const Eigen::Index half = x.cols() / 2;
  Eigen::Matrix3Xd dx = Eigen::Matrix3Xd::Zero(3, x.cols());
  dx.block(0, half, 1, half).setConstant(0.008);
  EXPECT_EQ(e.begin_line_search(x, dx), 1.0);
}

TEST(Contact, StepBoundIgnoresACommonTranslation) {
  // Both sheets fall together, far more than their distance: no pair comes closer, so the
  // step is not limited; moving only one sheet the same way is.
  auto s = two_sheets(contact("self_vertex_face", "unsigned", "analytic", true), 0.008);
  begin(*s);
  ContactEffect& e = contact_of(s->simulation.effects[0]);
  const Eigen::Matrix3Xd x = s->simulation.x;
  Eigen::Matrix3Xd dx = Eigen::Matrix3Xd::Zero(3, x.cols());
  dx.row(2).setConstant(-0.5);
  EXPECT_EQ(e.begin_line_search(x, dx), 1.0);
  dx.row(2).tail(x.cols() / 2).setZero();      // only sheet a (the lower one) moves down: apart
  EXPECT_LT(e.begin_line_search(x, dx), 0.1);  // conservative: the bound does not know the direction
}

TEST(Contact, StepNeverCarriesAVertexThroughAFaceThatWasNotACandidate) {
  // Sheet b starts 0.1 above sheet a, beyond the query radius 1.5d = 0.03: no pair of the
  // two sheets is a candidate. A step that moves b 0.2 down would carry it through a; the step must end
  // with b no closer than d to a.
  for (const char* type : {"self_vertex_face", "self_edge_edge"}) {
    SCOPED_TRACE(type);
    auto s = two_sheets(contact(type, "unsigned", "analytic", true), 0.1);
    begin(*s);
    ContactEffect& e = contact_of(s->simulation.effects[0]);
    const Eigen::Matrix3Xd x = s->simulation.x;
    const Eigen::Matrix3Xd dx = lift_b(x, -0.2) - x;  // (the candidates are pairs within one sheet)
    const double t = e.begin_line_search(x, dx);
    EXPECT_GT(t, 0.0);
    EXPECT_LE(0.2 * t, 0.1 - 0.02 + 1e-15);  // never closer than d: the set stays valid
    // 0.5 apart, the same step keeps them 0.3 apart: the meshes' gap is its budget, so it
    // is taken whole (a sheet falling away from the others is not held back)
    auto far = two_sheets(contact(type, "unsigned", "analytic", true), 0.5);
    begin(*far);
    EXPECT_EQ(contact_of(far->simulation.effects[0])
                  .begin_line_search(far->simulation.x, lift_b(far->simulation.x, -0.2) - far->simulation.x),
              1.0);
  }
}

TEST(Contact, LandingSheetIsCoveredByOneQueryOverItsSweep) {
  // Sheet b starts 0.1 above sheet a, beyond the query radius 1.5d = 0.03, and falls 0.09 in
  // this step: its inertial prediction x̃ is 0.01 above a. The step's one query sweeps
  // from xⁿ to x̃, so b's pairs with a are candidates from the start and a Newton step to x̃
  // is neither cut by the validity limit (every vertex moves along its swept box) nor by
  // the candidates' bound (0.9 of 0.1 ≥ 0.09). A query at xⁿ alone had no pair of the two
  // sheets and cut that step to (0.1 − d)/0.09 ≈ 0.89.
  for (const char* type : {"self_vertex_face", "self_edge_edge"}) {
    SCOPED_TRACE(type);
    auto s = two_sheets(contact(type, "unsigned", "analytic", true), 0.1);
    ContactEffect& e = contact_of(s->simulation.effects[0]);
    const Eigen::Matrix3Xd x = s->simulation.x;
    const double dt = 0.01;
    Eigen::Matrix3Xd v = (lift_b(x, -0.09) - x) / dt;
    StepContext ctx;
    ctx.frame = 1;
    ctx.time = dt;
    ctx.dt = dt;
    ctx.model = &s->simulation.model;
    ctx.x_start = &x;
    ctx.v_start = &v;
    e.begin_step(ctx);
    EffectCounters falling;
    e.report(falling);
    const Eigen::Matrix3Xd still = Eigen::Matrix3Xd::Zero(3, x.cols());
    ctx.v_start = &still;
    auto resting = two_sheets(contact(type, "unsigned", "analytic", true), 0.1);
    resting->simulation.effects[0]->begin_step(ctx);
    EffectCounters apart;
    resting->simulation.effects[0]->report(apart);
    const std::string kind = std::string(type) == "self_vertex_face" ? "vertex_face" : "edge_edge";
    EXPECT_GT(falling.at(kind + "_candidates"), apart.at(kind + "_candidates"));  // the sweep reaches a
    EXPECT_EQ(e.begin_line_search(x, lift_b(x, -0.09) - x), 1.0);
    EXPECT_TRUE(e.still_valid(lift_b(x, -0.09)));  // no second query
  }
}

TEST(Contact, StepBeyondTheSetIsCoveredByAQueryOverIt) {
  // Sheet b slides 5 cm along x, 8 mm above a: beyond the set's budget m = 1 cm, so max_step
  // alone stops at the validity limit (0.2). cover_step queries again over the step; then
  // the step is whole, a second cover_step has nothing to do, and the energy at x + dx is
  // that of a set queried there.
  for (const char* type : {"self_vertex_face", "self_edge_edge"}) {
    SCOPED_TRACE(type);
    auto s = two_sheets(contact(type, "unsigned", "analytic", true), 0.008);
    begin(*s);
    ContactEffect& e = contact_of(s->simulation.effects[0]);
    const Eigen::Matrix3Xd x = s->simulation.x;
    Eigen::Matrix3Xd dx = Eigen::Matrix3Xd::Zero(3, x.cols());
    dx.block(0, x.cols() / 2, 1, x.cols() / 2).setConstant(0.05);
    EXPECT_LE(e.begin_line_search(x, dx), 0.2 + 1e-12);
    EXPECT_TRUE(e.cover_step(x, dx));
    EXPECT_EQ(e.begin_line_search(x, dx), 1.0);
    EXPECT_FALSE(e.cover_step(x, dx));
    const Eigen::Matrix3Xd end = x + dx;
    auto fresh = two_sheets(contact(type, "unsigned", "analytic", true), 0.008);
    fresh->simulation.x = end;
    begin(*fresh);
    EXPECT_TRUE(e.still_valid(end));
    EXPECT_GT(fresh->simulation.effects[0]->evaluate(end, nullptr, nullptr), 0.0);
    EXPECT_DOUBLE_EQ(e.evaluate(end, nullptr, nullptr), fresh->simulation.effects[0]->evaluate(end, nullptr, nullptr));
  }
}

TEST(Contact, SetStillValidAtTheNextStepIsKeptWithoutAQuery) {
  // With a step bound, begin_step keeps a set that is still valid at xⁿ (the step's cover
  // queries once a Newton step would leave it): a second step from the same state makes no
  // query; a step from a state 5 cm away (beyond the budget) does.
  for (const char* type : {"self_vertex_face", "self_edge_edge"}) {
    SCOPED_TRACE(type);
    auto s = two_sheets(contact(type, "unsigned", "analytic", true), 0.008);
    ContactEffect& e = contact_of(s->simulation.effects[0]);
    const auto queries = [&e] { return queries_of(e); };
    begin(*s);
    EXPECT_EQ(queries(), 1.0);
    begin(*s);
    EXPECT_EQ(queries(), 0.0);
    s->simulation.x.row(0).tail(s->simulation.x.cols() / 2).array() += 0.05;
    begin(*s);
    EXPECT_EQ(queries(), 1.0);
  }
}

TEST(Contact, SavedStateCarriesTheQueryAndRefusesACorruptOne) {
  // save_state: the pairs, then the query's header (1, validity byte) and its sweep. A state
  // without the query part (as older checkpoints wrote) loads and makes the next step query;
  // a corrupt header or a non-finite position is refused, naming what is wrong.
  auto s = two_sheets(contact("self_vertex_face", "unsigned", "analytic", true), 0.008);
  ContactEffect& e = contact_of(s->simulation.effects[0]);
  begin(*s);
  const std::string state = e.save_state();
  const std::size_t n = static_cast<std::size_t>(s->simulation.x.cols());
  const std::size_t query_part = 2 + 2 * 3 * n * sizeof(double);
  ASSERT_GT(state.size(), query_part);
  const std::size_t head = state.size() - query_part;
  EXPECT_EQ(state[head], 1);
  const auto queries = [&e] { return queries_of(e); };
  e.load_state(state);
  begin(*s);
  EXPECT_EQ(queries(), 0.0);  // the restored query is still valid
  e.load_state(state.substr(0, head));
  begin(*s);
  EXPECT_EQ(queries(), 1.0);  // no query saved: one now
  std::string bad = state;
  bad[head + 1] = 7;
  try {
    e.load_state(bad);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& err) {
    EXPECT_NE(std::string(err.what()).find("header"), std::string::npos) << err.what();
  }
  bad = state;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(bad.data() + head + 2, &nan, sizeof nan);
  try {
    e.load_state(bad);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& err) {
    EXPECT_NE(std::string(err.what()).find("not all finite"), std::string::npos) << err.what();
  }
  EXPECT_THROW(e.load_state(state.substr(0, state.size() - 1)), std::invalid_argument);
}

TEST(Contact, ThreadCountDoesNotChangeTheTrajectory) {
  // crumple.json (contact from frame ~9, closest features, fold pairs) with one and with two
  // threads: per-pair results are merged in candidate order and the step bound is a minimum,
  // so every frame is bit for bit the same.
  const auto path = std::filesystem::path(PCE_SOURCE_DIR) / "examples" / "scenes" / "crumple.json";
  auto one = load_scene(path), two = load_scene(path);
  one->simulation.solver.threads = 1;
  two->simulation.solver.threads = 2;
  long contacts = 0;
  for (int f = 1; f <= 13; ++f) {
    const FrameStats a = one->simulation.step();
    const FrameStats b = two->simulation.step();
    ASSERT_EQ(one->simulation.x, two->simulation.x) << "frame " << f;
    ASSERT_EQ(a.newton_iterations, b.newton_iterations) << "frame " << f;
    contacts += static_cast<long>(a.counters.at("vertex_face_contacts") + a.counters.at("edge_edge_contacts"));
  }
  EXPECT_GT(contacts, 100);  // the frames compared include contact
}

TEST(Contact, StepBoundEqualsTheBoundOverEveryCandidate) {
  for (const char* type : {"self_vertex_face", "self_edge_edge"}) {
    for (int seed = 0; seed < 20; ++seed) {
      SCOPED_TRACE(std::string(type) + " seed " + std::to_string(seed));
      // ccd on by default; the reference is the tenth's bound, so no floor (pairs 4 mm apart
      // are at twice the default floor; test_separation_floor checks the floor's bound)
      json effect = contact(type, "unsigned", "analytic", true);
      effect["min_separation"] = 0.0;
      auto s = two_sheets(effect, 0.004);
      begin(*s);  // queried at the scene's positions
      ContactEffect& e = contact_of(s->simulation.effects[0]);
      const Eigen::Matrix3Xd x = s->simulation.x;
      const Eigen::Matrix3Xd dx = closing_motion(x, seed);  // different pairs bind from seed to seed
      const Candidates c = brute_force_candidates(x, s->simulation.model.triangles, s->simulation.model.edges, 0.03);
      double valid = 0;
      const double expected = std::string(type) == "self_vertex_face"
                                  ? reference_step<pce::VertexFace>(*s, c.vertex_face, x, dx, 0.03, &valid)
                                  : reference_step<pce::EdgeEdge>(*s, c.edge_edge, x, dx, 0.03, &valid);
      EXPECT_LT(expected, valid);  // a pair binds, not the validity limit
      EXPECT_DOUBLE_EQ(e.begin_line_search(x, dx), expected);
    }
  }
}

TEST(Contact, CrumplingSheetNeverPassesThroughItselfOrTheSheetBelow) {
  // examples/scenes/crumple.json: a soft 21 × 21 sheet (2 cm edges) dropped edge-first onto a
  // pinned sheet; contact distance one edge length, weak bending, closest features. It
  // lands at frame ~9 and folds onto itself. Every frame: no intersecting triangle pair
  // (exact count), Newton below its iteration cap and the state moving (no line search
  // failing at the first iteration). While pairs closer than 2d at rest were dropped from
  // the candidates, this scene in plane mode had intersecting pairs at frames 21 and 25.
  auto scene = load_scene(std::filesystem::path(PCE_SOURCE_DIR) / "examples" / "scenes" / "crumple.json");
  Simulation& sim = scene->simulation;
  long contacts = 0;
  double fold_contacts = 0;
  for (int f = 1; f <= 40; ++f) {
    const FrameStats st = sim.step();
    ASSERT_EQ(intersecting_triangle_pairs(sim.x, sim.model.triangles), 0) << "frame " << f;
    EXPECT_FALSE(st.hit_iteration_cap) << "frame " << f;
    EXPECT_FALSE(st.line_search_failures > 0 && st.newton_iterations == 1) << "frame " << f << ": did not move";
    contacts += static_cast<long>(st.counters.at("vertex_face_contacts") + st.counters.at("edge_edge_contacts"));
    fold_contacts += st.counters.at("vertex_face_fold_contacts") + st.counters.at("edge_edge_fold_contacts");
  }
  EXPECT_GT(contacts, 10000);     // it landed
  EXPECT_GT(fold_contacts, 0.0);  // and folded onto itself closer than its rest spacing
}

TEST(Contact, RemovedRestExclusionKeyIsRefusedWithTheReason) {
  json c = contact("self_vertex_face", "unsigned", "analytic", false);
  c["exclude_rest_neighbours"] = true;
  try {
    two_sheets(c, 0.1);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("effects[0].exclude_rest_neighbours: this option was removed"),
              std::string::npos)
        << e.what();
  }
}

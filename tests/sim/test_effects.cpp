// SPDX-License-Identifier: MIT
// pce::sim elastic and kinematic effects (src/sim/effects): for every effect the gradient
// against central differences of the energy, the Hessian against central differences of
// the gradient where it is exact, the Hessian's positive semi-definiteness everywhere
// (random, compressed, degenerate states), the declared pattern covering every block the
// effect adds (BlockHessian throws otherwise), and one InputError per kind of bad parameter
// naming its JSON path; pins' targets by a constant velocity and by keyframes, and a
// keyframed pinned edge lifting a hanging sheet that follows. DISABLED_Timing is the microbenchmark (run with
// --gtest_also_run_disabled_tests --gtest_filter=*Timing*).
#include "scene/effect_loaders.hpp"

#include <pce/sim/effects.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/mesh.hpp>
#include <pce/sim/scene.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <ctime>

namespace {
using namespace pce::sim;
using Eigen::Matrix3Xd;
using Eigen::MatrixXd;

Model cloth(int nx = 3, int ny = 3, double bump = 0.0, unsigned seed = 1) {
  const Mesh m = grid(1.0, 1.0, nx, ny);
  Model model;
  model.rest = m.positions;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (Eigen::Index i = 0; i < model.rest.cols(); ++i) model.rest(2, i) += bump * u(rng);
  model.triangles = m.triangles;
  model.edges = unique_edges(m.triangles);
  model.mass = Eigen::VectorXd::Ones(model.rest.cols());
  model.meshes.push_back(
      {"cloth", 0, static_cast<int>(m.vertex_count()), 0, static_cast<int>(m.triangles.cols()), 0, 0});
  return model;
}

Model hair(int count = 2, int segments = 4, double curl = 0.0) {
  const Mesh m = strands(count, segments, 1.0, 0.2, curl);
  Model model;
  model.rest = m.positions;
  model.segments = m.segments;
  model.edges = m.segments;
  model.mass = Eigen::VectorXd::Constant(model.rest.cols(), 0.5);
  model.meshes.push_back({"hair", 0, static_cast<int>(m.vertex_count()), 0, 0, 0, static_cast<int>(m.segments.cols())});
  return model;
}

std::unique_ptr<Effect> build(EffectFactory factory, const std::string& text, const Model& model) {
  const nlohmann::json j = nlohmann::json::parse(text);
  const Params p(j, "test.json", "effects[0]");
  BuildContext ctx;
  ctx.model = &model;
  return factory(p, ctx);
}

/// The JSON path of the InputError building `text` throws ("(no error)" when none).
std::string error_at(EffectFactory factory, const std::string& text, const Model& model) {
  try {
    build(factory, text, model);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "test.json");
    return e.where();
  }
  return "(no error)";
}

Matrix3Xd perturbed(const Matrix3Xd& x, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Matrix3Xd y = x;
  for (Eigen::Index i = 0; i < y.size(); ++i) y.data()[i] += amplitude * u(rng);
  return y;
}

/// A rotation about a generic axis and a translation: rigid motions keep every angle.
Matrix3Xd rigid(const Matrix3Xd& x, double scale = 1.0) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  return ((scale * R) * x).colwise() + Eigen::Vector3d(0.3, -0.2, 0.5);
}

double energy(Effect& e, const Matrix3Xd& x) { return e.evaluate(x, nullptr, nullptr); }

Matrix3Xd gradient(Effect& e, const Matrix3Xd& x) {
  Matrix3Xd g = Matrix3Xd::Zero(3, x.cols());
  e.evaluate(x, &g, nullptr);
  return g;
}

/// The full symmetric matrix of an assembled upper triangle.
MatrixXd dense(const BlockHessian& H) {
  const Eigen::SparseMatrix<double> full = H.matrix().selfadjointView<Eigen::Upper>();
  return MatrixXd(full);
}

/// The Hessian assembled into the pattern the effect declares (throws for an undeclared
/// block), as a dense symmetric matrix.
MatrixXd hessian(Effect& e, const Matrix3Xd& x) {
  Pattern pattern;
  e.declare(pattern);
  BlockHessian H;
  H.set_pattern(static_cast<int>(x.cols()), pattern);
  H.set_zero();
  e.evaluate(x, nullptr, &H);
  return dense(H);
}

Matrix3Xd fd_gradient(Effect& e, const Matrix3Xd& x, double h = 1e-6) {
  Matrix3Xd g(3, x.cols());
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    Matrix3Xd p = x, m = x;
    p.data()[k] += h;
    m.data()[k] -= h;
    g.data()[k] = (energy(e, p) - energy(e, m)) / (2 * h);
  }
  return g;
}

MatrixXd fd_hessian(Effect& e, const Matrix3Xd& x, double h = 1e-6) {
  MatrixXd H(x.size(), x.size());
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    Matrix3Xd p = x, m = x;
    p.data()[k] += h;
    m.data()[k] -= h;
    const Matrix3Xd d = (gradient(e, p) - gradient(e, m)) / (2 * h);
    H.col(k) = Eigen::Map<const Eigen::VectorXd>(d.data(), d.size());
  }
  return 0.5 * (H + H.transpose());
}

double min_eigenvalue(const MatrixXd& H) { return Eigen::SelfAdjointEigenSolver<MatrixXd>(H).eigenvalues().minCoeff(); }

/// ‖a − b‖ / max(‖b‖, floor)
double rel_error(const MatrixXd& a, const MatrixXd& b, double floor = 1e-8) {
  return (a - b).norm() / std::max(b.norm(), floor);
}

void expect_gradient_matches(Effect& e, const Matrix3Xd& x, double tol = 1e-6) {
  const Matrix3Xd g = gradient(e, x), f = fd_gradient(e, x);
  EXPECT_TRUE(g.allFinite());
  EXPECT_LT(rel_error(g, f), tol) << "analytic\n" << g << "\nfinite differences\n" << f;
}

void expect_psd(Effect& e, const Matrix3Xd& x) {
  const MatrixXd H = hessian(e, x);
  ASSERT_TRUE(H.allFinite());
  EXPECT_GE(min_eigenvalue(H), -1e-9 * std::max(1.0, H.norm()));
}

void expect_hessian_matches(Effect& e, const Matrix3Xd& x, double tol = 1e-5) {
  const MatrixXd H = hessian(e, x), F = fd_hessian(e, x);
  EXPECT_LT(rel_error(H, F), tol);
}

// --- gravity --------------------------------------------------------------------------

TEST(Gravity, EnergyGradientAndNoHessian) {
  Model m = cloth();
  m.mass.setLinSpaced(m.mass.size(), 0.5, 2.0);
  auto e = build(load_gravity, R"({"type":"gravity","acceleration":[1,2,-9]})", m);
  const Matrix3Xd x = perturbed(m.rest, 0.1, 3);
  double expected = 0;
  for (Eigen::Index i = 0; i < x.cols(); ++i) expected -= m.mass[i] * Eigen::Vector3d(1, 2, -9).dot(x.col(i));
  EXPECT_NEAR(energy(*e, x), expected, 1e-12 * std::abs(expected));
  expect_gradient_matches(*e, x);
  EXPECT_EQ(hessian(*e, x).norm(), 0.0);
  auto d = build(load_gravity, R"({"type":"gravity"})", m);  // default −9.81 ẑ
  EXPECT_NEAR(gradient(*d, x)(2, 4), 9.81 * m.mass[4], 1e-12);
}

TEST(Gravity, BadParameters) {
  const Model m = cloth();
  EXPECT_EQ(error_at(load_gravity, R"({"type":"gravity","acceleration":[0,-9.81]})", m), "effects[0].acceleration");
  EXPECT_EQ(error_at(load_gravity, R"({"type":"gravity","g":[0,0,-9.81]})", m), "effects[0].g");
}

// --- stretching -------------------------------------------------------------------------

TEST(Stretching, ZeroAtRestAndUnderRigidMotion) {
  const Model m = cloth(3, 3, 0.1);
  auto e = build(load_stretching, R"({"type":"stretching","stiffness":10})", m);
  EXPECT_NEAR(energy(*e, m.rest), 0.0, 1e-24);
  EXPECT_NEAR(energy(*e, rigid(m.rest)), 0.0, 1e-20);
  EXPECT_LT(gradient(*e, rigid(m.rest)).norm(), 1e-10);
  // A uniform stretch by s = 1.5: σ₁ = σ₂ = 1.5, E = μ Σ A · 2 (s − 1)².
  double area = 0;
  for (Eigen::Index t = 0; t < m.triangles.cols(); ++t)
    area += 0.5 * (m.rest.col(m.triangles(1, t)) - m.rest.col(m.triangles(0, t)))
                      .cross(m.rest.col(m.triangles(2, t)) - m.rest.col(m.triangles(0, t)))
                      .norm();
  EXPECT_NEAR(energy(*e, rigid(m.rest, 1.5)), 10 * area * 2 * 0.25, 1e-10);
}

TEST(Stretching, GradientMatchesFiniteDifferences) {
  const Model m = cloth(3, 3, 0.05);
  auto e = build(load_stretching, R"({"type":"stretching","model":"arap","stiffness":7})", m);
  for (unsigned seed = 1; seed <= 4; ++seed)
    expect_gradient_matches(*e, perturbed(rigid(m.rest, 0.8 + 0.2 * seed), 0.1, seed));
}

TEST(Stretching, HessianIsExactWhenStretched) {
  // σ₁, σ₂ > 1 and σ₁ + σ₂ > 2 in every triangle: no eigenvalue is clamped.
  const Model m = cloth(3, 3, 0.05);
  auto e = build(load_stretching, R"({"type":"stretching","stiffness":7})", m);
  expect_hessian_matches(*e, perturbed(rigid(m.rest, 1.4), 0.02, 5));
}

TEST(Stretching, HessianIsPsdEverywhere) {
  const Model m = cloth(3, 3, 0.05);
  auto e = build(load_stretching, R"({"type":"stretching","stiffness":7})", m);
  for (unsigned seed = 1; seed <= 4; ++seed) expect_psd(*e, perturbed(rigid(m.rest, 0.25 * seed), 0.2, seed));
  // Compressed (every σ < 1): the true Hessian is indefinite, the projection is not.
  const Matrix3Xd squeezed = perturbed(rigid(m.rest, 0.6), 0.01, 9);
  EXPECT_LT(min_eigenvalue(fd_hessian(*e, squeezed)), -1e-3);
  expect_psd(*e, squeezed);
}

/// The symmetric matrix with `H`'s eigenvalues clamped at 0 (the numerical reference).
MatrixXd projected(const MatrixXd& H) {
  const Eigen::SelfAdjointEigenSolver<MatrixXd> es(H);
  return es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() * es.eigenvectors().transpose();
}

TEST(Stretching, ClosedFormEqualsTheNumericalProjectionInFSpace) {
  // One rest triangle with D_m = I: with x0 = 0 the columns of F are x1 and x2, so the
  // Hessian's (x1, x2) block is the F-space Hessian, whose eigenvalue clamping the closed
  // form must reproduce in compressed, mixed and stretched states.
  Model m;
  m.rest.setZero(3, 3);
  m.rest(0, 1) = 1;
  m.rest(1, 2) = 1;
  m.triangles = Eigen::Vector3i(0, 1, 2);
  m.mass = Eigen::VectorXd::Ones(3);
  auto e = build(load_stretching, R"({"type":"stretching","stiffness":3})", m);
  for (unsigned seed = 1; seed <= 6; ++seed)
    for (double s : {0.4, 0.8, 1.1, 1.6}) {
      Matrix3Xd x = perturbed(rigid(m.rest, s), 0.15, seed);
      x.col(1) -= x.col(0);
      x.col(2) -= x.col(0);
      x.col(0).setZero();
      const MatrixXd H = hessian(*e, x).bottomRightCorner(6, 6);
      const MatrixXd P = projected(fd_hessian(*e, x).bottomRightCorner(6, 6));
      EXPECT_LT(rel_error(H, P), 1e-5) << "scale " << s << " seed " << seed;
    }
}

TEST(Stretching, DegenerateTrianglesStayFinite) {
  const Model m = cloth(2, 2);
  auto e = build(load_stretching, R"({"type":"stretching","stiffness":7})", m);
  Matrix3Xd line = m.rest;
  line.row(1).setZero();                                // every triangle flattened onto a line: σ₂ = 0
  Matrix3Xd point = Matrix3Xd::Zero(3, m.rest.cols());  // F = 0
  for (const Matrix3Xd& x : {line, point}) {
    EXPECT_TRUE(std::isfinite(energy(*e, x)));
    EXPECT_TRUE(gradient(*e, x).allFinite());
    expect_psd(*e, x);
  }
  // F = 0: E = μ Σ 2A
  EXPECT_NEAR(energy(*e, point), 7 * 2 * 1.0, 1e-12);
}

TEST(Stretching, BadParameters) {
  const Model m = cloth();
  EXPECT_EQ(error_at(load_stretching, R"({"type":"stretching","stiffness":-1})", m), "effects[0].stiffness");
  EXPECT_EQ(error_at(load_stretching, R"({"type":"stretching"})", m), "effects[0].stiffness");
  EXPECT_EQ(error_at(load_stretching, R"({"type":"stretching","stiffness":1,"model":"neo"})", m), "effects[0].model");
  EXPECT_EQ(error_at(load_stretching, R"({"type":"stretching","stifness":1})", m), "effects[0].stifness");
  Model flat = cloth(1, 1);
  flat.rest.col(3) = flat.rest.col(0);  // a zero-area rest triangle
  EXPECT_EQ(error_at(load_stretching, R"({"type":"stretching","stiffness":1})", flat), "effects[0]");
}

// --- bending ----------------------------------------------------------------------------

TEST(Bending, HingesOfTheGrid) {
  const Model m = cloth(3, 3);
  auto e = build(load_bending, R"({"type":"bending","stiffness":1})", m);
  EffectCounters c;
  e->report(c);
  EXPECT_EQ(c.at("hinges"), 33 - 12);  // interior edges: all 33 minus the 12 on the boundary
  EXPECT_NEAR(energy(*e, m.rest), 0.0, 1e-30);
}

TEST(Bending, GradientMatchesFiniteDifferences) {
  const Model m = cloth(3, 3, 0.1);
  auto e = build(load_bending, R"({"type":"bending","stiffness":0.3})", m);
  for (unsigned seed = 1; seed <= 4; ++seed) expect_gradient_matches(*e, perturbed(m.rest, 0.08, seed));
}

TEST(Bending, HessianIsExactAtTheRestAngle) {
  const Model m = cloth(3, 3, 0.1);
  auto e = build(load_bending, R"({"type":"bending","stiffness":0.3})", m);
  const Matrix3Xd x = rigid(m.rest);
  EXPECT_NEAR(energy(*e, x), 0.0, 1e-20);
  expect_hessian_matches(*e, x);
  expect_psd(*e, x);
}

TEST(Bending, EnergyOfAKnownFold) {
  // Two triangles folded by 90° about their shared diagonal: E = k (π/2)² 3|e|²/(A₁ + A₂).
  Model m = cloth(1, 1);
  auto e = build(load_bending, R"({"type":"bending","stiffness":2})", m);
  ASSERT_EQ(m.triangles.cols(), 2);
  // Find the shared edge and the wings, then rotate one wing about the edge by 90°.
  int shared[2], n = 0, wing = -1;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (m.triangles(a, 0) == m.triangles(b, 1)) shared[n++] = m.triangles(a, 0);
  for (int b = 0; b < 3; ++b)
    if (m.triangles(b, 1) != shared[0] && m.triangles(b, 1) != shared[1]) wing = m.triangles(b, 1);
  const Eigen::Vector3d p = m.rest.col(shared[0]), axis = (m.rest.col(shared[1]) - p).normalized();
  Matrix3Xd x = m.rest;
  x.col(wing) = p + Eigen::AngleAxisd(M_PI / 2, axis) * (m.rest.col(wing) - p);
  const double len2 = (m.rest.col(shared[1]) - p).squaredNorm();
  EXPECT_NEAR(energy(*e, x), 2 * (M_PI / 2) * (M_PI / 2) * 3 * len2 / 1.0, 1e-12);
  expect_gradient_matches(*e, x);
}

TEST(Bending, HessianIsPsdAndDegenerateHingesStayFinite) {
  const Model m = cloth(3, 3, 0.1);
  auto e = build(load_bending, R"({"type":"bending","stiffness":0.3})", m);
  for (unsigned seed = 1; seed <= 3; ++seed) expect_psd(*e, perturbed(m.rest, 0.3, seed));
  Matrix3Xd x = m.rest;
  x.col(5) = x.col(6);  // collapses the triangles around the edge (5, 6)
  EXPECT_TRUE(std::isfinite(energy(*e, x)));
  EXPECT_TRUE(gradient(*e, x).allFinite());
  expect_psd(*e, x);
  EffectCounters c;
  e->report(c);
  EXPECT_GT(c.at("degenerate_hinges"), 0);
}

TEST(Bending, BadParameters) {
  const Model m = cloth();
  EXPECT_EQ(error_at(load_bending, R"({"type":"bending","stiffness":0})", m), "effects[0].stiffness");
  EXPECT_EQ(error_at(load_bending, R"({"type":"bending","stiffness":"1"})", m), "effects[0].stiffness");
  EXPECT_EQ(error_at(load_bending, R"({"type":"bending","stiffness":1,"rest_angle":0})", m), "effects[0].rest_angle");
}

// --- strand stretching ------------------------------------------------------------------

TEST(StrandStretching, GradientHessianAndProjection) {
  const Model m = hair(2, 4, 0.05);
  auto e = build(load_strand_stretching, R"({"type":"strand_stretching","stiffness":50})", m);
  EXPECT_NEAR(energy(*e, rigid(m.rest)), 0.0, 1e-20);
  for (unsigned seed = 1; seed <= 3; ++seed) expect_gradient_matches(*e, perturbed(m.rest, 0.05, seed));
  expect_hessian_matches(*e, perturbed(rigid(m.rest, 1.3), 0.005, 4));  // every segment stretched: exact
  const Matrix3Xd squeezed = perturbed(rigid(m.rest, 0.7), 0.005, 5);
  EXPECT_LT(min_eigenvalue(fd_hessian(*e, squeezed)), -1e-3);
  expect_psd(*e, squeezed);
  // A segment of zero current length: finite.
  Matrix3Xd x = m.rest;
  x.col(1) = x.col(0);
  EXPECT_TRUE(gradient(*e, x).allFinite());
  expect_psd(*e, x);
  // One segment stretched by 10 %: E = ½ k (0.1 L)²/L.
  Model one = hair(1, 1);
  auto s = build(load_strand_stretching, R"({"type":"strand_stretching","stiffness":50})", one);
  EXPECT_NEAR(energy(*s, one.rest * 1.1), 0.5 * 50 * 0.01, 1e-12);
}

TEST(StrandStretching, BadParameters) {
  const Model m = hair();
  EXPECT_EQ(error_at(load_strand_stretching, R"({"type":"strand_stretching","stiffness":-3})", m),
            "effects[0].stiffness");
  EXPECT_EQ(error_at(load_strand_stretching, R"({"type":"strand_stretching","k":3})", m), "effects[0].k");
}

// --- strand bending ---------------------------------------------------------------------

TEST(StrandBending, JointsGradientAndExactHessianAtRest) {
  const Model m = hair(2, 5, 0.05);
  auto e = build(load_strand_bending, R"({"type":"strand_bending","stiffness":0.01})", m);
  EffectCounters c;
  e->report(c);
  EXPECT_EQ(c.at("joints"), 2 * 4);
  EXPECT_NEAR(energy(*e, rigid(m.rest)), 0.0, 1e-20);
  for (unsigned seed = 1; seed <= 3; ++seed) expect_gradient_matches(*e, perturbed(m.rest, 0.03, seed));
  expect_hessian_matches(*e, rigid(m.rest));
  for (unsigned seed = 1; seed <= 3; ++seed) expect_psd(*e, perturbed(m.rest, 0.1, seed));
}

TEST(StrandBending, KnownAngle) {
  // Three vertices with a right angle, rest straight: E = k (π/2)²/ℓ̄.
  Model m = hair(1, 2);
  auto e = build(load_strand_bending, R"({"type":"strand_bending","stiffness":0.5})", m);
  Matrix3Xd x = m.rest;
  const double L = (m.rest.col(1) - m.rest.col(0)).norm();
  x.col(2) = x.col(1) + Eigen::Vector3d(L, 0, 0);
  EXPECT_NEAR(energy(*e, x), 0.5 * (M_PI / 2) * (M_PI / 2) / L, 1e-12);
  expect_gradient_matches(*e, x);
}

TEST(StrandBending, StraightStrandsStayFiniteAndStiffBothWays) {
  const Model straight = hair(1, 4);
  auto e = build(load_strand_bending, R"({"type":"strand_bending","stiffness":0.01})", straight);
  // Exactly straight at rest: zero gradient, finite Hessian, stiff in both transverse
  // directions (the Hessian of k φ²/ℓ̄ is isotropic about the tangent there).
  EXPECT_EQ(gradient(*e, straight.rest).norm(), 0.0);
  const MatrixXd H = hessian(*e, straight.rest);
  ASSERT_TRUE(H.allFinite());
  const Eigen::Index mid = 3 * 2;  // vertex 2, a middle joint
  EXPECT_NEAR(H(mid, mid), H(mid + 1, mid + 1), 1e-12 * H.norm());
  EXPECT_GT(H(mid, mid), 0);
  // Nearly straight: the Hessian agrees with finite differences up to the dropped in-plane
  // term, O(φ).
  const Matrix3Xd bent = perturbed(straight.rest, 1e-4, 3);
  expect_gradient_matches(*e, bent, 1e-4);
  EXPECT_LT(rel_error(hessian(*e, bent), fd_hessian(*e, bent, 1e-7)), 2e-2);
  // Curly rest shape, straight current shape (φ = 0 ≠ φ₀): the direction of ∇φ is not
  // defined; gradient and Hessian stay finite.
  const Model curly = hair(1, 4, 0.05);
  auto f = build(load_strand_bending, R"({"type":"strand_bending","stiffness":0.01})", curly);
  EXPECT_TRUE(gradient(*f, straight.rest).allFinite());
  expect_psd(*f, straight.rest);
  // Folded back onto itself (φ = π).
  Matrix3Xd folded = straight.rest;
  folded.col(2) = folded.col(0);
  EXPECT_TRUE(gradient(*e, folded).allFinite());
  expect_psd(*e, folded);
}

TEST(StrandBending, BadParameters) {
  const Model m = hair();
  EXPECT_EQ(error_at(load_strand_bending, R"({"type":"strand_bending","stiffness":-1})", m), "effects[0].stiffness");
  EXPECT_EQ(error_at(load_strand_bending, R"({"type":"strand_bending","stiffness":1,"rest":0})", m), "effects[0].rest");
}

// --- pins -------------------------------------------------------------------------------

TEST(Pins, EnergyGradientHessianAndRelease) {
  const Model m = cloth(3, 3);
  auto e = build(load_pins,
                 R"({"type":"pins","stiffness":100,"groups":[{"vertices":[0,3]},
                     {"box":{"min":[-1,0.4,-1],"max":[1,1,1]},"release_frame":3}]})",
                 m);
  EffectCounters c;
  e->report(c);
  EXPECT_EQ(c.at("pinned_vertices"), 2 + 4);  // the top row y = 0.5 has 4 vertices
  const Matrix3Xd x = perturbed(m.rest, 0.1, 2);
  double expected = 0;
  for (int i : {0, 3, 12, 13, 14, 15}) expected += 50 * (x.col(i) - m.rest.col(i)).squaredNorm();
  EXPECT_NEAR(energy(*e, x), expected, 1e-12);
  expect_gradient_matches(*e, x);
  expect_hessian_matches(*e, x);
  StepContext step;
  step.frame = 2;
  e->begin_step(step);
  EXPECT_NEAR(energy(*e, x), expected, 1e-12);
  step.frame = 3;  // released from frame 3 on
  e->begin_step(step);
  e->report(c);
  EXPECT_EQ(c.at("pinned_vertices"), 2);
  EXPECT_NEAR(energy(*e, x), 50 * ((x.col(0) - m.rest.col(0)).squaredNorm() + (x.col(3) - m.rest.col(3)).squaredNorm()),
              1e-12);
  expect_hessian_matches(*e, x);
}

TEST(Pins, MovingGroupFollowsItsMotionAtTheEndOfTheStep) {
  // Vertices 0 and 3 (the bottom corners, (-0.5,-0.5) and (0.5,-0.5) at z = 0) turn about
  // their midpoint (0,-0.5,0) at π/2 rad/s about +y and move +z at 0.2 m/s, from t = 1 s
  // to t = 3 s; vertex 12 is pinned in place.
  const Model m = cloth(3, 3);
  auto e = build(load_pins,
                 R"({"type":"pins","stiffness":100,"groups":[{"vertices":[12]},
                     {"vertices":[0,3],"motion":{"angular_velocity":[0,1.5707963267948966,0],
                      "velocity":[0,0,0.2],"start":1,"stop":3}}]})",
                 m);
  StepContext step;
  const auto target_gradient = [&](double t) {
    step.time = t;
    e->begin_step(step);
    Matrix3Xd g = Matrix3Xd::Zero(3, m.rest.cols());
    e->evaluate(m.rest, &g, nullptr);      // at the rest shape, ∇ᵢE = k (x̄ᵢ − x̂ᵢ)
    return Matrix3Xd(m.rest - g / 100.0);  // x̂ for pinned vertices
  };
  Matrix3Xd x_hat = target_gradient(0.5);  // before start: the rest positions
  EXPECT_LT((x_hat - m.rest).norm(), 1e-15);
  x_hat = target_gradient(2.0);  // a quarter turn about +y (x → −z), 0.2 m up
  EXPECT_LT((x_hat.col(0) - Eigen::Vector3d(0, -0.5, 0.5 + 0.2)).norm(), 1e-12);
  EXPECT_LT((x_hat.col(3) - Eigen::Vector3d(0, -0.5, -0.5 + 0.2)).norm(), 1e-12);
  EXPECT_LT((x_hat.col(12) - m.rest.col(12)).norm(), 1e-15);
  x_hat = target_gradient(10.0);  // frozen after stop: half a turn, 0.4 m up
  EXPECT_LT((x_hat.col(0) - Eigen::Vector3d(0.5, -0.5, 0.4)).norm(), 1e-12);
  const Matrix3Xd x = perturbed(m.rest, 0.1, 5);
  expect_gradient_matches(*e, x);
  expect_hessian_matches(*e, x);
  // an explicit centre
  auto c = build(load_pins, R"({"type":"pins","stiffness":100,"groups":[{"vertices":[0],
                     "motion":{"angular_velocity":[0,0,3.141592653589793],"center":[0,0,0]}}]})",
                 m);
  step.time = 1.0;  // half a turn about z through the origin: (-0.5,-0.5) → (0.5,0.5)
  c->begin_step(step);
  Matrix3Xd g = Matrix3Xd::Zero(3, m.rest.cols());
  c->evaluate(m.rest, &g, nullptr);
  EXPECT_LT((m.rest.col(0) - g.col(0) / 100.0 - Eigen::Vector3d(0.5, 0.5, 0)).norm(), 1e-12);
}

TEST(Pins, KeyframedGroupFollowsItsKeyframesAtTheEndOfTheStep) {
  // Vertices 0 and 3 (the bottom corners, (−0.5, −0.5, 0) and (0.5, −0.5, 0)) are at rest
  // until t = 1 s and by t = 3 s have turned a quarter turn about +y about their midpoint
  // c = (0, −0.5, 0) and moved 0.4 m up; vertex 12 is pinned in place.
  const Model m = cloth(3, 3);
  const std::string keys = R"("keyframes":[{"time":1},
      {"time":3,"translation":[0,0,0.4],"rotation":{"axis":[0,1,0],"degrees":90}}])";
  for (const char* how : {"linear", "smooth"}) {
    SCOPED_TRACE(how);
    auto e = build(load_pins,
                   R"({"type":"pins","stiffness":100,"groups":[{"vertices":[12]},
                       {"vertices":[0,3],"motion":{"interpolation":")" +
                       std::string(how) + "\"," + keys + "}}]}",
                   m);
    StepContext step;
    const auto targets = [&](double t) {
      step.time = t;
      e->begin_step(step);
      Matrix3Xd g = Matrix3Xd::Zero(3, m.rest.cols());
      e->evaluate(m.rest, &g, nullptr);      // at the rest shape, ∇ᵢE = k (x̄ᵢ − x̂ᵢ)
      return Matrix3Xd(m.rest - g / 100.0);  // x̂ for pinned vertices
    };
    // The targets at time t after a fraction w of the segment: x̂ = c + w (0, 0, 0.4) +
    // Ry(w 90°)(x̄ − c), with x̄ − c = (∓0.5, 0, 0) and Ry(θ)(x, 0, 0) = (x cos θ, 0, −x sin θ).
    const auto expect_at = [&](double t, double w) {
      const Matrix3Xd x_hat = targets(t);
      const double a = w * M_PI / 2, z = 0.4 * w;
      EXPECT_LT((x_hat.col(0) - Eigen::Vector3d(-0.5 * std::cos(a), -0.5, z + 0.5 * std::sin(a))).norm(), 1e-12)
          << "t " << t;
      EXPECT_LT((x_hat.col(3) - Eigen::Vector3d(0.5 * std::cos(a), -0.5, z - 0.5 * std::sin(a))).norm(), 1e-12)
          << "t " << t;
      EXPECT_LT((x_hat.col(12) - m.rest.col(12)).norm(), 1e-15);
    };
    const bool linear = std::string(how) == "linear";
    expect_at(0.5, 0);  // before the first keyframe: its pose, the rest pose
    expect_at(1.0, 0);
    expect_at(1.5, linear ? 0.25 : 0.15625);  // s(¼) = 3/16 − 2/64
    expect_at(2.0, 0.5);
    expect_at(2.5, linear ? 0.75 : 0.84375);
    expect_at(3.0, 1);
    expect_at(10.0, 1);  // after the last: it holds
    const Matrix3Xd x = perturbed(m.rest, 0.1, 5);
    expect_gradient_matches(*e, x);
    expect_hessian_matches(*e, x);
  }
  // An explicit centre: vertex 0 turns a quarter turn about z through the origin in 1 s,
  // smoothly; half way it has turned 45°: (−0.5, −0.5) → (0, −√½).
  auto c = build(load_pins, R"({"type":"pins","stiffness":100,"groups":[{"vertices":[0],
                     "motion":{"center":[0,0,0],"interpolation":"smooth","keyframes":[{"time":0},
                     {"time":1,"rotation":{"axis":[0,0,1],"degrees":90}}]}}]})",
                 m);
  StepContext step;
  step.time = 0.5;
  c->begin_step(step);
  Matrix3Xd g = Matrix3Xd::Zero(3, m.rest.cols());
  c->evaluate(m.rest, &g, nullptr);
  EXPECT_LT((m.rest.col(0) - g.col(0) / 100.0 - Eigen::Vector3d(0, -std::sqrt(0.5), 0)).norm(), 1e-12);
}

TEST(Pins, KeyframedEdgeLiftsAHangingSheetThatFollows) {
  // A 0.4 m square sheet under gravity, pinned along its edge x = −0.2 (9 vertices) by a
  // group that is grabbed and lifted: by t = 0.5 s its targets have risen 0.2 m and turned
  // 20° about x through the edge's centre c = (−0.2, 0, 0) (smooth, from rest at t = 0), then
  // they hold. The same run with the group left in place is the reference.
  nlohmann::json scene = nlohmann::json::parse(R"({
    "dt": 0.02, "frames": 75,
    "meshes": [{"name": "sheet", "generator": {"type": "grid", "width": 0.4, "height": 0.4, "nx": 8, "ny": 8}}],
    "effects": [{"type": "gravity"}, {"type": "stretching", "stiffness": 50}, {"type": "bending", "stiffness": 1e-4},
                {"type": "damping", "coefficient": 2},
                {"type": "pins", "stiffness": 1e4, "groups": [{"box": {"min": [-1, -1, -1], "max": [-0.19, 1, 1]},
                  "motion": {"interpolation": "smooth", "keyframes": [{"time": 0},
                    {"time": 0.5, "translation": [0, 0, 0.2], "rotation": {"axis": [1, 0, 0], "degrees": 20}}]}}]}]
  })");
  const Eigen::Vector3d c(-0.2, 0, 0);
  const auto target = [&](const Eigen::Vector3d& rest, double t) {
    const double u = std::min(t / 0.5, 1.0), w = u * u * (3 - 2 * u);
    return Eigen::Vector3d(c + Eigen::Vector3d(0, 0, 0.2 * w) +
                           Eigen::AngleAxisd(w * 20 * M_PI / 180, Eigen::Vector3d::UnitX()) * (rest - c));
  };
  auto lifted = load_scene_text(scene.dump(), "lift.json", PCE_TEST_TMP);
  scene["effects"][4]["groups"][0].erase("motion");
  auto still = load_scene_text(scene.dump(), "still.json", PCE_TEST_TMP);
  Simulation& a = lifted->simulation;
  Simulation& b = still->simulation;
  const Model& model = a.model;
  std::vector<int> pinned, free;
  for (int i = 0; i < model.vertex_count(); ++i) (model.rest(0, i) < -0.19 ? pinned : free).push_back(i);
  ASSERT_EQ(pinned.size(), 9u);
  // The pins' give: a pinned vertex is off its target by its force over k; no pin carries
  // more than the whole sheet's weight once the lift has stopped.
  const double weight = model.mass.sum() * 9.81, k = 1e4;
  for (int f = 1; f <= 75; ++f) {
    a.step();
    b.step();
    if (f != 12 && f != 25 && f != 75) continue;
    double off = 0;
    for (int i : pinned) off = std::max(off, (a.x.col(i) - target(model.rest.col(i), a.time)).norm());
    std::printf("frame %d (t = %.2f s): pinned vertices at most %.3g m off their targets\n", f, a.time, off);
    EXPECT_LT(off, (f == 75 ? 1 : 4) * weight / k) << "frame " << f;
  }
  ASSERT_TRUE(a.x.allFinite());
  // The sheet follows: every free vertex ends higher than in the reference run, by 0.2 m on
  // average (the edge's centre rose 0.2 m and the sheet hangs from it), and the sheet hangs
  // below its lifted edge.
  double rise = 0, least = 1;
  for (int i : free) {
    const double dz = a.x(2, i) - b.x(2, i);
    rise += dz / static_cast<double>(free.size());
    least = std::min(least, dz);
    EXPECT_LT(a.x(2, i), 0.2 + 0.2 * std::sin(20 * M_PI / 180)) << "vertex " << i;
  }
  std::printf("free vertices rose %.4f m on average, at least %.4f m\n", rise, least);
  EXPECT_NEAR(rise, 0.2, 0.03);
  EXPECT_GT(least, 0.1);
  // The reference's edge stayed where it was pinned.
  for (int i : pinned) EXPECT_LT((b.x.col(i) - model.rest.col(i)).norm(), weight / k);
}

TEST(Pins, TargetsSetBetweenStepsReplaceRestAndMotionFromTheNextStep) {
  // Group 0 (vertex 12) is pinned in place, group 1 (vertices 0 and 3) moves +z at 1 m/s,
  // group 2 (vertex 5) is released at frame 3. Targets set through PinsEffect replace a
  // group's rest positions or motion from the next begin_step on, until cleared.
  const Model m = cloth(3, 3);
  auto e = build(load_pins,
                 R"({"type":"pins","stiffness":100,"groups":[{"vertices":[12]},
                     {"vertices":[0,3],"motion":{"velocity":[0,0,1]}},{"vertices":[5],"release_frame":3}]})",
                 m);
  auto* pins = dynamic_cast<PinsEffect*>(e.get());
  ASSERT_NE(pins, nullptr);
  ASSERT_EQ(pins->group_count(), 3);
  EXPECT_EQ(pins->group_vertices(1), (std::vector<int>{0, 3}));
  StepContext step;
  step.frame = 1;
  const auto targets = [&](double t) {  // x̂ from the gradient at the rest shape (to rounding), after begin_step at t
    step.time = t;
    e->begin_step(step);
    Matrix3Xd g = Matrix3Xd::Zero(3, m.rest.cols());
    e->evaluate(m.rest, &g, nullptr);
    return Matrix3Xd(m.rest - g / 100.0);
  };
  const Eigen::Vector3d up(0, 0, 2);
  Matrix3Xd x_hat = targets(2.0);
  EXPECT_LT((x_hat.col(12) - (m.rest.col(12))).norm(), 1e-14);
  EXPECT_LT((x_hat.col(0) - (m.rest.col(0) + up)).norm(), 1e-14);
  Matrix3Xd set0(3, 1), set1(3, 2);
  set0 << 1, 2, 3;
  set1 << 0.1, 0.2, 0.3, 0.4, 0.5, 0.6;
  pins->set_targets(0, set0);
  pins->set_targets(1, set1);
  EXPECT_EQ(pins->group_targets(0), set0);  // the ones set, before any step uses them
  x_hat = targets(3.0);
  EXPECT_LT((x_hat.col(12) - (set0.col(0))).norm(), 1e-14);
  EXPECT_LT((x_hat.col(0) - (set1.col(0))).norm(), 1e-14);
  EXPECT_LT((x_hat.col(3) - (set1.col(1))).norm(), 1e-14);
  EXPECT_LT((x_hat.col(5) - (m.rest.col(5))).norm(), 1e-14);
  EXPECT_EQ(pins->group_targets(1), set1);
  const Matrix3Xd x = perturbed(m.rest, 0.1, 3);
  expect_gradient_matches(*e, x);
  expect_hessian_matches(*e, x);
  // Cleared: the rest position and the motion (at the new time) again.
  pins->clear_targets(0);
  pins->clear_targets(1);
  x_hat = targets(4.0);
  EXPECT_LT((x_hat.col(12) - (m.rest.col(12))).norm(), 1e-14);
  EXPECT_LT((x_hat.col(0) - (m.rest.col(0) + 2 * up)).norm(), 1e-14);
  EXPECT_EQ(pins->group_targets(0).col(0), m.rest.col(12));
  // A released group stays released with targets set.
  pins->set_targets(2, set0);
  step.frame = 3;
  e->begin_step(step);
  EffectCounters c;
  e->report(c);
  EXPECT_EQ(c.at("pinned_vertices"), 3);
  // Errors name the argument.
  const auto field_of = [&](const std::function<void()>& call) {
    try {
      call();
    } catch (const ArgumentError& err) {
      return err.field() + ": " + err.expected();
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(field_of([&] { pins->set_targets(3, set0); }), "group: expected a pin group index in [0, 3), got 3");
  EXPECT_EQ(field_of([&] { pins->clear_targets(-1); }), "group: expected a pin group index in [0, 3), got -1");
  EXPECT_EQ(field_of([&] { pins->group_vertices(7); }), "group: expected a pin group index in [0, 3), got 7");
  EXPECT_EQ(field_of([&] { pins->set_targets(1, set0); }),
            "targets: expected one target per vertex of group 1 (2), got 1");
  Matrix3Xd bad = set1;
  bad(2, 1) = std::nan("");
  EXPECT_EQ(field_of([&] { pins->set_targets(1, bad); }).rfind("targets[1]: ", 0), 0u);
  bad(2, 1) = 2e6;
  EXPECT_EQ(field_of([&] { pins->set_targets(1, bad); }).rfind("targets[1]: ", 0), 0u);
  Matrix3Xd kept(3, 2);  // the bad ones were not kept: the motion's of the last begin_step
  kept << m.rest.col(0) + 2 * up, m.rest.col(3) + 2 * up;
  EXPECT_EQ(pins->group_targets(1), kept);
}

TEST(Pins, MeshLocalIndicesAndDefaultStiffness) {
  Model m = cloth(1, 1);  // 4 vertices, then a second mesh of 2 more
  m.rest.conservativeResize(3, 6);
  m.rest.col(4) << 5, 5, 5;
  m.rest.col(5) << 6, 6, 6;
  m.mass = Eigen::VectorXd::Ones(6);
  m.meshes.push_back({"other", 4, 2, 2, 0, 0, 0});
  auto e = build(load_pins, R"({"type":"pins","groups":[{"mesh":"other","vertices":[1]}]})", m);
  Matrix3Xd x = m.rest;
  x(0, 5) += 0.01;
  EXPECT_NEAR(energy(*e, x), 0.5 * 1e5 * 1e-4, 1e-9);
  auto b = build(load_pins, R"({"type":"pins","groups":[{"mesh":"other","box":{"min":[0,0,0],"max":[9,9,9]}}]})", m);
  EffectCounters c;
  b->report(c);
  EXPECT_EQ(c.at("pinned_vertices"), 2);
}

TEST(Pins, BadParameters) {
  const Model m = cloth(1, 1);
  EXPECT_EQ(error_at(load_pins, R"({"type":"pins","groups":[{"vertices":[0,4]}]})", m),
            "effects[0].groups[0].vertices[1]");
  EXPECT_EQ(
      error_at(load_pins, R"({"type":"pins","groups":[{"vertices":[0]},{"box":{"min":[5,5,5],"max":[6,6,6]}}]})", m),
      "effects[0].groups[1].box");
  EXPECT_EQ(error_at(load_pins, R"({"type":"pins","stiffness":-1,"groups":[{"vertices":[0]}]})", m),
            "effects[0].stiffness");
  EXPECT_EQ(error_at(load_pins, R"({"type":"pins","groups":[{"vertices":[0],"release_frame":0}]})", m),
            "effects[0].groups[0].release_frame");
  EXPECT_EQ(error_at(load_pins, R"({"type":"pins","groups":[{"vertices":[0],"mesh":"nope"}]})", m),
            "effects[0].groups[0].mesh");
  EXPECT_EQ(
      error_at(load_pins, R"({"type":"pins","groups":[{"vertices":[0],"box":{"min":[0,0,0],"max":[1,1,1]}}]})", m),
      "effects[0].groups[0].box");
  EXPECT_EQ(error_at(load_pins, R"({"type":"pins","groups":[{"vertex":[0]}]})", m), "effects[0].groups[0].vertex");
  EXPECT_EQ(error_at(load_pins, R"({"type":"pins","groups":[{"box":{"min":[1,0,0],"max":[0,1,1]}}]})", m),
            "effects[0].groups[0].box.max");
  EXPECT_EQ(error_at(load_pins, R"({"type":"pins","groups":[{"vertices":[0],"motion":{"start":2,"stop":1}}]})", m),
            "effects[0].groups[0].motion.stop");
  EXPECT_EQ(error_at(load_pins, R"({"type":"pins","groups":[{"vertices":[0],"motion":{"centre":[0,0,0]}}]})", m),
            "effects[0].groups[0].motion.centre");
  EXPECT_EQ(error_at(load_pins, R"({"type":"pins","groups":[{"vertices":[0],"motion":{"velocity":[0,"a",0]}}]})", m),
            "effects[0].groups[0].motion.velocity");
  EXPECT_EQ(error_at(load_pins, R"({"type":"pins","groups":[]})", m), "effects[0].groups");
  EXPECT_EQ(error_at(load_pins, R"({"type":"pins"})", m), "effects[0].groups");
}

// --- damping ----------------------------------------------------------------------------

TEST(Damping, DragOnTheStepVelocity) {
  Model m = cloth(2, 2);
  m.mass.setLinSpaced(m.mass.size(), 1.0, 3.0);
  auto e = build(load_damping, R"({"type":"damping","coefficient":0.5})", m);
  const Matrix3Xd start = perturbed(m.rest, 0.1, 7);
  StepContext step;
  step.frame = 1;
  step.dt = 0.02;
  step.x_start = &start;
  e->begin_step(step);
  const Matrix3Xd x = perturbed(start, 0.01, 8);
  // Force = −c m v with v = (x − xⁿ)/h.
  const Matrix3Xd g = gradient(*e, x);
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    EXPECT_LT((g.col(i) - 0.5 * m.mass[i] * (x.col(i) - start.col(i)) / 0.02).norm(), 1e-12);
  expect_gradient_matches(*e, x);
  expect_hessian_matches(*e, x);
  auto none = build(load_damping, R"({"type":"damping","coefficient":0})", m);
  EXPECT_EQ(energy(*none, x), 0.0);
}

TEST(Damping, BadParameters) {
  const Model m = cloth(1, 1);
  EXPECT_EQ(error_at(load_damping, R"({"type":"damping","coefficient":-0.1})", m), "effects[0].coefficient");
  EXPECT_EQ(error_at(load_damping, R"({"type":"damping","coeff":0.1})", m), "effects[0].coeff");
}

// --- all together: one pattern covers every effect's blocks ----------------------------

TEST(Effects, SharedPatternCoversEverything) {
  const Model m = cloth(4, 3, 0.05);
  std::vector<std::unique_ptr<Effect>> effects;
  effects.push_back(build(load_gravity, R"({"type":"gravity"})", m));
  effects.push_back(build(load_stretching, R"({"type":"stretching","stiffness":5})", m));
  effects.push_back(build(load_bending, R"({"type":"bending","stiffness":0.1})", m));
  effects.push_back(build(load_pins, R"({"type":"pins","groups":[{"vertices":[0,4]}]})", m));
  effects.push_back(build(load_damping, R"({"type":"damping","coefficient":1})", m));
  Pattern pattern;
  for (const auto& e : effects) e->declare(pattern);
  BlockHessian H;
  H.set_pattern(m.vertex_count(), pattern);
  H.set_zero();
  const Matrix3Xd x = perturbed(m.rest, 0.05, 4);
  Matrix3Xd g = Matrix3Xd::Zero(3, x.cols());
  for (const auto& e : effects) EXPECT_NO_THROW(e->evaluate(x, &g, &H));
  EXPECT_TRUE(g.allFinite());
  EXPECT_GE(min_eigenvalue(dense(H)), -1e-9 * H.matrix().norm());
}

// --- microbenchmark (not run by ctest) -------------------------------------------------

/// Thread CPU seconds of `repeats` calls (the build machine is shared: wall time is not).
template <class F> double seconds(F&& f, int repeats) {
  const auto now = [] {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  };
  const double t0 = now();
  for (int r = 0; r < repeats; ++r) f();
  return now() - t0;
}

TEST(Effects, DISABLED_Timing) {
  const Model m = cloth(100, 100, 0.01);
  const Matrix3Xd x = perturbed(m.rest, 0.003, 1);
  for (const char* which : {"stretching", "bending"}) {
    const bool stretch = std::string(which) == "stretching";
    auto e = stretch ? build(load_stretching, R"({"type":"stretching","stiffness":5})", m)
                     : build(load_bending, R"({"type":"bending","stiffness":0.1})", m);
    Pattern pattern;
    e->declare(pattern);
    BlockHessian H;
    H.set_pattern(m.vertex_count(), pattern);
    Matrix3Xd g = Matrix3Xd::Zero(3, x.cols());
    EffectCounters c;
    e->report(c);
    const double elements = stretch ? static_cast<double>(m.triangles.cols()) : c.at("hinges");
    const int repeats = 50;
    double sink = 0;
    const double t_full = seconds([&] { sink += e->evaluate(x, &g, &H); }, repeats);
    const double t_gradient = seconds([&] { sink += e->evaluate(x, &g, nullptr); }, repeats);
    const double t_energy = seconds([&] { sink += e->evaluate(x, nullptr, nullptr); }, repeats);
    const double per = 1e9 / (repeats * elements);
    std::printf(
        "%s: %.0f elements, ns/element: energy+gradient+Hessian (assembled) %.1f, energy+gradient %.1f, energy %.1f "
        "(%g)\n",
        which, elements, t_full * per, t_gradient * per, t_energy * per, sink);
  }
}

}  // namespace

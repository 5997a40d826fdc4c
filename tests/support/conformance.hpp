// SPDX-License-Identifier: MIT
/// @file
/// Shared machinery of the conformance suite (one suite, run on every pair × length ×
/// penalty × scalar, as manif runs one Jacobian suite on every group): random active
/// configurations, scalar conversion, finite differences and error measures.
#pragma once

#include "eigensolvers.hpp"

#include <pce/pce.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <string>

namespace pce_test {

enum class PairKind { vertex_face, edge_edge };
enum class LengthKind { signed_positive, signed_negative, unsigned_ };
enum class PenaltyKind { quadratic, cubic, log_barrier, custom };

inline const char* name(PairKind p) { return p == PairKind::vertex_face ? "vertex_face" : "edge_edge"; }
inline const char* name(LengthKind l) {
  switch (l) {
    case LengthKind::signed_positive:
      return "signed_pos";
    case LengthKind::signed_negative:
      return "signed_neg";
    case LengthKind::unsigned_:
      return "unsigned";
  }
  return "?";
}
inline const char* name(PenaltyKind p) {
  switch (p) {
    case PenaltyKind::quadratic:
      return "quadratic";
    case PenaltyKind::cubic:
      return "cubic";
    case PenaltyKind::log_barrier:
      return "log_barrier";
    case PenaltyKind::custom:
      return "custom";
  }
  return "?";
}

/// A user-written penalty that the library has never seen: ψ = k sin(L/w) + k (L/w)³/6.
/// Deliberately non-convex (ψ″ changes sign), so the clamps on ψ″ are exercised.
struct WavyPenalty {
  double stiffness = 1.0;
  double width = 1.0;
  template <class Scalar> pce::PenaltyDerivatives<Scalar> evaluate(const Scalar& L) const {
    using std::cos;
    using std::sin;
    const Scalar k = Scalar(stiffness), w = Scalar(width), u = L / w;
    return {k * (sin(u) + u * u * u / Scalar(6)), k * (cos(u) + u * u / Scalar(2)) / w, k * (-sin(u) + u) / (w * w)};
  }
};

/// Runtime description of a penalty, instantiated for any scalar by `with_penalty`.
struct PenaltySpec {
  PenaltyKind kind;
  double stiffness, eps, delta, dhat, width;
};

template <class F> decltype(auto) with_penalty(const PenaltySpec& p, F&& f) {
  switch (p.kind) {
    case PenaltyKind::quadratic:
      return f(pce::QuadraticPenalty{p.stiffness, p.eps});
    case PenaltyKind::cubic:
      return f(pce::CubicPenalty{p.stiffness, p.eps, p.delta});
    case PenaltyKind::log_barrier:
      return f(pce::LogBarrierPenalty{p.stiffness, p.dhat});
    case PenaltyKind::custom:
      break;
  }
  return f(WavyPenalty{p.stiffness, p.width});
}

template <class F> decltype(auto) with_length(LengthKind l, F&& f) {
  switch (l) {
    case LengthKind::signed_positive:
      return f(pce::SignedLength{pce::Side::positive});
    case LengthKind::signed_negative:
      return f(pce::SignedLength{pce::Side::negative});
    case LengthKind::unsigned_:
      break;
  }
  return f(pce::UnsignedLength{});
}

template <class F> decltype(auto) with_pair(PairKind p, F&& f) {
  if (p == PairKind::vertex_face) return f(pce::VertexFace{});
  return f(pce::EdgeEdge{});
}

template <class To, class From> pce::Vec12<To> cast12(const pce::Vec12<From>& x) {
  pce::Vec12<To> y;
  for (int i = 0; i < 12; ++i) y[i] = To(x[i]);
  return y;
}

/// Max-abs of a matrix or vector, in double.
template <class Derived> double max_abs(const Eigen::MatrixBase<Derived>& m) {
  double r = 0;
  for (Eigen::Index j = 0; j < m.cols(); ++j)
    for (Eigen::Index i = 0; i < m.rows(); ++i) r = std::max(r, std::fabs(static_cast<double>(m(i, j))));
  return r;
}

/// ‖a − b‖_max / max(‖b‖_max, floor), computed in the precision of `b` (the reference).
template <class DA, class DB>
double rel_error(const Eigen::MatrixBase<DA>& a, const Eigen::MatrixBase<DB>& b, double floor = 1e-300) {
  using RS = typename DB::Scalar;
  double num = 0;
  for (Eigen::Index j = 0; j < b.cols(); ++j)
    for (Eigen::Index i = 0; i < b.rows(); ++i) {
      const RS d = RS(a(i, j)) - b(i, j);
      num = std::max(num, std::fabs(static_cast<double>(d)));
    }
  return num / std::max(max_abs(b), floor);
}

/// A random well-shaped configuration: primitives of size ~`scale`, angles ≥ ~15°, at
/// offset `offset` from the origin, with signed length l of the given sign and magnitude.
struct Configuration {
  pce::Vec12<double> x;
  double scale;
};

inline Eigen::Matrix3d random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> N(0, 1);
  Eigen::Quaterniond q(N(rng), N(rng), N(rng), N(rng));
  q.normalize();
  return q.toRotationMatrix();
}

/// Builds a pair in a local frame (plane z = 0 holds the triangle / the first edge and the
/// direction of the second), then rotates and offsets it.
inline Configuration random_configuration(PairKind kind, double l, double scale, double offset, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> U(0, 1);
  const double pi = 3.14159265358979323846;
  pce::Vec12<double> x;
  if (kind == PairKind::vertex_face) {
    // Triangle with angles bounded away from 0: corners on a circle at spread-out angles.
    const double a0 = U(rng) * 2 * pi;
    const double a1 = a0 + (0.6 + 0.9 * U(rng)) * pi * 2 / 3;
    const double a2 = a1 + (0.6 + 0.9 * U(rng)) * pi * 2 / 3;
    Eigen::Vector3d t0(std::cos(a0), std::sin(a0), 0), t1(std::cos(a1), std::sin(a1), 0),
        t2(std::cos(a2), std::sin(a2), 0);
    // Vertex over a random point (inside or outside the triangle) at height l: the
    // triangle t0,t1,t2 is counter-clockwise, so its right-hand normal is +z.
    Eigen::Vector3d p(2.4 * U(rng) - 1.2, 2.4 * U(rng) - 1.2, l / scale);
    x << p, t0, t1, t2;
  } else {
    const double th0 = U(rng) * pi;
    const double dth = (0.1 + 0.8 * U(rng)) * pi;  // angle between the edges in [18°, 162°]
    Eigen::Vector3d d0(std::cos(th0), std::sin(th0), 0), d1(std::cos(th0 + dth), std::sin(th0 + dth), 0);
    Eigen::Vector3d c0(U(rng) - 0.5, U(rng) - 0.5, 0), c1(U(rng) - 0.5, U(rng) - 0.5, 0);
    const double s0 = 0.5 + U(rng), s1 = 0.5 + U(rng);
    Eigen::Vector3d ea0 = c0 - s0 * 0.5 * d0, ea1 = c0 + s0 * 0.5 * d0;
    Eigen::Vector3d eb0 = c1 - s1 * 0.5 * d1, eb1 = c1 + s1 * 0.5 * d1;
    // n = (ea1 − ea0) × (eb1 − eb0) = +z·sin(dth) > 0; l = (eb0 − ea0)·n̂ = eb0.z − ea0.z.
    eb0.z() = eb1.z() = l / scale;
    x << ea0, ea1, eb0, eb1;
  }
  const Eigen::Matrix3d R = random_rotation(rng);
  Eigen::Vector3d shift(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5);
  shift = shift.normalized() * offset;
  for (int j = 0; j < 4; ++j) x.segment<3>(3 * j) = R * (scale * x.segment<3>(3 * j)) + shift;
  return {x, scale};
}

/// Central-difference gradient of `f` (Vec12 -> Scalar) at step h.
template <class S, class F> pce::Vec12<S> fd_gradient(F&& f, const pce::Vec12<S>& x, S h) {
  pce::Vec12<S> g;
  for (int i = 0; i < 12; ++i) {
    pce::Vec12<S> xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    g[i] = (f(xp) - f(xm)) / (xp[i] - xm[i]);
  }
  return g;
}

/// Central-difference Jacobian of `f` (Vec12 -> Vec12) at step h.
template <class S, class F> pce::Mat12<S> fd_jacobian(F&& f, const pce::Vec12<S>& x, S h) {
  pce::Mat12<S> J;
  for (int i = 0; i < 12; ++i) {
    pce::Vec12<S> xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    J.col(i) = (f(xp) - f(xm)) / (xp[i] - xm[i]);
  }
  return J;
}

}  // namespace pce_test

// SPDX-License-Identifier: MIT
/// @file
/// pce-probe: the templates of `evaluate_in<Scalar>` (`evaluate_scalar.hpp`), included only
/// by the translation unit of each scalar type. Dispatch of a request to `pce::evaluate<Pair>`
/// (or, with a "mollifier" field, `pce::mollified_pair_energy<Pair>`; with
/// "closest_feature": true, `pce::closest_feature_energy<Pair>`) for the requested pair,
/// length and penalty; conversion of the result to double; messages for non-ok statuses.
#pragma once

// GCC 12 at -O3 reports `-Wmaybe-uninitialized` inside `pce::closest_feature_energy`, where
// the library copies its local `ClosestFeatureEnergy` (whose unused members are
// uninitialized) to the output: a false positive located in the header, so it is silenced
// for the library's headers only, not for this file.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <pce/pce.hpp>
#pragma GCC diagnostic pop
#endif

#include "evaluate_messages.hpp"
#include "evaluate_scalar.hpp"

#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace pce_probe {

namespace detail {

/// The request's coordinates (`N` of them, checked by the parser) rounded to `Scalar`
/// (exact for double and long double).
template <class Scalar, int N> pce::VecN<Scalar, N> to_scalar(const std::vector<double>& x) {
  pce::VecN<Scalar, N> out;
  for (int i = 0; i < N; ++i) out[i] = static_cast<Scalar>(x.at(static_cast<std::size_t>(i)));
  return out;
}

/// Converts `v` to double into `out`; false if the result is not finite (a long double
/// beyond the double range).
template <class Scalar> bool store(const Scalar& v, double& out) {
  out = static_cast<double>(v);
  return std::isfinite(out);
}

/// The first `count` entries of `v` (all of them by default) as doubles.
template <class Scalar, int N>
bool store_vector(const Eigen::Matrix<Scalar, N, 1>& v, std::vector<double>& out, int count = N) {
  out.assign(static_cast<std::size_t>(count), 0.0);
  bool ok = true;
  for (int i = 0; i < count; ++i) ok = store(v[i], out[static_cast<std::size_t>(i)]) && ok;
  return ok;
}

/// Row-major copy of an N×N matrix.
template <class Scalar, int N> bool store_matrix(const pce::MatN<Scalar, N>& m, std::vector<double>& out) {
  out.assign(static_cast<std::size_t>(N * N), 0.0);
  bool ok = true;
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c) ok = store(m(r, c), out[static_cast<std::size_t>(N * r + c)]) && ok;
  return ok;
}

/// All outputs as doubles; false if any of them does not fit.
template <class Scalar, int Dofs, int FrameDofs>
bool to_evaluation(const pce::PairResult<Scalar, Dofs, FrameDofs>& r, Evaluation& e) {
  double length = 0;
  bool ok = store(r.length, length);
  e.length = length;
  ok = store(r.value, e.value) && ok;
  ok = store_vector<Scalar, Dofs>(r.gradient, e.gradient) && ok;
  ok = store_matrix<Scalar, Dofs>(r.hessian, e.hessian) && ok;
  ok = store_matrix<Scalar, Dofs>(r.projected_hessian, e.projected_hessian) && ok;
  ok = store_vector<Scalar, FrameDofs>(r.eigen.values, e.eigenvalues) && ok;
  return ok;
}

/// Which coordinate the library rejected (empty if none).
template <class Scalar, int N> std::string coordinate_problem(const Request& req, const pce::VecN<Scalar, N>& xs) {
  using std::abs;
  const Scalar lim = pce::Constants<Scalar>::max_coordinate();
  for (int i = 0; i < N; ++i) {
    if (std::isfinite(xs[i]) && !(abs(xs[i]) > lim)) continue;
    const double v = req.x[static_cast<std::size_t>(i)];
    std::string msg = "field \"x\"[" + std::to_string(i) + "] ";
    if (!std::isfinite(v)) return msg + "is too large to be represented as a double";
    msg += "= " + format_number(v) + " is beyond the largest accepted magnitude " + describe(static_cast<double>(lim));
    return msg + " for scalar \"" + to_string(req.scalar) + "\"";
  }
  return {};
}

template <class Penalty> std::string domain_message(const Penalty&, double L) {
  if constexpr (std::is_same_v<Penalty, pce::LogBarrierPenalty>)
    return "log barrier undefined at L <= 0 (L = " + describe(L) + ")";
  else
    return "penalty undefined at L = " + describe(L);
}

/// L at the request's coordinates (the frame exists whenever the status is out_of_domain).
template <class Pair, class Scalar, class Length>
double length_at(const pce::VecN<Scalar, Pair::dofs>& xs, const Length& len) {
  if constexpr (std::is_same_v<Pair, pce::PointEdge>) {
    pce::PointEdgeFrame<Scalar> f;
    return Pair::frame(xs, f) == pce::Status::ok ? static_cast<double>(f.d) : 0.0;
  } else if constexpr (std::is_same_v<Pair, pce::PointPoint>) {
    pce::PointPointFrame<Scalar> f;
    return Pair::frame(xs, f) == pce::Status::ok ? static_cast<double>(f.d) : 0.0;
  } else {
    pce::Frame<Scalar> f;
    if (Pair::frame(xs, f) != pce::Status::ok) return 0.0;
    return static_cast<double>(pce::length_value(f, len));
  }
}

/// The closest-feature distance at the request's coordinates: evaluated again with a
/// penalty that is zero and defined everywhere (a quadratic one with k = 0, an
/// instantiation every quadratic closest-feature request needs anyway).
template <class Pair, class Scalar> double closest_feature_length_at(const pce::Vec12<Scalar>& xs) {
  pce::QuadraticPenalty zero;
  zero.stiffness = 0.0;
  zero.eps = 0.0;
  pce::ClosestFeatureEnergy<Scalar> e;
  if (pce::closest_feature_energy<Pair>(xs, pce::UnsignedLength{}, zero, e) != pce::Status::ok) return 0.0;
  return static_cast<double>(e.length);
}

/// Human-readable explanation of a non-ok status.
template <class Pair, class Scalar, class Length, class Penalty>
std::string failure_message(pce::Status s, const Request& req, const pce::VecN<Scalar, Pair::dofs>& xs,
                            const Length& len, const Penalty& pen) {
  switch (s) {
    case pce::Status::invalid_input: {
      std::string m = penalty_problem(pen);
      if (m.empty()) m = coordinate_problem(req, xs);
      return m.empty() ? "invalid input" : m;
    }
    case pce::Status::degenerate:
      return degenerate_message(req);
    case pce::Status::out_of_domain: {
      if constexpr (Pair::dofs == 12)
        if (req.closest_feature) return domain_message(pen, closest_feature_length_at<Pair>(xs));
      return domain_message(pen, length_at<Pair>(xs, len));
    }
    case pce::Status::overflow:
      return std::string("a result is not finite in scalar \"") + to_string(req.scalar) + "\"";
    case pce::Status::ok:
      break;
  }
  return "unexpected status";
}

template <class Pair, class Scalar, class Length, class Penalty>
Response evaluate_typed(const Request& req, const Length& len, const Penalty& pen) {
  const pce::VecN<Scalar, Pair::dofs> xs = to_scalar<Scalar, Pair::dofs>(req.x);
  pce::PairResult<Scalar, Pair::dofs, Pair::frame_dofs> result;
  const pce::Status s = pce::evaluate<Pair>(xs, len, pen, req.projection, result);
  if (s != pce::Status::ok) return error_response(pce::to_string(s), failure_message<Pair>(s, req, xs, len, pen));
  Evaluation e;
  if (!to_evaluation(result, e))
    return error_response(pce::to_string(pce::Status::overflow),
                          "a result is finite in long double but beyond the double range used for printing");
  return ok_response(std::move(e), req);
}

/// Whether every output of a mollified or closest-feature evaluation is finite in `Scalar`
/// (as `pce::evaluate` checks for the plain energy).
template <class Scalar> bool all_finite(const pce::PairResult<Scalar>& r) {
  return std::isfinite(r.length) && std::isfinite(r.value) && r.gradient.allFinite() && r.hessian.allFinite() &&
         r.projected_hessian.allFinite() && r.eigen.values.allFinite();
}

/// The response of a successful closest-feature evaluation (penalty-independent, so it is
/// instantiated once per scalar type): every output on all 12 coordinates from the
/// `ClosestFeatureEnergy` overloads, the eigenvalues of the kind evaluated (9, 6 or 3) and
/// its name as "feature".
template <class Scalar>
Response closest_feature_response(const pce::ClosestFeatureEnergy<Scalar>& energy, const Request& req) {
  pce::PairResult<Scalar> result;
  result.length = energy.length;
  result.value = energy.psi.value;
  result.gradient = pce::energy_gradient(energy);
  result.hessian = pce::energy_hessian(energy);
  result.projected_hessian =
      req.projection == pce::Projection::none ? result.hessian : pce::projected_hessian(energy, req.projection);
  const pce::FeatureEigenvalues<Scalar> eig = pce::feature_eigenvalues(energy);
  result.eigen.values = eig.values;  // entries from `count` on are zeros (not printed)
  if (!all_finite(result))
    return error_response(pce::to_string(pce::Status::overflow),
                          std::string("a result is not finite in scalar \"") + to_string(req.scalar) + "\"");
  Evaluation e;
  if (!to_evaluation(result, e) || !store_vector<Scalar, 9>(eig.values, e.eigenvalues, eig.count))
    return error_response(pce::to_string(pce::Status::overflow),
                          "a result is finite in long double but beyond the double range used for printing");
  e.feature = pce::to_string(energy.feature);
  return ok_response(std::move(e), req);
}

/// "closest_feature": true — classify by the closest features and evaluate that kind with
/// the unsigned distance (`pce::closest_feature_energy`).
template <class Pair, class Scalar, class Penalty>
Response evaluate_closest_feature(const Request& req, const Penalty& pen) {
  const pce::Vec12<Scalar> xs = to_scalar<Scalar, 12>(req.x);
  pce::ClosestFeatureEnergy<Scalar> energy;
  const pce::Status s = pce::closest_feature_energy<Pair>(xs, pce::UnsignedLength{}, pen, energy);
  if (s != pce::Status::ok)
    return error_response(pce::to_string(s), failure_message<Pair>(s, req, xs, pce::UnsignedLength{}, pen));
  return closest_feature_response(energy, req);
}

/// The opt-in mollified energy E_m = m(X) ψ(L) (`pce::mollified_pair_energy`) with every
/// output from its `MollifiedEnergy` overloads. Where X = 0 (no frame) the library gives
/// ok with all zeros and m = 0; the length is then undefined and left out of the response.
template <class Pair, class Scalar, class Length, class Penalty>
Response evaluate_mollified(const Request& req, const Length& len, const Penalty& pen) {
  const pce::Mollifier& mollifier = *req.mollifier;
  const Scalar threshold = static_cast<Scalar>(mollifier.threshold);
  if (!std::isfinite(threshold) || !(threshold > Scalar(0)))
    return error_response(pce::to_string(pce::Status::invalid_input),
                          "field \"mollifier.threshold\" = " + format_number(mollifier.threshold) +
                              " is not representable as a positive finite number in scalar \"" + to_string(req.scalar) +
                              "\"");
  const pce::Vec12<Scalar> xs = to_scalar<Scalar, 12>(req.x);
  pce::MollifiedEnergy<Scalar> energy;
  const pce::Status s = pce::mollified_pair_energy<Pair>(xs, len, pen, mollifier, energy);
  if (s != pce::Status::ok) return error_response(pce::to_string(s), failure_message<Pair>(s, req, xs, len, pen));
  pce::PairResult<Scalar> result;
  result.length = energy.has_frame ? energy.base.length : Scalar(0);
  result.value = energy.value;
  result.gradient = pce::energy_gradient(energy);
  result.hessian = pce::energy_hessian(energy);
  result.projected_hessian =
      req.projection == pce::Projection::none ? result.hessian : pce::projected_hessian(energy, req.projection);
  result.eigen = pce::energy_eigensystem(energy);
  if (!all_finite(result) || !std::isfinite(energy.mollifier))
    return error_response(pce::to_string(pce::Status::overflow),
                          std::string("a result is not finite in scalar \"") + to_string(req.scalar) + "\"");
  Evaluation e;
  MollifierOutput m;
  m.threshold = mollifier.threshold;
  if (!to_evaluation(result, e) || !store(energy.mollifier, m.value))
    return error_response(pce::to_string(pce::Status::overflow),
                          "a result is finite in long double but beyond the double range used for printing");
  if (!energy.has_frame) e.length.reset();
  e.mollifier = m;
  return ok_response(std::move(e), req);
}

/// The plain energy, the mollified one when the request has a "mollifier" field, or the
/// closest-feature one for "closest_feature": true (the parser allows those two only for
/// the plane kinds, and closest_feature only with an unsigned length).
template <class Pair, class Scalar, class Length, class Penalty>
Response evaluate_variant(const Request& req, const Length& len, const Penalty& pen) {
  if constexpr (Pair::dofs == 12) {
    if (req.mollifier) return evaluate_mollified<Pair, Scalar>(req, len, pen);
    if constexpr (std::is_same_v<Length, pce::UnsignedLength>)
      if (req.closest_feature) return evaluate_closest_feature<Pair, Scalar>(req, pen);
  }
  return evaluate_typed<Pair, Scalar>(req, len, pen);
}

/// The point kinds are instantiated with the unsigned length only (the parser rejects a
/// signed one, and so would the library).
template <class Scalar, class Length, class Penalty>
Response dispatch_pair(const Request& req, const Length& len, const Penalty& pen) {
  if (req.closest_feature && !std::is_same_v<Length, pce::UnsignedLength>)
    return error_response("internal_error", "closest_feature with a signed length reached evaluation");
  switch (req.pair) {
    case PairKind::edge_edge:
      return evaluate_variant<pce::EdgeEdge, Scalar>(req, len, pen);
    case PairKind::point_edge:
    case PairKind::point_point:
      if constexpr (std::is_same_v<Length, pce::UnsignedLength>) {
        if (req.pair == PairKind::point_edge) return evaluate_variant<pce::PointEdge, Scalar>(req, len, pen);
        return evaluate_variant<pce::PointPoint, Scalar>(req, len, pen);
      } else {
        return error_response("internal_error", "a signed length for a point pair reached evaluation");
      }
    case PairKind::vertex_face:
      break;
  }
  return evaluate_variant<pce::VertexFace, Scalar>(req, len, pen);
}

}  // namespace detail

template <class Scalar> Response evaluate_in(const Request& request) {
  return std::visit([&](const auto& len, const auto& pen) { return detail::dispatch_pair<Scalar>(request, len, pen); },
                    request.length, request.penalty);
}

}  // namespace pce_probe

// SPDX-License-Identifier: MIT
// pce._pce: the compiled part of the Python package (python/pce wraps it; docs/python.md).
// `_evaluate` checks what the Python layer already checked (shapes, dtypes, sizes) once more,
// so no call can make it read or write outside the arrays, then evaluates without the GIL.
#include "batch.hpp"
#include "simulation.hpp"

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>

#include <cstdint>
#include <optional>
#include <string>

namespace nb = nanobind;

namespace pce_python {
namespace {

using Input = nb::ndarray<nb::ro, nb::c_contig, nb::device::cpu>;
using Output = nb::ndarray<nb::c_contig, nb::device::cpu>;

static_assert(sizeof(pce::Status) == sizeof(std::int32_t) && sizeof(pce::Feature) == sizeof(std::int32_t),
              "status and feature arrays are int32");

/// The data of output `name`, checked to hold `count × width` elements of `dtype`; null for None.
template <class T> T* output(const std::optional<Output>& a, const char* name, std::size_t count, std::size_t width) {
  if (!a) return nullptr;
  if (a->dtype() != nb::dtype<T>())
    throw nb::type_error((std::string("pce._pce._evaluate: output ") + name + " has the wrong dtype").c_str());
  if (a->size() != count * width)
    throw nb::value_error((std::string("pce._pce._evaluate: output ") + name + " has " + std::to_string(a->size()) +
                           " elements, expected " + std::to_string(count * width))
                              .c_str());
  return static_cast<T*>(a->data());
}

/// Whether `code` is the integer of a strategy in `pce::kProjectionNames`.
bool is_projection(int code) {
  for (const auto& entry : pce::kProjectionNames)
    if (static_cast<int>(entry.first) == code) return true;
  return false;
}

/// `pce::kProjectionNames` as a list of (name, integer) pairs, in the table's order.
nb::list projections() {
  nb::list out;
  for (const auto& entry : pce::kProjectionNames)
    out.append(nb::make_tuple(std::string(entry.second), static_cast<int>(entry.first)));
  return out;
}

template <class Scalar> void evaluate_in(const BatchCall& call, const Input& x, const std::optional<Output>& status,
                                         const std::optional<Output>& length, const std::optional<Output>& value,
                                         const std::optional<Output>& gradient, const std::optional<Output>& hessian,
                                         const std::optional<Output>& projected,
                                         const std::optional<Output>& eigenvalues,
                                         const std::optional<Output>& feature) {
  const auto d = static_cast<std::size_t>(dofs(call.kind));
  const auto f = static_cast<std::size_t>(frame_dofs(call.kind, call.closest_feature));
  const std::size_t n = call.count;
  pce::BatchOutput<Scalar> out;
  out.status = reinterpret_cast<pce::Status*>(output<std::int32_t>(status, "status", n, 1));
  out.length = output<Scalar>(length, "length", n, 1);
  out.value = output<Scalar>(value, "value", n, 1);
  out.gradient = output<Scalar>(gradient, "gradient", n, d);
  out.hessian = output<Scalar>(hessian, "hessian", n, d * d);
  out.projected = output<Scalar>(projected, "projected", n, d * d);
  out.eigenvalues = output<Scalar>(eigenvalues, "eigenvalues", n, f);
  out.feature = reinterpret_cast<pce::Feature*>(output<std::int32_t>(feature, "feature", n, 1));
  const auto* data = static_cast<const Scalar*>(x.data());
  nb::gil_scoped_release release;
  run_batch<Scalar>(call, data, out);
}

void evaluate(int kind, const Input& x, bool signed_length, int side, int penalty, double a, double b, double c,
              int projection, bool closest_feature, int threads, const std::optional<Output>& status,
              const std::optional<Output>& length, const std::optional<Output>& value,
              const std::optional<Output>& gradient, const std::optional<Output>& hessian,
              const std::optional<Output>& projected, const std::optional<Output>& eigenvalues,
              const std::optional<Output>& feature) {
  if (kind < 0 || kind > 3) throw nb::value_error("pce._pce._evaluate: kind out of range");
  if (penalty < 0 || penalty > 2) throw nb::value_error("pce._pce._evaluate: penalty out of range");
  if (!is_projection(projection)) throw nb::value_error("pce._pce._evaluate: projection out of range");
  if (side != 1 && side != -1) throw nb::value_error("pce._pce._evaluate: side must be 1 or -1");
  if (threads < 1) throw nb::value_error("pce._pce._evaluate: threads must be >= 1");
  BatchCall call;
  call.kind = static_cast<Kind>(kind);
  call.signed_length = signed_length;
  call.side = side > 0 ? pce::Side::positive : pce::Side::negative;
  call.penalty = static_cast<PenaltyKind>(penalty);
  call.parameters[0] = a;
  call.parameters[1] = b;
  call.parameters[2] = c;
  call.projection = static_cast<pce::Projection>(projection);
  call.closest_feature = closest_feature;
  call.threads = threads;
  if (closest_feature && (signed_length || dofs(call.kind) != 12))
    throw nb::value_error("pce._pce._evaluate: closest features need a plane kind and the unsigned length");
  if (signed_length && dofs(call.kind) != 12)
    throw nb::value_error("pce._pce._evaluate: the point kinds have the unsigned length only");
  const auto d = static_cast<std::size_t>(dofs(call.kind));
  if (x.ndim() != 2 || x.shape(1) != d)
    throw nb::value_error(("pce._pce._evaluate: X must have shape (N, " + std::to_string(d) + ")").c_str());
  call.count = x.shape(0);
  if (x.dtype() == nb::dtype<double>())
    evaluate_in<double>(call, x, status, length, value, gradient, hessian, projected, eigenvalues, feature);
  else if (x.dtype() == nb::dtype<float>())
    evaluate_in<float>(call, x, status, length, value, gradient, hessian, projected, eigenvalues, feature);
  else
    throw nb::type_error("pce._pce._evaluate: X must be float32 or float64");
}

}  // namespace
}  // namespace pce_python

NB_MODULE(_pce, m) {
  m.doc() = "pce's compiled core: batched pair evaluation and the simulator (use the pce package)";
  m.attr("__version__") = PCE_VERSION_STRING;
  m.def("_evaluate", &pce_python::evaluate, nb::arg("kind"), nb::arg("x"), nb::arg("signed_length"), nb::arg("side"),
        nb::arg("penalty"), nb::arg("a"), nb::arg("b"), nb::arg("c"), nb::arg("projection"), nb::arg("closest_feature"),
        nb::arg("threads"), nb::arg("status").none(), nb::arg("length").none(), nb::arg("value").none(),
        nb::arg("gradient").none(), nb::arg("hessian").none(), nb::arg("projected").none(),
        nb::arg("eigenvalues").none(), nb::arg("feature").none(),
        "Batched evaluation into preallocated arrays (pce.evaluate checks the arguments and allocates).");
  m.def("_projections", &pce_python::projections,
        "The PSD strategies as (name, code) pairs in pce::kProjectionNames' order (pce.PROJECTIONS).");
  pce_python::bind_simulation(m);
}

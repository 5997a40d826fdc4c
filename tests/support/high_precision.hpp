// SPDX-License-Identifier: MIT
/// @file
/// The tests' high-precision reference scalar: a 50-digit binary float from
/// Boost.Multiprecision, with the Eigen traits it needs (Boost 1.74's own `eigen.hpp`
/// lacks `infinity()`/`quiet_NaN()`, which Eigen 3.4's eigensolvers call).
#pragma once

#include <boost/multiprecision/cpp_bin_float.hpp>

#include <Eigen/Core>

#include <limits>

namespace pce_test {
using HighPrecision =
    boost::multiprecision::number<boost::multiprecision::cpp_bin_float<50>, boost::multiprecision::et_off>;
}

namespace Eigen {
template <> struct NumTraits<pce_test::HighPrecision> : GenericNumTraits<pce_test::HighPrecision> {
  using Self = pce_test::HighPrecision;
  using Real = Self;
  using NonInteger = Self;
  using Literal = Self;
  using Nested = Self;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 1,
    AddCost = 4,
    MulCost = 8
  };
  static Real epsilon() { return std::numeric_limits<Self>::epsilon(); }
  static Real dummy_precision() { return Real(1000) * epsilon(); }
  static Real highest() { return (std::numeric_limits<Self>::max)(); }
  static Real lowest() { return -(std::numeric_limits<Self>::max)(); }
  static Real infinity() { return std::numeric_limits<Self>::infinity(); }
  static Real quiet_NaN() { return std::numeric_limits<Self>::quiet_NaN(); }
  static int digits10() { return std::numeric_limits<Self>::digits10; }
  static int digits() { return std::numeric_limits<Self>::digits; }
};
}  // namespace Eigen

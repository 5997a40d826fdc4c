// SPDX-License-Identifier: MIT
/// @file
/// The scalar types every typed test runs on (TinyAD/Sophus style), with tolerances.
#pragma once

#include <gtest/gtest.h>

#include <limits>

namespace pce_test {
using Scalars = testing::Types<float, double, long double>;

/// `k` units of roundoff of S, as double.
template <class S> double ulps(double k) { return k * static_cast<double>(std::numeric_limits<S>::epsilon()); }
}  // namespace pce_test

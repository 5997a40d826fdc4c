// SPDX-License-Identifier: MIT
/// @file
/// What a penalty is: a small value type giving ψ(L), ψ′(L), ψ″(L) (Shi & Kim 2023, Sec. 3:
/// every penalty energy is ψ composed with a length). Everything else — the gradient, the
/// exact Hessian, its closed-form eigensystem and every PSD projection — follows from the
/// length's frame derivatives, for any ψ. A user-written penalty needs only
///
///     struct MyPenalty {
///       template <class Scalar> pce::PenaltyDerivatives<Scalar> evaluate(Scalar L) const;
///     };
///
/// and may add `template <class Scalar> bool in_domain(Scalar L) const` (default: every
/// finite L) and `bool valid() const` (default: true) for parameter checks.
#pragma once

#include <pce/core/types.hpp>

#include <type_traits>
#include <utility>

namespace pce {

/// ψ, ψ′ and ψ″ at one length.
template <class Scalar> struct PenaltyDerivatives {
  Scalar value;   ///< ψ(L)
  Scalar first;   ///< ψ′(L)
  Scalar second;  ///< ψ″(L)
};

namespace detail {

template <class P, class S, class = void> struct has_in_domain : std::false_type {};
template <class P, class S>
struct has_in_domain<P, S, std::void_t<decltype(std::declval<const P&>().in_domain(std::declval<S>()))>>
    : std::true_type {};

template <class P, class = void> struct has_valid : std::false_type {};
template <class P> struct has_valid<P, std::void_t<decltype(std::declval<const P&>().valid())>> : std::true_type {};

}  // namespace detail

/// Whether `penalty` is defined at `L` (calls `in_domain` when the type has it).
template <class Penalty, class Scalar> PCE_HOST_DEVICE bool penalty_in_domain(const Penalty& penalty, const Scalar& L) {
  if constexpr (detail::has_in_domain<Penalty, Scalar>::value)
    return penalty.in_domain(L);
  else
    return true;
}

/// Whether the penalty's parameters are acceptable (calls `valid` when the type has it).
template <class Penalty> PCE_HOST_DEVICE bool penalty_valid(const Penalty& penalty) {
  if constexpr (detail::has_valid<Penalty>::value)
    return penalty.valid();
  else
    return true;
}

/// ψ(L), ψ′(L), ψ″(L) of `penalty`, checked: `Status::out_of_domain` where the penalty is
/// undefined (`penalty_in_domain`), `Status::overflow` when a value or derivative is not
/// finite, else `Status::ok`; `psi` is written only on `ok`. The one evaluation every pair
/// energy makes (paper Sec. 3: the energy is ψ of the pair's length).
template <class Penalty, class Scalar>
PCE_HOST_DEVICE PCE_ALWAYS_INLINE Status evaluate_penalty(const Penalty& penalty, const Scalar& L,
                                                          PenaltyDerivatives<Scalar>& psi) {
  if (!penalty_in_domain(penalty, L)) return Status::out_of_domain;
  const PenaltyDerivatives<Scalar> v = penalty.template evaluate<Scalar>(L);
  if (!detail::finite_all(v.value, v.first, v.second)) return Status::overflow;
  psi = v;
  return Status::ok;
}

}  // namespace pce

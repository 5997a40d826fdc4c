// SPDX-License-Identifier: MIT
// The translation unit clang-tidy checks include/pce through (tests/tidy/run_clang_tidy.cmake,
// ctest `clang_tidy_include`): every public entry point instantiated for every pair kind,
// length, penalty and strategy, so template bodies are analysed as a solver instantiates
// them. In double only: float instantiates the same code and doubles the time. Never
// compiled into a binary.
#include <pce/pce.hpp>

namespace {

template <class Pair, class Scalar, class Length, class Penalty>
void every_strategy(const pce::VecN<Scalar, Pair::dofs>& x, const Length& length, const Penalty& penalty) {
  for (pce::Projection p : {pce::Projection::none, pce::Projection::analytic, pce::Projection::abs,
                            pce::Projection::exact, pce::Projection::gauss_newton, pce::Projection::numerical}) {
    pce::PairResult<Scalar, Pair::dofs, Pair::frame_dofs> r;
    (void)pce::evaluate<Pair>(x, length, penalty, p, r);
  }
}

template <class Scalar, class Penalty> void every_kind(const Penalty& penalty) {
  const pce::Vec12<Scalar> x = pce::Vec12<Scalar>::LinSpaced(Scalar(-1), Scalar(1));
  every_strategy<pce::VertexFace, Scalar>(x, pce::SignedLength{}, penalty);
  every_strategy<pce::VertexFace, Scalar>(x, pce::UnsignedLength{}, penalty);
  every_strategy<pce::EdgeEdge, Scalar>(x, pce::SignedLength{pce::Side::negative}, penalty);
  every_strategy<pce::EdgeEdge, Scalar>(x, pce::UnsignedLength{}, penalty);
  every_strategy<pce::PointEdge, Scalar>(pce::Vec9<Scalar>(x.template head<9>()), pce::UnsignedLength{}, penalty);
  every_strategy<pce::PointPoint, Scalar>(pce::Vec6<Scalar>(x.template head<6>()), pce::UnsignedLength{}, penalty);
  pce::MollifiedEnergy<Scalar> m;
  if (pce::mollified_pair_energy<pce::EdgeEdge>(x, pce::UnsignedLength{}, penalty, pce::Mollifier{}, m) ==
      pce::Status::ok) {
    (void)pce::energy_gradient(m);
    (void)pce::projected_hessian(m, pce::Projection::analytic);
    (void)pce::energy_eigensystem(m);
  }
  pce::ClosestFeatureEnergy<Scalar> c;
  if (pce::closest_feature_energy<pce::VertexFace>(x, pce::UnsignedLength{}, penalty, c) == pce::Status::ok) {
    (void)pce::energy_gradient(c);
    (void)pce::projected_hessian(c, pce::Projection::exact);
    (void)pce::feature_eigenvalues(c);
    pce::LaggedFriction<Scalar, 4> f;
    pce::Vec3<Scalar> n;
    if (pce::friction_geometry(c, x, f.weights, n)) {
      f.basis = pce::tangent_basis(n);
      (void)pce::friction_energy(f, x);
      (void)pce::friction_gradient(f, x);
      (void)pce::friction_hessian(f, x);
    }
  }
  pce::LaggedFriction<Scalar, 1> one;
  one.weights.setOnes();
  one.basis = pce::tangent_basis(pce::Vec3<Scalar>::UnitZ().eval());
  (void)pce::friction_tangent_block(one, pce::Vec3<Scalar>(x.template head<3>()));
  pce::Status status[1];
  Scalar value[1], gradient[12], projected[144], eigenvalues[9];
  pce::Feature feature[1];
  pce::BatchOutput<Scalar> out;
  out.status = status;
  out.value = value;
  out.gradient = gradient;
  out.projected = projected;
  out.eigenvalues = eigenvalues;
  pce::evaluate_batch<pce::EdgeEdge>(x.data(), 1, pce::SignedLength{}, penalty, pce::Projection::exact, out);
  out.feature = feature;
  pce::closest_feature_batch<pce::VertexFace>(x.data(), 1, penalty, pce::Projection::analytic, out);
}

template <class Scalar> void every_penalty() {
  every_kind<Scalar>(pce::QuadraticPenalty{1e4, 0.1});
  every_kind<Scalar>(pce::CubicPenalty{1e5, 0.1, 1e-4});
  every_kind<Scalar>(pce::LogBarrierPenalty{1e3, 0.1});
}

}  // namespace

int main() {
  every_penalty<double>();
  return 0;
}

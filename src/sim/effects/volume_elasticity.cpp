// SPDX-License-Identifier: MIT
// volume_elasticity (effects.hpp): the stable Neo-Hookean energy of every tetrahedron of
// the model's volumes, E = Σ_T V_T Ψ(F_T) (pce/volumes/stable_neo_hookean.hpp, Smith, de
// Goes & Kim 2018), with a PSD Hessian per tetrahedron from the closed-form eigensystem
// (analytic) or from a numerical eigendecomposition of the 9×9 F-space Hessian (numerical,
// the reference). The tetrahedra are evaluated in parallel (OpenMP) into per-tetrahedron
// slots and added to the gradient and Hessian in order, so results do not depend on the
// thread count.
#include "local_terms.hpp"

#include <pce/sim/effects.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/volumes/stable_neo_hookean.hpp>

#include <omp.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace pce::sim {

namespace {

class VolumeElasticity final : public Effect {
 public:
  VolumeElasticity(int vertex_count, const StableNeoHookean& material, VolumeProjection how,
                   std::vector<std::array<int, 4>> tets, std::vector<TetRest<double>> rests)
      : Effect("volume_elasticity"), material_(material), how_(how), tets_(std::move(tets)), rests_(std::move(rests)) {
    incidence_.build(vertex_count, tets_.size(), [this](std::size_t e) { return tets_[e]; });
    for (const auto& r : rests_) rest_volume_ += r.volume;
    volume_ = rest_volume_;
  }

  void declare(Pattern& pattern) const override {
    for (const auto& t : tets_) pattern.add(t);
  }

  /// E = Σ_T V_T Ψ(F_T); +∞ when a tetrahedron's energy or derivatives overflow (the line
  /// search then takes a shorter step).
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) override {
    const long n = static_cast<long>(tets_.size());
    energy_.resize(tets_.size());
    if (gradient) gradient_.resize(tets_.size());
    if (hessian) hessian_.resize(tets_.size());
    volume_of_.resize(tets_.size());
    bool overflow = false;
#pragma omp parallel for schedule(static) reduction(|| : overflow)
    for (long k = 0; k < n; ++k) {
      const auto uk = static_cast<std::size_t>(k);
      Vec12<double> xt;
      for (int a = 0; a < 4; ++a) xt.segment<3>(3 * a) = x.col(tets_[uk][static_cast<std::size_t>(a)]);
      volume_of_[uk] = (xt.segment<3>(3) - xt.head<3>())
                           .dot((xt.segment<3>(6) - xt.head<3>()).cross(xt.segment<3>(9) - xt.head<3>())) /
                       6;
      const Status s = snh_tet_energy(material_, rests_[uk], xt, how_, energy_[uk], gradient ? &gradient_[uk] : nullptr,
                                      hessian ? &hessian_[uk] : nullptr);
      if (s != Status::ok) overflow = true;
    }
    inverted_ = 0;
    volume_ = 0;
    for (const double v : volume_of_) {  // in order: the counters do not depend on the thread count either
      volume_ += v;
      inverted_ += v <= 0;
    }
    if (overflow) return std::numeric_limits<double>::infinity();
    double energy = 0;
    for (std::size_t k = 0; k < tets_.size(); ++k) {
      energy += energy_[k];
      if (gradient)
        for (int a = 0; a < 4; ++a)
          gradient->col(tets_[k][static_cast<std::size_t>(a)]) += gradient_[k].segment<3>(3 * a);
      if (hessian) hessian->add<4>(tets_[k], hessian_[k]);
    }
    return energy;
  }

  /// Per listed vertex, the sum over its tetrahedra of their gradient slot and diagonal
  /// Hessian block at it (snh_tet_energy, as `evaluate`). Where `evaluate` returns +∞ (a
  /// tetrahedron's energy or derivatives overflow) it adds nothing at all; here a vertex one
  /// of whose tetrahedra overflows gets nothing (its terms stay finite). The statistics are
  /// those of the last `evaluate`.
  void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) override {
    add_local_terms(incidence_, vertices, terms, [&](const Incident& u, Eigen::Vector3d& g, Eigen::Matrix3d& B) {
      const auto k = static_cast<std::size_t>(u.item);
      Vec12<double> xt, gt;
      Mat12<double> Ht;
      for (int a = 0; a < 4; ++a) xt.segment<3>(3 * a) = x.col(tets_[k][static_cast<std::size_t>(a)]);
      double energy;
      if (snh_tet_energy(material_, rests_[k], xt, how_, energy, &gt, &Ht) != Status::ok) return false;
      g += gt.segment<3>(3 * u.slot);
      B += Ht.block<3, 3>(3 * u.slot, 3 * u.slot);
      return true;
    });
  }

  /// The tetrahedra, those inverted (signed volume ≤ 0) and Σ volume / Σ rest volume, at
  /// the last state evaluated (the accepted one when the solver reports).
  void report(EffectCounters& counters) const override {
    counters[Counter::tetrahedra] = static_cast<double>(tets_.size());
    counters[Counter::inverted_tetrahedra] = static_cast<double>(inverted_);
    counters[Counter::volume_ratio] = volume_ / rest_volume_;
  }

 private:
  StableNeoHookean material_;
  VolumeProjection how_;
  std::vector<std::array<int, 4>> tets_;
  std::vector<TetRest<double>> rests_;
  VertexIncidence incidence_;  ///< per vertex, its tetrahedra
  double rest_volume_ = 0, volume_ = 0;
  long inverted_ = 0;
  std::vector<double> energy_, volume_of_;  ///< per tetrahedron, at the last state evaluated
  std::vector<Vec12<double>> gradient_;
  std::vector<Mat12<double>, Eigen::aligned_allocator<Mat12<double>>> hessian_;
};

}  // namespace

std::unique_ptr<Effect> make_volume_elasticity(const Model& model, const StableNeoHookean& material,
                                               VolumeProjection hessian) {
  if (!material.valid())
    throw ArgumentError("", "expected a shear modulus mu > 0 and lambda_lame > -mu (Poisson's ratio in (-1, 0.5))");
  if (hessian == VolumeProjection::none)
    throw ArgumentError("hessian", "expected \"analytic\" or \"numerical\" (the solver needs a PSD Hessian)");
  if (model.tetrahedra.cols() == 0)
    throw ArgumentError("", "volume_elasticity needs a mesh with tetrahedra (a volume)");
  std::vector<std::array<int, 4>> tets;
  std::vector<TetRest<double>> rests;
  tets.reserve(static_cast<std::size_t>(model.tetrahedra.cols()));
  rests.reserve(tets.capacity());
  for (Eigen::Index k = 0; k < model.tetrahedra.cols(); ++k) {
    std::array<int, 4> t;
    Vec12<double> X;
    for (int a = 0; a < 4; ++a) {
      t[static_cast<std::size_t>(a)] = model.tetrahedra(a, k);
      X.segment<3>(3 * a) = model.rest.col(t[static_cast<std::size_t>(a)]);
    }
    TetRest<double> rest;
    if (tet_rest(X, rest) != Status::ok)
      throw ArgumentError("", "tetrahedron " + std::to_string(k) +
                                  " has no positive rest volume (volume_elasticity needs a rest shape)");
    tets.push_back(t);
    rests.push_back(rest);
  }
  return std::make_unique<VolumeElasticity>(model.vertex_count(), material, hessian, std::move(tets), std::move(rests));
}

}  // namespace pce::sim

// SPDX-License-Identifier: MIT
// Driving pce::sim from C++ instead of a scene file: a generated cloth grid becomes the
// Model, two effects written against the public pce::sim::Effect interface (gravity, and a
// pce vertex-face penalty against a fixed ground triangle) are the physics, and
// Simulation::step advances it. Check: the state stays finite and the cloth lands and rests.
#include <pce/pce.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/simulation.hpp>

#include <cstdio>
#include <memory>

using pce::sim::BlockHessian;

struct Gravity final : pce::sim::Effect {  // E = −Σᵢ mᵢ g·xᵢ (linear: no Hessian)
  const pce::sim::Model* model;
  explicit Gravity(const pce::sim::Model& m) : model(&m) {}
  const char* name() const override { return "gravity"; }
  void declare(pce::sim::Pattern&) const override {}
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* grad, BlockHessian*) override {
    const Eigen::Vector3d g(0, 0, -9.81);
    if (grad) grad->noalias() -= g * model->mass.transpose();
    return -(g.transpose() * x * model->mass)(0);
  }
};

// Each cloth vertex p against one fixed triangle (t0, t1, t2): the triangle's vertices are
// not unknowns, so their indices are −1 and BlockHessian::add skips their rows.
struct GroundContact final : pce::sim::Effect {
  pce::Vec9<double> ground;
  pce::QuadraticPenalty penalty{1e3, 0.01};  // k, ε
  int active = 0;
  const char* name() const override { return "ground_contact"; }
  void declare(pce::sim::Pattern&) const override {}  // diagonal blocks only: always present
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* grad, BlockHessian* H) override {
    double E = 0;
    active = 0;
    for (int i = 0; i < x.cols(); ++i) {
      pce::Vec12<double> xl;
      xl << x.col(i), ground;
      pce::PairEnergy<double> e;  // signed: above the ground (its normal side) is outside
      if (pce::pair_energy<pce::VertexFace>(xl, pce::SignedLength{}, penalty, e) != pce::Status::ok ||
          e.length >= penalty.eps)
        continue;
      ++active, E += e.psi.value;
      if (grad) grad->col(i) += pce::energy_gradient(e).head<3>();
      if (H) H->add<4>({i, -1, -1, -1}, pce::projected_hessian(e, pce::Projection::analytic));
    }
    return E;
  }
  void report(pce::sim::EffectCounters& c) const override { c["ground_contacts"] = active; }
};

int main() {
  pce::sim::Mesh cloth = pce::sim::grid(1.0, 1.0, 8, 8);  // 81 vertices in z = 0, lifted to z = 0.05
  cloth.positions.row(2).array() += 0.05;
  pce::sim::Simulation sim;  // the Model by hand: what a scene file's "meshes" would build
  sim.model.rest = cloth.positions;
  sim.model.triangles = cloth.triangles;
  sim.model.edges = pce::sim::unique_edges(cloth.triangles);
  sim.model.mass = Eigen::VectorXd::Constant(cloth.vertex_count(), 0.1 / cloth.vertex_count());  // 0.1 kg
  sim.effects.push_back(std::make_unique<Gravity>(sim.model));
  auto contact = std::make_unique<GroundContact>();
  contact->ground << -5, -5, 0, 5, -5, 0, 0, 5, 0;  // counter-clockwise from above: +z is outside
  sim.effects.push_back(std::move(contact));
  sim.solver.dt = 1.0 / 40;
  sim.x = sim.model.rest;
  sim.v = Eigen::Matrix3Xd::Zero(3, sim.model.vertex_count());
  for (int f = 0; f < 12; ++f) {
    const pce::sim::FrameStats st = sim.step();  // throws std::runtime_error if the state turns non-finite
    if (st.frame % 3 == 0 || st.frame == 1)
      std::printf("frame %2d: %d Newton its, %2.0f contacts, z in [%.4f, %.4f], %.2f ms\n", st.frame,
                  st.newton_iterations, st.counters.at("ground_contacts"), sim.x.row(2).minCoeff(),
                  sim.x.row(2).maxCoeff(), st.wall_ms);
  }
  const bool ok = sim.x.allFinite() && sim.x.row(2).minCoeff() > 0 && sim.x.row(2).maxCoeff() < 0.02 &&
                  sim.v.cwiseAbs().maxCoeff() < 0.1;
  std::printf("%s\n", ok ? "ok: landed and resting" : "FAILED");
  return ok ? 0 : 1;
}

// SPDX-License-Identifier: MIT
// The contact tests' fixture (test_contact.cpp, test_separation_floor.cpp,
// test_friction_derivatives.cpp): two small sheets with one contact effect, the start of a
// step that queries its pairs, and an effect's Hessian as a dense matrix.
#pragma once

#include <pce/sim/block_hessian.hpp>
#include <pce/sim/contact_effect.hpp>
#include <pce/sim/scene.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <nlohmann/json.hpp>

#include <memory>

namespace pce::sim::fixtures {

/// The scene's effect as the contact effect it is.
inline ContactEffect& contact_of(const std::unique_ptr<Effect>& e) { return dynamic_cast<ContactEffect&>(*e); }

/// Two 4 × 4 sheets (5 cm edges), the second `gap` above the first and turned by 10°, with
/// the one effect `contact`.
inline std::unique_ptr<Scene> two_sheets(const nlohmann::json& contact, double gap) {
  nlohmann::json j = nlohmann::json::parse(R"({
    "dt": 0.01, "frames": 1,
    "meshes": [
      {"name": "a", "generator": {"type": "grid", "width": 0.2, "height": 0.2, "nx": 4, "ny": 4}},
      {"name": "b", "generator": {"type": "grid", "width": 0.2, "height": 0.2, "nx": 4, "ny": 4},
       "transform": {"rotation": {"axis": [0, 0, 1], "degrees": 10}}}
    ],
    "effects": []
  })");
  j["meshes"][1]["transform"]["translation"] = {0.003, -0.002, gap};
  j["effects"].push_back(contact);
  return load_scene_text(j.dump(), "contact.json", PCE_TEST_TMP);
}

/// The effect's assembled Hessian at x, dense and symmetric (the pairs active at x join the
/// pattern first).
inline Eigen::MatrixXd dense_hessian(ContactEffect& e, const Eigen::Matrix3Xd& x) {
  e.begin_iteration(x);
  Pattern p;
  e.declare(p);
  BlockHessian H;
  H.set_pattern(static_cast<int>(x.cols()), p);
  Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, x.cols());
  e.evaluate(x, &g, &H);
  const Eigen::SparseMatrix<double> full = H.matrix().selfadjointView<Eigen::Upper>();
  return Eigen::MatrixXd(full);
}

/// Starts a step at `at` (zero velocity) for every effect of `s`, so contact effects query
/// their pairs there.
inline void begin_at(Scene& s, const Eigen::Matrix3Xd& at) {
  static Eigen::Matrix3Xd x, v;
  x = at;
  v = Eigen::Matrix3Xd::Zero(3, x.cols());
  StepContext ctx;
  ctx.frame = 1;
  ctx.time = 0.01;
  ctx.dt = 0.01;
  ctx.model = &s.simulation.model;
  ctx.x_start = &x;
  ctx.v_start = &v;
  for (auto& e : s.simulation.effects) e->begin_step(ctx);
}

}  // namespace pce::sim::fixtures

// SPDX-License-Identifier: MIT
// Rotations, transforms and motions of the scene (motion.hpp). Every number is checked here
// or by the builders' argument checks (effects/arguments.hpp), with errors at its JSON path.
#include "motion.hpp"

#include "../effects/arguments.hpp"

#include <limits>

namespace pce::sim {

namespace {

/// A transform's uniform scale: [1e-6, 1e6] (a mesh in µm to one in Mm); the transformed
/// coordinates are then checked against `kMaxCoordinate` by `validate`.
constexpr double kMinScale = 1e-6, kMaxScale = 1e6;

/// A motion's `keyframes` (at least one), with its `interpolation`; the times, their order
/// and the translations are checked by `args::motion`, named by their path.
Motion parse_keyframes(const Params& m) {
  for (const char* key : {"velocity", "angular_velocity", "start", "stop"})
    if (m.has(key))
      m.fail(key,
             "a motion has either \"keyframes\" or a constant velocity (\"velocity\", \"angular_velocity\", "
             "\"start\", \"stop\"), not both");
  const std::size_t keyframe_count = m.array("keyframes", true).size();
  if (keyframe_count == 0) m.fail("keyframes", "expected at least one keyframe");
  Motion motion;
  for (std::size_t k = 0; k < keyframe_count; ++k) {
    const Params f = m.element("keyframes", k);
    f.only({"time", "translation", "rotation"});
    Keyframe key;
    key.time = f.number("time");
    key.translation = f.vec3("translation", Eigen::Vector3d::Zero());
    if (f.has("rotation")) key.rotation = parse_rotation(f.object("rotation"));
    motion.keyframes.push_back(key);
  }
  motion.interpolation = m.choice<Interpolation>("interpolation", Interpolation::linear);
  m.build([&] { args::motion("", motion); });
  return motion;
}

}  // namespace

Eigen::Matrix3d parse_rotation(const Params& p) {
  p.only({"axis", "degrees"});
  const Eigen::Vector3d axis = p.vec3("axis");
  const double largest = axis.cwiseAbs().maxCoeff();
  if (!(largest > 0)) p.fail("axis", "expected a non-zero axis");
  const double degrees = p.number("degrees");  // any finite angle: only its sine and cosine are used
  return axis_rotation(axis, degrees);
}

Transform parse_transform(const Params& p) {
  p.only({"translation", "rotation", "scale"});
  Transform t;
  t.translation = p.checked_vec3("translation", args::position, Eigen::Vector3d::Zero());
  if (p.has("rotation")) t.rotation = parse_rotation(p.object("rotation"));
  t.scale = p.number("scale", 1.0);
  if (!(t.scale >= kMinScale && t.scale <= kMaxScale))
    p.fail("scale", "expected a number in [" + args::limit_text(kMinScale) + ", " + args::limit_text(kMaxScale) +
                        "] (the scales pce::sim accepts), got " + args::text(t.scale));
  return t;
}

Motion parse_motion(const Params& m) {
  if (m.has("keyframes")) return parse_keyframes(m);
  if (m.has("interpolation")) m.fail("interpolation", "an interpolation is between \"keyframes\": give them too");
  Motion motion;
  motion.velocity = m.checked_vec3("velocity", args::speed, Eigen::Vector3d::Zero());
  motion.angular_velocity = m.checked_vec3("angular_velocity", args::speed, Eigen::Vector3d::Zero());
  motion.start = m.nonnegative("start", 0.0);
  motion.stop = m.has("stop") ? m.nonnegative("stop") : std::numeric_limits<double>::infinity();
  if (motion.stop < motion.start) m.fail("stop", "expected stop >= start");
  return motion;
}

}  // namespace pce::sim

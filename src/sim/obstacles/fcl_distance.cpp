// SPDX-License-Identifier: MIT
#include <pce/sim/fcl_distance.hpp>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/narrowphase/distance.h>

#include <memory>
#include <stdexcept>

namespace pce::sim {

double fcl_point_distance(const Obstacle& o, const Eigen::Isometry3d& pose, const Eigen::Vector3d& p) {
  std::shared_ptr<fcl::CollisionGeometry<double>> shape;
  switch (o.kind) {
    case ShapeKind::sphere:
      shape = std::make_shared<fcl::Ellipsoid<double>>(o.radius, o.radius, o.radius);
      break;
    case ShapeKind::box:
      shape = std::make_shared<fcl::Box<double>>(2 * o.half_extents);
      break;
    case ShapeKind::capsule:
      shape = std::make_shared<fcl::Capsule<double>>(o.radius, 2 * o.half_length);
      break;  // lz = full length
    case ShapeKind::mesh:
      throw std::invalid_argument("fcl_point_distance: meshes are not supported");
  }
  const auto point = std::make_shared<fcl::Box<double>>(0.0, 0.0, 0.0);
  fcl::Transform3<double> shape_pose = fcl::Transform3<double>::Identity();
  shape_pose.linear() = pose.linear();
  shape_pose.translation() = pose.translation();
  fcl::Transform3<double> point_pose = fcl::Transform3<double>::Identity();
  point_pose.translation() = p;
  fcl::DistanceRequest<double> request;
  request.gjk_solver_type = fcl::GST_LIBCCD;
  request.distance_tolerance = 1e-12;
  fcl::DistanceResult<double> result;
  return fcl::distance(shape.get(), shape_pose, point.get(), point_pose, request, result);
}

}  // namespace pce::sim

//! \file collision_shapes.hpp
//! \brief Private to the core: Bullet shapes from URDF geometry, and frame conversions.
#pragma once

#include <btBulletCollisionCommon.h>
#include <urdf_model/link.h>
#include <urdf_model/pose.h>

#include <Eigen/Geometry>
#include <kdl/frames.hpp>
#include <memory>
#include <string>

#include "a2l/collision_model.hpp"

namespace a2l::detail {

//! m: Bullet's collision margin of every shape the collision model makes.
constexpr double kShapeMargin = 0.001;

//! m: every link shape is this much larger than the URDF says (boxes, cylinders and spheres on
//! every side, hulls through their margin on top of kShapeMargin), so that planned paths keep
//! a clearance. It covers simulators that approximate the same geometry a little larger:
//! PyBullet loads a URDF cylinder as an inscribed 32-gon prism inflated by a 1 mm margin (up to
//! 1 mm outside the true cylinder), and a transit planned against the exact cylinders grazed
//! such a prism by 0.27 mm (tests/python/test_planning_transit.py).
constexpr double kLinkPadding = 0.002;

//! Conversions into Bullet transforms.
btTransform to_bt(const Eigen::Isometry3d& t);
btTransform to_bt(const KDL::Frame& f);
btTransform to_bt(const urdf::Pose& p);

//! A Bullet shape for one URDF geometry, grown by kLinkPadding: boxes, cylinders (along z) and
//! spheres, a mesh as the convex hull of its vertices from `meshes` (reduced by btShapeHull). On
//! failure nullptr, and `error` names the mesh or the geometry and `link`.
std::unique_ptr<btCollisionShape> make_shape(const urdf::Geometry& g, const MeshVertices& meshes,
                                             const std::string& link, std::string& error);

}  // namespace a2l::detail

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

//! Conversions into Bullet transforms.
btTransform to_bt(const Eigen::Isometry3d& t);
btTransform to_bt(const KDL::Frame& f);
btTransform to_bt(const urdf::Pose& p);

//! A Bullet shape for one URDF geometry: boxes, cylinders (along z) and spheres as they are,
//! a mesh as the convex hull of its vertices from `meshes` (reduced by btShapeHull). On
//! failure nullptr, and `error` names the mesh or the geometry and `link`.
std::unique_ptr<btCollisionShape> make_shape(const urdf::Geometry& g, const MeshVertices& meshes,
                                             const std::string& link, std::string& error);

}  // namespace a2l::detail

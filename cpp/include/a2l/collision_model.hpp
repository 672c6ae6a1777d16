//! \file collision_model.hpp
//! \brief Collision checking of a robot arm against itself and boxes, with Bullet shapes built
//! from the URDF's collision geometry.
//!
//! Every link's `<collision>` elements become Bullet shapes: boxes, cylinders and spheres as
//! they are, meshes as convex hulls of their vertices (the vertices are given by the caller,
//! see MeshVertices), each grown by 2 mm on every side so that planned paths keep a clearance
//! (simulators approximate the same geometry up to ~1 mm larger). The arm is the chain between two
//! links (as in Kinematics); every link below the chain's first joint moves with it, every other
//! link stays where the fixed joint positions put it. A configuration of the arm is in collision
//! when a moving link touches an obstacle box (inflated by a padding), a static link, or another
//! moving link — except the allowed pairs: adjacent links (parent and child, through links without
//! geometry), links rigidly attached to each other (no arm joint between them: their contact never
//! changes) and the pairs found in collision at a reference pose (allow_collisions_at()).
//!
//! Poses are expressed in the frame of the chain's base link. Available when the core was
//! built with Bullet (A2L_HAVE_BULLET).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "a2l/kinematics.hpp"
#include "a2l/status.hpp"

namespace a2l {

//! An obstacle: a box of half-extents `half_extents` (m) at `pose` in the base link's frame.
struct CollisionBox {
  std::string name;                                        //!< reported in collisions
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  //!< the box's centre and axes
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  //!< m, each > 0
};

//! Vertices (rows of x, y, z in the mesh file's units) of the URDF's collision meshes, by the
//! `filename` attribute exactly as the URDF writes it. The mesh's `scale` is applied here.
using MeshVertices = std::map<std::string, Eigen::Matrix<double, Eigen::Dynamic, 3>>;

//! A pair of names that collide (links or obstacles).
using CollisionPair = std::pair<std::string, std::string>;

//! True if this build has the collision model (Bullet).
bool collision_model_available() noexcept;

#if A2L_HAVE_BULLET
//! The collision geometry of a URDF with one moving arm. Not thread-safe: a check moves the
//! Bullet objects; use one object per thread.
class CollisionModel {
 public:
  CollisionModel();
  ~CollisionModel();
  CollisionModel(CollisionModel&&) noexcept;
  CollisionModel& operator=(CollisionModel&&) noexcept;
  CollisionModel(const CollisionModel&) = delete;
  CollisionModel& operator=(const CollisionModel&) = delete;

  //! Load a URDF file; the arm is the chain `base_link` -> `tip_link`.
  //! \param meshes vertices of every collision mesh the URDF names (see MeshVertices)
  //! \return `file_error`, `parse_error`, `unknown_link`, `invalid_argument` (a mesh without
  //!         vertices, an unsupported geometry), or `ok`.
  static Result load(const std::string& urdf_path, const std::string& base_link,
                     const std::string& tip_link, const MeshVertices& meshes, CollisionModel& out);
  //! Same as load() for a URDF held in a string.
  static Result load_from_string(const std::string& urdf_xml, const std::string& base_link,
                                 const std::string& tip_link, const MeshVertices& meshes,
                                 CollisionModel& out);

  //! True once loaded.
  bool loaded() const noexcept;
  //! The arm's kinematics.
  const Kinematics& kinematics() const noexcept;
  //! Links that have collision geometry.
  std::vector<std::string> links() const;
  //! Links with geometry that move with the arm.
  std::vector<std::string> moving_links() const;

  //! Positions of movable joints outside the arm (the other arm, the head, the fingers);
  //! every joint not given stays where it is (0 at load).
  //! \return `invalid_argument` naming a joint that is unknown or in the arm, else `ok`.
  Result set_joint_positions(const std::map<std::string, double>& positions);
  //! Replace the obstacle boxes; each is inflated by `padding` (m, >= 0) on every side.
  //! \return `invalid_argument` for a non-positive half-extent, a negative padding or NaN.
  Result set_obstacles(const std::vector<CollisionBox>& boxes, double padding);
  //! Allow (ignore from now on) every pair of links in collision at arm configuration `q`.
  //! \return `size_mismatch`, `invalid_argument` (NaN) or `ok`.
  Result allow_collisions_at(const Eigen::Ref<const Eigen::VectorXd>& q);
  //! The allowed pairs of links, sorted.
  std::vector<CollisionPair> allowed_pairs() const;

  //! True if the arm at `q` collides (q must have n_joints() finite entries; no check).
  bool in_collision(const Eigen::Ref<const Eigen::VectorXd>& q);
  //! Every colliding pair at `q` (empty if none).
  std::vector<CollisionPair> colliding_pairs(const Eigen::Ref<const Eigen::VectorXd>& q);
  //! How a check runs: pair by pair (true, the default: each tested pair's exact bounding boxes,
  //! then Bullet's narrow phase only where they overlap, stopping at the first collision for
  //! in_collision()), or Bullet's world pass (false: its broad phase with a 2 cm contact
  //! threshold and persistent contact manifolds over every pair, as before). Both use the same
  //! shapes and call the same configurations colliding up to Bullet's contact caching.
  void set_pairwise(bool pairwise) noexcept;
  //! True if checks run pair by pair (set_pairwise()).
  bool pairwise() const noexcept;
  //! Number of in_collision() / colliding_pairs() calls since load.
  long long checks() const noexcept;
  //! Pose of link `link` (base link frame) at arm configuration `q`.
  //! \return `unknown_link`, `size_mismatch` or `ok`.
  Result link_pose(const Eigen::Ref<const Eigen::VectorXd>& q, const std::string& link,
                   Eigen::Isometry3d& pose);

  //! The implementation (opaque; defined in collision_model.cpp).
  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};
#endif

}  // namespace a2l

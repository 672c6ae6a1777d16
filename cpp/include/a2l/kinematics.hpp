//! \file kinematics.hpp
//! \brief Forward kinematics, Jacobian and inverse kinematics of a serial chain of a URDF.
//!
//! The URDF is parsed by urdfdom and converted into a KDL tree by our own converter
//! (urdf_to_kdl.hpp); the chain between two links is taken from that tree and flattened into
//! per-joint fixed frames and joint axes, so that FK, the Jacobian and IK run on small
//! fixed-capacity Eigen objects: they allocate nothing and throw nothing (real-time safe).
//!
//! Conventions: poses are 4x4 homogeneous transforms of the tip link's frame in the base
//! link's frame; the Jacobian is 6 x n, rows (vx, vy, vz, wx, wy, wz), reference point at the
//! tip, expressed in the base frame (KDL's convention).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <kdl/chain.hpp>
#include <kdl/tree.hpp>
#include <string>
#include <vector>

#include "a2l/status.hpp"

namespace a2l {

//! Most movable joints a chain may have (capacity of the fixed-size workspaces).
constexpr int kMaxJoints = 16;

//! A joint-space vector of at most kMaxJoints entries; resizing it never allocates.
using JointVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxJoints, 1>;
//! A 6 x n Jacobian with n <= kMaxJoints; resizing it never allocates.
using Jacobian = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxJoints>;

//! Options of Kinematics::ik().
struct IkOptions {
  int max_iterations = 60;              //!< Levenberg-Marquardt iterations per attempt
  int max_attempts = 100;               //!< the seed first, then random restarts
  double position_tolerance = 1e-5;     //!< m
  double orientation_tolerance = 1e-5;  //!< rad
  double orientation_weight = 0.5;      //!< weight of rad against m in the error
  std::uint64_t seed = 0;               //!< seed of the random restarts (reproducible)
};

//! What happened during one Kinematics::ik() call.
struct IkReport {
  Status status = Status::not_initialized;  //!< ok or unreachable
  int attempts = 0;                         //!< attempts made (1 = the seed sufficed)
  int iterations = 0;                       //!< iterations over all attempts
  double position_error = 0.0;              //!< m, of the returned configuration
  double orientation_error = 0.0;           //!< rad, of the returned configuration
};

//! Kinematics of the chain between two links of a URDF. Immutable once loaded; every const
//! method may be called from several threads at once.
class Kinematics {
 public:
  //! An empty object; use load() or from_tree().
  Kinematics() = default;

  //! Load a URDF file and take the chain from `base_link` to `tip_link`.
  //! \return `file_error` (missing file), `parse_error` (malformed URDF), `unknown_link`
  //!         (a link that is not in the URDF; the message lists the links), or `ok`.
  static Result load(const std::string& urdf_path, const std::string& base_link,
                     const std::string& tip_link, Kinematics& out);

  //! Same as load() for a URDF held in a string.
  static Result load_from_string(const std::string& urdf_xml, const std::string& base_link,
                                 const std::string& tip_link, Kinematics& out);

  //! True once loaded.
  bool loaded() const noexcept { return n_ > 0 || !chain_.segments.empty(); }
  //! Number of movable joints of the chain.
  int n_joints() const noexcept { return n_; }
  //! Names of the movable joints, base to tip.
  const std::vector<std::string>& joint_names() const noexcept { return joint_names_; }
  //! Lower position limits (rad or m); -inf for continuous joints.
  const JointVector& lower() const noexcept { return lower_; }
  //! Upper position limits (rad or m); +inf for continuous joints.
  const JointVector& upper() const noexcept { return upper_; }
  //! Velocity limits (rad/s or m/s); 0 where the URDF gives none.
  const JointVector& velocity_limits() const noexcept { return velocity_; }
  //! The base link's name.
  const std::string& base_link() const noexcept { return base_link_; }
  //! The tip link's name.
  const std::string& tip_link() const noexcept { return tip_link_; }
  //! The robot's name in the URDF.
  const std::string& robot_name() const noexcept { return robot_name_; }
  //! The KDL chain (for KDL's own solvers).
  const KDL::Chain& chain() const noexcept { return chain_; }

  //! True if every q[i] lies in [lower[i] - tol, upper[i] + tol]. Sizes must match.
  bool within_limits(const Eigen::Ref<const Eigen::VectorXd>& q, double tol = 0.0) const noexcept;

  //! Forward kinematics: the tip's pose in the base frame.
  //! \return `size_mismatch` if q.size() != n_joints(), `invalid_argument` on NaN, else `ok`.
  Status fk(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Isometry3d& pose) const noexcept;

  //! The 6 x n geometric Jacobian at q (see the file's conventions).
  Status jacobian(const Eigen::Ref<const Eigen::VectorXd>& q, Jacobian& jac) const noexcept;

  //! Forward kinematics and Jacobian in one pass.
  Status fk_jacobian(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Isometry3d& pose,
                     Jacobian& jac) const noexcept;

  //! Inverse kinematics for position and orientation within the joint limits.
  //!
  //! Levenberg-Marquardt with error-dependent damping (Sugihara 2011) and projection onto
  //! the limits, started from `q_seed`, then from random configurations (seeded by
  //! options.seed) until the tolerances are met or options.max_attempts is reached.
  //! \param target  wanted pose of the tip in the base frame
  //! \param q_seed  first guess (clamped into the limits), size n_joints()
  //! \param q_out   the solution (resized to n_joints()); on failure the best one found
  //! \return `ok`, `unreachable`, `size_mismatch` or `invalid_argument`
  Status ik(const Eigen::Isometry3d& target, const Eigen::Ref<const Eigen::VectorXd>& q_seed,
            JointVector& q_out, const IkOptions& options = IkOptions(),
            IkReport* report = nullptr) const noexcept;

 private:
  static Result from_tree(const KDL::Tree& tree, const std::string& base_link,
                          const std::string& tip_link, const std::string& source, Kinematics& out);
  struct JointModel {
    Eigen::Matrix3d pre_rotation;  // fixed frame from the previous joint to this joint
    Eigen::Vector3d pre_translation;
    Eigen::Vector3d axis;     // unit axis in this joint's frame
    int principal_axis = -1;  // 0, 1, 2 if axis is +-x, +-y, +-z (fast path), else -1
    double axis_sign = 1.0;   // the sign of that principal axis
    bool prismatic = false;
  };
  Status check(const Eigen::Ref<const Eigen::VectorXd>& q) const noexcept;
  static void rotate_about(Eigen::Matrix3d& r, const JointModel& jm, double angle) noexcept;
  template <bool WithJacobian>
  void forward(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Isometry3d& pose,
               Jacobian* jac) const noexcept;

  KDL::Chain chain_;
  std::vector<JointModel> joints_;
  Eigen::Matrix3d post_rotation_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d post_translation_ = Eigen::Vector3d::Zero();
  int n_ = 0;
  std::vector<std::string> joint_names_;
  JointVector lower_, upper_, velocity_;
  std::string base_link_, tip_link_, robot_name_;
};

}  // namespace a2l

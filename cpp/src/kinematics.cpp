// Kinematics from a URDF (kinematics.hpp): the KDL chain flattened into joint models, limits,
// and forward kinematics and the Jacobian; the inverse kinematics is in kinematics_ik.cpp.
#include "a2l/kinematics.hpp"

#include <cmath>
#include <kdl/tree.hpp>
#include <limits>
#include <sstream>

#include "a2l/urdf_to_kdl.hpp"

namespace a2l {
namespace {

Eigen::Matrix3d to_eigen(const KDL::Rotation& r) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = r(i, j);
  return m;
}

Eigen::Vector3d to_eigen(const KDL::Vector& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }

std::string list_links(const KDL::Tree& tree) {
  std::ostringstream ss;
  bool first = true;
  for (const auto& [name, element] : tree.getSegments()) {
    (void)element;
    ss << (first ? "" : ", ") << name;
    first = false;
  }
  return ss.str();
}

}  // namespace

// r <- r * Rot(axis, angle); a principal axis only mixes two columns.
void Kinematics::rotate_about(Eigen::Matrix3d& r, const JointModel& jm, double angle) noexcept {
  if (jm.principal_axis < 0) {
    r = r * Eigen::AngleAxisd(angle, jm.axis).toRotationMatrix();
    return;
  }
  const double c = std::cos(angle), s = jm.axis_sign * std::sin(angle);
  // Columns (i, j) rotated about the third, in the right-handed order x->y->z->x.
  const int i = (jm.principal_axis + 1) % 3, j = (jm.principal_axis + 2) % 3;
  const Eigen::Vector3d ci = r.col(i), cj = r.col(j);
  r.col(i) = c * ci + s * cj;
  r.col(j) = c * cj - s * ci;
}

Result Kinematics::load(const std::string& urdf_path, const std::string& base_link,
                        const std::string& tip_link, Kinematics& out) {
  KDL::Tree tree;
  UrdfInfo info;
  Result r = urdf_file_to_kdl_tree(urdf_path, tree, &info);
  if (!r.ok()) return r;
  Kinematics k;
  r = from_tree(tree, base_link, tip_link, "'" + urdf_path + "'", k);
  if (!r.ok()) return r;
  k.robot_name_ = info.robot_name;
  for (int i = 0; i < k.n_; ++i) {
    const auto it = info.joints.find(k.joint_names_[i]);
    if (it == info.joints.end()) {
      return Result::failure(Status::internal_error, "joint '" + k.joint_names_[i] +
                                                         "' of the KDL chain is not in the URDF");
    }
    const UrdfJointInfo& j = it->second;
    k.lower_[i] = j.lower;
    k.upper_[i] = j.upper;
    k.velocity_[i] = j.velocity;
    if (!j.continuous && !(j.lower <= j.upper)) {
      return Result::failure(Status::parse_error, "URDF '" + urdf_path + "': joint '" +
                                                      k.joint_names_[i] +
                                                      "' has no valid position limits");
    }
  }
  out = std::move(k);
  return Result::success();
}

Result Kinematics::load_from_string(const std::string& urdf_xml, const std::string& base_link,
                                    const std::string& tip_link, Kinematics& out) {
  KDL::Tree tree;
  UrdfInfo info;
  Result r = urdf_string_to_kdl_tree(urdf_xml, tree, "<string>", &info);
  if (!r.ok()) return r;
  Kinematics k;
  r = from_tree(tree, base_link, tip_link, "<string>", k);
  if (!r.ok()) return r;
  k.robot_name_ = info.robot_name;
  for (int i = 0; i < k.n_; ++i) {
    const UrdfJointInfo& j = info.joints.at(k.joint_names_[i]);
    k.lower_[i] = j.lower;
    k.upper_[i] = j.upper;
    k.velocity_[i] = j.velocity;
  }
  out = std::move(k);
  return Result::success();
}

Result Kinematics::from_tree(const KDL::Tree& tree, const std::string& base_link,
                             const std::string& tip_link, const std::string& source,
                             Kinematics& out) {
  const auto& segments = tree.getSegments();
  for (const std::string* link : {&base_link, &tip_link}) {
    if (segments.find(*link) == segments.end()) {
      return Result::failure(Status::unknown_link, "unknown link '" + *link + "' in URDF " +
                                                       source +
                                                       "; its links are: " + list_links(tree));
    }
  }
  KDL::Chain chain;
  if (!tree.getChain(base_link, tip_link, chain)) {
    return Result::failure(Status::unknown_link, "no chain from '" + base_link + "' to '" +
                                                     tip_link + "' in URDF " + source);
  }
  if (static_cast<int>(chain.getNrOfJoints()) > kMaxJoints) {
    return Result::failure(Status::size_mismatch,
                           "the chain from '" + base_link + "' to '" + tip_link + "' has " +
                               std::to_string(chain.getNrOfJoints()) + " movable joints; at most " +
                               std::to_string(kMaxJoints) + " are supported");
  }
  out.chain_ = chain;
  out.base_link_ = base_link;
  out.tip_link_ = tip_link;
  out.joints_.clear();
  out.joint_names_.clear();
  // Each KDL segment is pose(q) = F * J(q) where F = pose(0) is the joint origin in the
  // parent and J(q) the motion about (along) the joint axis expressed in F (see the
  // derivation in docs/kinematics.md). Fixed segments are folded into the next joint's
  // pre-transform, the trailing ones into the post-transform.
  Eigen::Matrix3d acc_r = Eigen::Matrix3d::Identity();
  Eigen::Vector3d acc_t = Eigen::Vector3d::Zero();
  for (const KDL::Segment& seg : chain.segments) {
    const KDL::Frame f = seg.pose(0.0);
    const Eigen::Matrix3d fr = to_eigen(f.M);
    acc_t = acc_t + acc_r * to_eigen(f.p);
    acc_r = acc_r * fr;
    const KDL::Joint& jnt = seg.getJoint();
    if (jnt.getType() == KDL::Joint::Fixed) continue;
    JointModel jm;
    jm.pre_rotation = acc_r;
    jm.pre_translation = acc_t;
    // KDL gives the axis in the parent frame: bring it into the joint frame F.
    jm.axis = (fr.transpose() * to_eigen(jnt.JointAxis())).normalized();
    jm.prismatic = jnt.getType() == KDL::Joint::TransAxis || jnt.getType() == KDL::Joint::TransX ||
                   jnt.getType() == KDL::Joint::TransY || jnt.getType() == KDL::Joint::TransZ;
    for (int a = 0; a < 3; ++a) {
      if (std::abs(std::abs(jm.axis[a]) - 1.0) < 1e-12) {
        jm.principal_axis = a;
        jm.axis_sign = jm.axis[a] > 0 ? 1.0 : -1.0;
        jm.axis = Eigen::Vector3d::Unit(a) * jm.axis_sign;
      }
    }
    out.joints_.push_back(jm);
    out.joint_names_.push_back(jnt.getName());
    acc_r.setIdentity();
    acc_t.setZero();
  }
  out.post_rotation_ = acc_r;
  out.post_translation_ = acc_t;
  out.n_ = static_cast<int>(out.joints_.size());
  out.lower_ = JointVector::Constant(out.n_, -std::numeric_limits<double>::infinity());
  out.upper_ = JointVector::Constant(out.n_, std::numeric_limits<double>::infinity());
  out.velocity_ = JointVector::Zero(out.n_);
  return Result::success();
}

bool Kinematics::within_limits(const Eigen::Ref<const Eigen::VectorXd>& q,
                               double tol) const noexcept {
  if (q.size() != n_) return false;
  for (int i = 0; i < n_; ++i) {
    if (!(q[i] >= lower_[i] - tol && q[i] <= upper_[i] + tol)) return false;
  }
  return true;
}

Status Kinematics::check(const Eigen::Ref<const Eigen::VectorXd>& q) const noexcept {
  if (n_ == 0 && chain_.segments.empty()) return Status::not_initialized;
  if (q.size() != n_) return Status::size_mismatch;
  if (!q.allFinite()) return Status::invalid_argument;
  return Status::ok;
}

template <bool WithJacobian>
void Kinematics::forward(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Isometry3d& pose,
                         Jacobian* jac) const noexcept {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 3, kMaxJoints> origins;
  Eigen::Matrix<double, 3, kMaxJoints> axes;
  for (int k = 0; k < n_; ++k) {
    const JointModel& jm = joints_[k];
    p.noalias() += r * jm.pre_translation;
    r = r * jm.pre_rotation;
    if constexpr (WithJacobian) {
      origins.col(k) = p;
      axes.col(k).noalias() = r * jm.axis;
    }
    if (jm.prismatic) {
      p.noalias() += r * (jm.axis * q[k]);
    } else {
      rotate_about(r, jm, q[k]);
    }
  }
  p.noalias() += r * post_translation_;
  r = r * post_rotation_;
  pose.linear() = r;
  pose.translation() = p;
  pose.makeAffine();
  if constexpr (WithJacobian) {
    jac->resize(6, n_);
    for (int k = 0; k < n_; ++k) {
      const Eigen::Vector3d z = axes.col(k);
      if (joints_[k].prismatic) {
        jac->col(k).head<3>() = z;
        jac->col(k).tail<3>().setZero();
      } else {
        jac->col(k).head<3>() = z.cross(p - origins.col(k));
        jac->col(k).tail<3>() = z;
      }
    }
  }
}

// (the IK, in kinematics_ik.cpp, calls forward<true> without seeing its definition)
template void Kinematics::forward<true>(const Eigen::Ref<const Eigen::VectorXd>& q,
                                        Eigen::Isometry3d& pose, Jacobian* jac) const noexcept;

Status Kinematics::fk(const Eigen::Ref<const Eigen::VectorXd>& q,
                      Eigen::Isometry3d& pose) const noexcept {
  const Status s = check(q);
  if (s != Status::ok) return s;
  forward<false>(q, pose, nullptr);
  return Status::ok;
}

Status Kinematics::jacobian(const Eigen::Ref<const Eigen::VectorXd>& q,
                            Jacobian& jac) const noexcept {
  const Status s = check(q);
  if (s != Status::ok) return s;
  Eigen::Isometry3d pose;
  forward<true>(q, pose, &jac);
  return Status::ok;
}

Status Kinematics::fk_jacobian(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Isometry3d& pose,
                               Jacobian& jac) const noexcept {
  const Status s = check(q);
  if (s != Status::ok) return s;
  forward<true>(q, pose, &jac);
  return Status::ok;
}

}  // namespace a2l

#include "a2l/kinematics.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <kdl/tree.hpp>
#include <limits>
#include <random>
#include <sstream>

#include "a2l/urdf_to_kdl.hpp"

namespace a2l {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using SquareMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxJoints, kMaxJoints>;

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

// Pose error (target - current): position (m), orientation as a rotation vector (rad), both
// in the base frame.
void pose_error(const Eigen::Isometry3d& target, const Eigen::Isometry3d& pose, Vector6& e) {
  e.head<3>() = target.translation() - pose.translation();
  const Eigen::Matrix3d r_err = target.linear() * pose.linear().transpose();
  const Eigen::AngleAxisd aa(r_err);
  e.tail<3>() = aa.angle() * aa.axis();
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

namespace {

// The arguments of Kinematics::ik other than the seed: ok, or invalid_argument.
Status check_ik_arguments(const Eigen::Isometry3d& target, const IkOptions& options) noexcept {
  if (!target.matrix().allFinite() || options.max_attempts < 1 || options.max_iterations < 1 ||
      !(options.position_tolerance > 0) || !(options.orientation_tolerance > 0)) {
    return Status::invalid_argument;
  }
  return Status::ok;
}

// The weighted cost of a pose error `e`.
double ik_cost(const Vector6& e, const Vector6& weights) noexcept {
  return 0.5 * e.dot(weights.cwiseProduct(e));
}

// The working storage of one IK solve for `n` joints (fixed capacities: no allocation).
struct IkScratch {
  explicit IkScratch(int n)
      : q(n), q_try(n), dq(n), g(n), a(n, n), ldlt(n), jac(6, n), jac_try(6, n) {}
  JointVector q, q_try, dq, g;
  SquareMatrix a;
  Eigen::LDLT<SquareMatrix> ldlt;
  Jacobian jac, jac_try;
  Eigen::Isometry3d pose, pose_try;
  Vector6 e, e_try;
};

// The lowest-cost point seen over the attempts, with its errors.
struct IkBest {
  explicit IkBest(int n) : q(n) {}
  double cost = std::numeric_limits<double>::infinity();
  JointVector q;
  double position_error = 0, orientation_error = 0;

  // Keeps `q` (pose error `e`) if its cost is lower.
  void keep(double c, const JointVector& point, const Vector6& e) noexcept {
    if (!(c < cost)) return;
    cost = c;
    q = point;
    position_error = e.head<3>().norm();
    orientation_error = e.tail<3>().norm();
  }
};

// The acceptance of a solution: `q` (pose error `e`) within the tolerances goes into `q_out`,
// its errors and ok into `rep`; false (nothing written) otherwise.
bool accept(const JointVector& q, const Vector6& e, const IkOptions& options, JointVector& q_out,
            IkReport& rep) noexcept {
  const double ep = e.head<3>().norm();
  const double er = e.tail<3>().norm();
  if (!(ep < options.position_tolerance && er < options.orientation_tolerance)) return false;
  q_out = q;
  rep.status = Status::ok;
  rep.position_error = ep;
  rep.orientation_error = er;
  return true;
}

// One Levenberg-Marquardt step with Sugihara's damping (lambda = cost + w_bar) from w.q: the
// point tried is taken when it lowers `cost`, the damping adapted. False when the attempt
// should restart (crawling along a limit, or stuck in a local minimum); `it` the iteration.
template <class Forward, class Clamp>
bool lm_step(const Forward& forward, const Clamp& clamp, const Eigen::Isometry3d& target,
             const Vector6& weights, int it, IkScratch& w, double& cost,
             double& damping_scale) noexcept {
  w.a.noalias() = w.jac.transpose() * weights.asDiagonal() * w.jac;
  w.a.diagonal().array() += damping_scale * (cost + 1e-4);
  w.g.noalias() = w.jac.transpose() * weights.cwiseProduct(w.e);
  w.ldlt.compute(w.a);
  w.dq = w.ldlt.solve(w.g);
  w.q_try = w.q + w.dq;
  clamp(w.q_try);
  forward(w.q_try, w.pose_try, w.jac_try);
  pose_error(target, w.pose_try, w.e_try);
  const double cost_try = ik_cost(w.e_try, weights);
  if (cost_try < cost) {
    w.q.swap(w.q_try);
    w.jac.swap(w.jac_try);
    w.e = w.e_try;
    const bool slow = cost_try > 0.98 * cost && cost_try > 1e-10;
    cost = cost_try;
    damping_scale = std::max(damping_scale * 0.5, 1e-3);
    if (slow && it > 10) return false;  // crawling along a limit: restart
  } else {
    damping_scale *= 8.0;
    if (damping_scale > 1e4) return false;  // stuck in a local minimum: restart
  }
  return true;
}

// One attempt's descent from w.q: true when it accepted a solution (into `q_out` and `rep`),
// else its points' best kept in `best`; the iterations counted in `rep`.
template <class Forward, class Clamp>
bool descend(const Forward& forward, const Clamp& clamp, const Eigen::Isometry3d& target,
             const Vector6& weights, const IkOptions& options, IkScratch& w, IkBest& best,
             JointVector& q_out, IkReport& rep) noexcept {
  forward(w.q, w.pose, w.jac);
  pose_error(target, w.pose, w.e);
  double cost = ik_cost(w.e, weights);
  double damping_scale = 1.0;
  for (int it = 0; it < options.max_iterations; ++it) {
    best.keep(cost, w.q, w.e);
    if (accept(w.q, w.e, options, q_out, rep)) return true;
    ++rep.iterations;
    if (!lm_step(forward, clamp, target, weights, it, w, cost, damping_scale)) break;
  }
  // Evaluate the last point of this attempt too.
  if (accept(w.q, w.e, options, q_out, rep)) return true;
  best.keep(cost, w.q, w.e);
  return false;
}

}  // namespace

Status Kinematics::ik(const Eigen::Isometry3d& target,
                      const Eigen::Ref<const Eigen::VectorXd>& q_seed, JointVector& q_out,
                      const IkOptions& options, IkReport* report) const noexcept {
  IkReport local;
  IkReport& rep = report ? *report : local;
  rep = IkReport();
  Status s = check(q_seed);
  if (s == Status::ok) s = check_ik_arguments(target, options);
  if (s != Status::ok) {
    rep.status = s;
    return s;
  }
  const double w_rot = options.orientation_weight * options.orientation_weight;
  Vector6 weights;
  weights << 1, 1, 1, w_rot, w_rot, w_rot;
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  IkScratch w(n_);
  IkBest best(n_);
  auto forward_jacobian = [this](const JointVector& q, Eigen::Isometry3d& pose, Jacobian& jac) {
    forward<true>(q, pose, &jac);
  };
  auto clamp = [&](JointVector& v) {
    for (int i = 0; i < n_; ++i) v[i] = std::min(std::max(v[i], lower_[i]), upper_[i]);
  };
  auto sample = [&](JointVector& v) {
    for (int i = 0; i < n_; ++i) {
      const double lo = std::isfinite(lower_[i]) ? lower_[i] : -M_PI;
      const double hi = std::isfinite(upper_[i]) ? upper_[i] : M_PI;
      v[i] = lo + (hi - lo) * unit(rng);
    }
  };
  for (int attempt = 0; attempt < options.max_attempts; ++attempt) {
    rep.attempts = attempt + 1;
    if (attempt == 0) {
      w.q = q_seed;
      clamp(w.q);
    } else {
      sample(w.q);
    }
    if (descend(forward_jacobian, clamp, target, weights, options, w, best, q_out, rep)) {
      return Status::ok;
    }
  }
  q_out = best.q;
  rep.status = Status::unreachable;
  rep.position_error = best.position_error;
  rep.orientation_error = best.orientation_error;
  return Status::unreachable;
}

}  // namespace a2l

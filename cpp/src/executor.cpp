#include "a2l/executor.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "rt_guard.hpp"

namespace a2l {

Result Executor::init(const Kinematics& kinematics, const Eigen::Ref<const Eigen::VectorXd>& q0,
                      const ExecutorOptions& options) {
  if (!kinematics.loaded() || kinematics.n_joints() < 1) {
    return Result::failure(Status::not_initialized, "executor: the kinematics are not loaded");
  }
  if (q0.size() != kinematics.n_joints()) {
    return Result::failure(Status::size_mismatch, "executor: q0 has " + std::to_string(q0.size()) +
                                                      " entries, the chain " +
                                                      std::to_string(kinematics.n_joints()) +
                                                      " joints");
  }
  if (!(options.period > 0.0) || !(options.max_speed > 0.0) || !(options.damping >= 0.0) ||
      !(options.position_tolerance > 0.0) || !(options.velocity_margin > 0.0) ||
      !(options.limit_margin >= 0.0) || options.watchdog_ticks < 1 ||
      !(options.orientation_gain >= 0.0 && options.orientation_gain <= 1.0) ||
      !(options.max_angular_speed > 0.0) ||
      !(options.limit_avoidance >= 0.0 && options.limit_avoidance <= 1.0) ||
      !(options.limit_band >= 0.0 && options.limit_band < 0.5)) {
    return Result::failure(Status::invalid_argument,
                           "executor: options out of their domain (period, max_speed, "
                           "position_tolerance, velocity_margin and max_angular_speed > 0; "
                           "damping, limit_margin >= 0; orientation_gain and limit_avoidance "
                           "in [0, 1]; limit_band in [0, 0.5); watchdog_ticks >= 1)");
  }
  kin_ = &kinematics;
  options_ = options;
  const int n = kinematics.n_joints();
  lower_ = kinematics.lower().array() + options.limit_margin;
  upper_ = kinematics.upper().array() - options.limit_margin;
  max_step_.resize(n);
  for (int i = 0; i < n; ++i) {
    const double v = kinematics.velocity_limits()[i];
    max_step_[i] = v > 0.0 ? v * options.velocity_margin * options.period
                           : std::numeric_limits<double>::infinity();
  }
  const Status s = reset(q0);
  if (s != Status::ok) {
    std::ostringstream ss;
    ss << "executor: q0 = (" << q0.transpose() << ") is not a valid start: " << status_name(s);
    kin_ = nullptr;
    return Result::failure(Status::invalid_argument, ss.str());
  }
  return Result::success();
}

Status Executor::reset(const Eigen::Ref<const Eigen::VectorXd>& q0) noexcept {
  if (kin_ == nullptr) return Status::not_initialized;
  if (q0.size() != kin_->n_joints()) return Status::size_mismatch;
  if (!q0.allFinite()) return Status::invalid_argument;
  for (int i = 0; i < q0.size(); ++i) {
    if (q0[i] < lower_[i] || q0[i] > upper_[i]) return Status::joint_limit;
  }
  q_ = q0;
  const Status s = kin_->fk_jacobian(q_, pose_, jac_);
  if (s != Status::ok) return s;
  hold_ = pose_.linear();
  target_ = reference_ = pose_.translation();
  ticks_ = 0;
  scaled_ticks_ = 0;
  reached_ = true;
  return Status::ok;
}

Status Executor::set_orientation(const Eigen::Matrix3d& rotation) noexcept {
  if (kin_ == nullptr) return Status::not_initialized;
  if (!rotation.allFinite() || rotation.determinant() <= 0.0 ||
      ((rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() >
       1e-6)) {
    return Status::invalid_argument;
  }
  hold_ = rotation;
  return Status::ok;
}

Status Executor::set_target(const Eigen::Vector3d& position) noexcept {
  if (kin_ == nullptr) return Status::not_initialized;
  if (!position.allFinite() || (position.array() < options_.workspace_min.array()).any() ||
      (position.array() > options_.workspace_max.array()).any()) {
    return Status::workspace_limit;
  }
  target_ = position;
  reference_ = pose_.translation();
  ticks_ = 0;
  reached_ = (target_ - reference_).norm() <= options_.position_tolerance;
  return Status::ok;
}

bool Executor::limit_push(JointVector& away) const noexcept {
  const int n = kin_->n_joints();
  away.setZero(n);
  if (!(options_.limit_avoidance > 0.0) || n <= 6) return false;  // no null space beside 6-D
  bool any = false;
  for (int i = 0; i < n; ++i) {
    const double band = options_.limit_band * (upper_[i] - lower_[i]);
    if (!(band > 0.0) || !std::isfinite(band)) continue;
    double depth = 0.0;  // in [-1, 1]: how deep into a band, signed toward the interior
    if (q_[i] < lower_[i] + band) depth = std::min(1.0, (lower_[i] + band - q_[i]) / band);
    if (q_[i] > upper_[i] - band) depth = -std::min(1.0, (q_[i] - (upper_[i] - band)) / band);
    if (depth == 0.0) continue;
    const double rate = std::isfinite(max_step_[i]) ? max_step_[i] : options_.period;
    away[i] = options_.limit_avoidance * depth * rate;
    any = true;
  }
  return any;
}

Status Executor::tick() noexcept {
  [[maybe_unused]] const detail::RealTimeSection rt;
  if (kin_ == nullptr) return Status::not_initialized;
  if (++ticks_ > options_.watchdog_ticks && !reached_) return Status::unreachable;
  // Advance the reference toward the target at most max_speed * period.
  const double max_move = options_.max_speed * options_.period;
  Eigen::Vector3d to_target = target_ - reference_;
  const double dist = to_target.norm();
  if (dist > max_move) to_target *= max_move / dist;
  const Eigen::Vector3d reference = reference_ + to_target;

  Eigen::Matrix<double, 6, 1> err;
  err.head<3>() = reference - pose_.translation();
  const Eigen::AngleAxisd aa(hold_ * pose_.linear().transpose());
  // AngleAxis' angle is in [0, pi]: the correction's size, capped per tick.
  const double turn = std::min(options_.orientation_gain * aa.angle(),
                               options_.max_angular_speed * options_.period);
  err.tail<3>() = turn * aa.axis();

  Eigen::Matrix<double, 6, 6> a = jac_ * jac_.transpose();
  a.diagonal().array() += options_.damping * options_.damping;
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(a);
  JointVector dq = jac_.transpose() * ldlt.solve(err);
  const int n = kin_->n_joints();
  // Away from the joint limits, in the task's null space (limit_push()), through
  // (I - J^T (J J^T + lambda^2 I)^-1 J), which leaves the end-effector's motion as it is.
  JointVector away(n);
  if (limit_push(away)) dq += away - jac_.transpose() * ldlt.solve(jac_ * away);
  if (!dq.allFinite()) return Status::internal_error;
  double scale = 1.0;  // the largest share of dq within every joint's velocity limit
  for (int i = 0; i < n; ++i) {
    if (std::abs(dq[i]) > max_step_[i]) scale = std::min(scale, max_step_[i] / std::abs(dq[i]));
  }
  if (scale < 1.0) {
    if (!options_.scale_velocity) return Status::velocity_limit;
    dq *= scale;
  }
  JointVector q = q_ + dq;
  for (int i = 0; i < n; ++i) {
    if (q[i] < lower_[i] || q[i] > upper_[i]) return Status::joint_limit;
  }
  Eigen::Isometry3d pose;
  Jacobian jac;
  const Status s = kin_->fk_jacobian(q, pose, jac);
  if (s != Status::ok) return Status::internal_error;
  q_ = q;
  pose_ = pose;
  jac_ = jac;
  // a scaled command: the reference waits, advancing by the share the arm was given
  reference_ += scale * to_target;
  if (scale < 1.0) ++scaled_ticks_;
  reached_ = (target_ - pose_.translation()).norm() <= options_.position_tolerance &&
             (target_ - reference_).norm() <= options_.position_tolerance;
  return Status::ok;
}

}  // namespace a2l

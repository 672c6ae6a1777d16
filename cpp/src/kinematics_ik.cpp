// Kinematics::ik (kinematics.hpp): Levenberg-Marquardt with Sugihara's damping, projected onto
// the joint limits, from the seed then random restarts; fixed-capacity storage, no allocation.
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "a2l/kinematics.hpp"

namespace a2l {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using SquareMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxJoints, kMaxJoints>;

// Pose error (target - current): position (m), orientation as a rotation vector (rad), both
// in the base frame.
void pose_error(const Eigen::Isometry3d& target, const Eigen::Isometry3d& pose, Vector6& e) {
  e.head<3>() = target.translation() - pose.translation();
  const Eigen::Matrix3d r_err = target.linear() * pose.linear().transpose();
  const Eigen::AngleAxisd aa(r_err);
  e.tail<3>() = aa.angle() * aa.axis();
}

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

// Time parameterization of a transit's path (transit.hpp): time_parameterize (a rest-to-rest
// trapezoidal profile on each edge) and the joint limits TransitPlanner::plan times it within.
#include "transit_timing.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "a2l/transit.hpp"

namespace a2l {

namespace {

// Rest-to-rest profile of s in [0, 1] with |s'| <= v and |s''| <= a.
struct Profile {
  double v = 0, a = 0, t_acc = 0, t_total = 0, v_peak = 0;
  explicit Profile(double vmax, double amax) : v(vmax), a(amax) {
    t_acc = v / a;
    if (a * t_acc * t_acc >= 1.0) {  // triangle: never reaches v
      t_acc = std::sqrt(1.0 / a);
      v_peak = a * t_acc;
      t_total = 2 * t_acc;
    } else {
      v_peak = v;
      t_total = 2 * t_acc + (1.0 - a * t_acc * t_acc) / v;
    }
  }
  // s, s', s'' at time t in [0, t_total]
  void at(double t, double& s, double& sd, double& sdd) const {
    const double s_acc = 0.5 * a * t_acc * t_acc;
    if (t <= t_acc) {
      s = 0.5 * a * t * t, sd = a * t, sdd = a;
    } else if (t >= t_total - t_acc) {
      const double r = std::max(0.0, t_total - t);
      s = 1.0 - 0.5 * a * r * r, sd = a * r, sdd = -a;
    } else {
      s = s_acc + v_peak * (t - t_acc), sd = v_peak, sdd = 0.0;
    }
    s = std::min(1.0, std::max(0.0, s));
  }
};

}  // namespace

Result time_parameterize(const Eigen::Ref<const Eigen::MatrixXd>& waypoints,
                         const Eigen::Ref<const Eigen::VectorXd>& velocity,
                         const Eigen::Ref<const Eigen::VectorXd>& acceleration,
                         double sample_period, TransitResult& out) {
  const Eigen::Index m = waypoints.rows(), n = waypoints.cols();
  if (m < 1 || velocity.size() != n || acceleration.size() != n)
    return Result::failure(Status::size_mismatch,
                           "time_parameterize: need (m >= 1, n) waypoints and (n,) limits");
  if (!waypoints.allFinite() || !(velocity.array() > 0).all() ||
      !(acceleration.array() > 0).all() || !(sample_period > 0) || !velocity.allFinite() ||
      !acceleration.allFinite())
    return Result::failure(Status::invalid_argument,
                           "time_parameterize: limits and sample period must be finite and > 0");
  std::vector<Profile> profiles;
  std::vector<Eigen::Index> edges;
  std::vector<double> starts;
  double t = 0.0;
  for (Eigen::Index k = 0; k + 1 < m; ++k) {
    const Eigen::VectorXd d = waypoints.row(k + 1) - waypoints.row(k);
    double vs = INFINITY, as = INFINITY;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double di = std::abs(d[i]);
      if (di <= 0) continue;
      vs = std::min(vs, velocity[i] / di);
      as = std::min(as, acceleration[i] / di);
    }
    if (!std::isfinite(vs)) continue;  // a repeated vertex
    profiles.emplace_back(vs, as);
    edges.push_back(k);
    starts.push_back(t);
    t += profiles.back().t_total;
  }
  out.duration = t;
  const Eigen::Index k_samples = static_cast<Eigen::Index>(std::ceil(t / sample_period - 1e-9)) + 1;
  out.times.resize(k_samples);
  out.positions.resize(k_samples, n);
  out.velocities.resize(k_samples, n);
  out.accelerations.resize(k_samples, n);
  size_t e = 0;
  for (Eigen::Index j = 0; j < k_samples; ++j) {
    const double tj = std::min(t, j * sample_period);
    out.times[j] = tj;
    while (e + 1 < profiles.size() && tj > starts[e] + profiles[e].t_total) ++e;
    if (profiles.empty()) {
      out.positions.row(j) = waypoints.row(m - 1);
      out.velocities.row(j).setZero();
      out.accelerations.row(j).setZero();
      continue;
    }
    double s, sd, sdd;
    profiles[e].at(std::min(tj - starts[e], profiles[e].t_total), s, sd, sdd);
    const Eigen::RowVectorXd q0 = waypoints.row(edges[e]);
    const Eigen::RowVectorXd d = waypoints.row(edges[e] + 1) - q0;
    out.positions.row(j) = q0 + s * d;
    out.velocities.row(j) = sd * d;
    out.accelerations.row(j) = sdd * d;
  }
  return Result::success();
}

namespace detail {

// The trajectory's joint limits: velocity (the URDF's, else default_velocity, times
// velocity_scale) and acceleration.
void trajectory_limits(const Kinematics& kin, const TransitOptions& o, Eigen::VectorXd& vel,
                       Eigen::VectorXd& acc) {
  const int n = kin.n_joints();
  vel.resize(n);
  acc.resize(n);
  for (int i = 0; i < n; ++i) {
    const double v = kin.velocity_limits()[i];
    vel[i] = (v > 0 ? v : o.default_velocity) * o.velocity_scale;
    acc[i] = o.acceleration;
  }
}

}  // namespace detail

}  // namespace a2l

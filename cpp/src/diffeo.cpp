// diffeo.cpp:
// Evaluation of the diffeomorphic DS: the maps applied and undone (one scalar
// solve per map), Jacobian, velocity, rollout, and the query timing. Validation and
// construction are in diffeo_maps.cpp.
#include "a2l/diffeo.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

namespace a2l {

namespace {

// exp(phi) for |phi| <= 1/32: Taylor polynomial of degree 8 (Estrin's scheme); relative error
// below 1e-19.
inline double exp_small(double phi) noexcept {
  const double p2 = phi * phi, p4 = p2 * p2;
  const double q01 = 1.0 + phi, q23 = 0.5 + phi * (1.0 / 6.0);
  const double q45 = 1.0 / 24.0 + phi * (1.0 / 120.0), q67 = 1.0 / 720.0 + phi * (1.0 / 5040.0);
  return (q01 + p2 * q23) + p4 * ((q45 + p2 * q67) + p4 * (1.0 / 40320.0));
}

constexpr double kSmallPhi = 1.0 / 32.0;
// Halley's error after a step s is about C |s|^3 with C = O(1 / g'^2) under the invertibility
// bound (the second and third derivatives of g are O(1)): accepting |s|^3 <= kAccept g'^2 leaves
// an error below ~1e-17.
constexpr double kAccept = 3e-20;

}  // namespace

// Undo one map at y, z = y - c. With t0 = rho^2 ||z||^2, a = 2 rho^2 z.v and b = rho^2 ||v||^2,
// the weight k solves g(k) = k - exp(-t0) exp(phi(k)) = 0 with phi(k) = k (a - b k):
// g(0) <= 0 <= g(1) and g' >= 1 - rho ||v|| / sqrt(e/2) > 0 under the bound, so [0, 1] brackets
// the one root. At k: g' = 1 - e (a - 2 b k), g'' = -e ((a - 2 b k)^2 - 2 b), e = exp(-t0 + phi).
// While |phi| <= 1/32, exp(phi) is a short polynomial: most solves need one exp, exp(-t0).
// A far map (e0 = exp(-t0) <= 1e-4) needs no iteration: the root's series in e0.
template <int D>
double DiffeoDS<D>::solve_weight(const Map& m, const Vec& z) noexcept {
  const double zz = z.squaredNorm();
  if (zz >= m.skip_zz) return 0.0;  // the root weight is below exp(-negligible)
  const double t0 = m.rho2 * zz;
  const double a = 2.0 * m.rho2 * z.dot(m.v), b = m.rho2 * m.vv;
  const double e0 = std::exp(-t0);
  if (e0 == 0.0) return 0.0;  // g(0) = 0
  const double a2 = a * a;
  if (e0 <= 1e-4) {
    // A far map: the root's series in e0 (Lagrange inversion of k = e0 exp(phi(k))) to fifth
    // order. Here rho ||z|| >= 3.03, so |a| e0 <= 2 rho||z|| rho||v|| e0 < 7.1e-4 and the first
    // omitted term, e0^6 (10.8 a^5 - 36 a^3 b + 18 a b^2), is below 2e-19.
    const double c4 = a * (8.0 / 3.0 * a2 - 4.0 * b);
    const double c5 = (125.0 / 24.0) * a2 * a2 - 12.5 * a2 * b + 2.5 * b * b;
    return e0 * (1.0 + e0 * (a + e0 * ((1.5 * a2 - b) + e0 * (c4 + e0 * c5))));
  }
  // e(k) = exp(-rho^2 ||z - k v||^2) = e0 exp(phi(k)): a short polynomial while |phi| <= 1/32
  // (here t0 < 9.3, so e0 is a normal number)
  const auto weight_at = [&](double k) {
    const double phi = k * (a - b * k);
    return std::abs(phi) <= kSmallPhi ? e0 * exp_small(phi)
                                      : std::exp(-m.rho2 * (z - k * m.v).squaredNorm());
  };
  // Start from the third-order series, close to the root while e0 is small (on the LASA fields
  // one Halley step is then accepted in most solves, instead of two from k = 0). Halley steps
  // safeguarded as Numerical Recipes' rtsafe (bisection whenever a step leaves the bracket or
  // does not halve the step before last), at most kDiffeoMaxIterations.
  double k = e0 * (1.0 + e0 * (a + e0 * (1.5 * a2 - b)));
  if (!(k > 0.0 && k < 1.0)) k = e0 < 1.0 ? e0 : 0.5;
  double lo = 0.0, hi = 1.0, dx_old = 2.0, dx = 2.0, e = weight_at(k);
  for (int it = 0; it < kDiffeoMaxIterations; ++it) {
    const double g = k - e;
    if (g < 0.0) {
      lo = k;
    } else if (g > 0.0) {
      hi = k;
    } else {
      return k;
    }
    const double ak = a - 2.0 * b * k;
    const double gp = 1.0 - e * ak, gpp = -e * (ak * ak - 2.0 * b);
    const double den = 2.0 * gp * gp - g * gpp;
    // Halley's step while its correction to Newton's is mild, else Newton's
    const double step = den > gp * gp ? 2.0 * g * gp / den : g / gp;
    double kn = k - step;
    if (!(kn > lo && kn < hi) || std::abs(2.0 * step) > std::abs(dx_old)) {
      dx_old = dx;
      dx = 0.5 * (hi - lo);
      kn = lo + dx;
      if (dx <= 1e-17) return kn;
    } else {
      dx_old = dx;
      dx = step;
      if (std::abs(step) * step * step <= kAccept * gp * gp) return kn;
    }
    k = kn;
    e = weight_at(k);
  }
  return k;
}

template <int D>
typename DiffeoDS<D>::Vec DiffeoDS<D>::apply(const Vec& x) const noexcept {
  Vec p = x;
  for (const Map& m : maps_) {
    const double r2 = m.rho2 * (p - m.c).squaredNorm();
    if (r2 > negligible_) continue;  // weight < exp(-negligible): skipped
    p += std::exp(-r2) * m.v;
  }
  return p;
}

template <int D>
typename DiffeoDS<D>::Vec DiffeoDS<D>::apply_jacobian(const Vec& x, Mat& jac) const noexcept {
  Vec p = x;
  Mat j = Mat::Identity();
  for (const Map& m : maps_) {
    const Vec w = p - m.c;
    const double r2 = m.rho2 * w.squaredNorm();
    if (r2 > negligible_) continue;  // weight < exp(-negligible): skipped
    const double k = std::exp(-r2);
    // J_i = I - 2 rho^2 k v w^T, J <- J_i J
    const Eigen::Matrix<double, 1, D> wj = w.transpose() * j;
    j.noalias() -= (2.0 * m.rho2 * k * m.v) * wj;
    p += k * m.v;
  }
  jac = j;
  return p;
}

template <int D>
typename DiffeoDS<D>::Vec DiffeoDS<D>::undo(const Vec& y) const noexcept {
  Vec p = y;
  for (auto it = maps_.rbegin(); it != maps_.rend(); ++it) {
    const double k = solve_weight(*it, p - it->c);
    p -= k * it->v;
  }
  return p;
}

template <int D>
typename DiffeoDS<D>::Vec DiffeoDS<D>::velocity_undo(const Vec& x, Vec& z) const noexcept {
  Vec p = x;
  Mat j = Mat::Identity();  // J_{K-1} ... J_i after undoing map i
  for (auto it = maps_.rbegin(); it != maps_.rend(); ++it) {
    const Map& m = *it;
    const double k = solve_weight(m, p - m.c);
    if (k == 0.0) continue;
    p -= k * m.v;
    // J <- J J_i with J_i = I - 2 rho^2 k v w^T at the map's input p = c + w
    const Vec jv = j * m.v;
    j.noalias() -= (2.0 * m.rho2 * k * jv) * (p - m.c).transpose();
  }
  z = p;
  return speed_ * (j * (target_ - p));
}

namespace {

// x = a^{-1} b for a fixed-size 2x2 or 3x3 (cofactors: no allocation); false if det(a) is 0 or
// not finite. Every factor of J_C has det 1 - 2 rho^2 k v.w >= 1 - rho ||v|| / sqrt(e/2) > 0
// under the bound, so det(J_C) > 0 unless it underflows.
template <int D>
bool solve_small(const Eigen::Matrix<double, D, D>& a, const Eigen::Matrix<double, D, 1>& b,
                 Eigen::Matrix<double, D, 1>& x) noexcept {
  const double det = a.determinant();
  if (!(det != 0.0) || !std::isfinite(det)) return false;
  x = a.inverse() * b;
  return true;
}

}  // namespace

template <int D>
bool DiffeoDS<D>::velocity_apply(const Vec& x, Vec& xdot, Vec& z) const noexcept {
  Mat j;
  z = apply_jacobian(x, j);
  return solve_small<D>(j, speed_ * (target_ - z), xdot);
}

template <int D>
Status DiffeoDS<D>::forward(const Vec& x, Vec& y) const noexcept {
  if (!x.allFinite()) return Status::invalid_argument;
  const Vec p = direction_ == DiffeoDirection::to_demo ? apply(x) : undo(x);
  if (!p.allFinite()) return Status::invalid_argument;
  y = p;
  return Status::ok;
}

template <int D>
Status DiffeoDS<D>::inverse(const Vec& y, Vec& x) const noexcept {
  if (!y.allFinite()) return Status::invalid_argument;
  const Vec p = direction_ == DiffeoDirection::to_demo ? undo(y) : apply(y);
  if (!p.allFinite()) return Status::invalid_argument;
  x = p;
  return Status::ok;
}

template <int D>
Status DiffeoDS<D>::jacobian(const Vec& x, Vec& y, Mat& jac) const noexcept {
  if (!x.allFinite()) return Status::invalid_argument;
  Vec p;
  Mat j;
  if (direction_ == DiffeoDirection::to_demo) {
    p = apply_jacobian(x, j);
  } else {
    // Phi = C^{-1}: J_Phi(x) = J_C(Phi(x))^{-1}
    p = undo(x);
    Mat jc;
    apply_jacobian(p, jc);
    const double det = jc.determinant();
    if (!(det != 0.0) || !std::isfinite(det)) return Status::invalid_argument;
    j = jc.inverse();
  }
  if (!p.allFinite() || !j.allFinite()) return Status::invalid_argument;
  y = p;
  jac = j;
  return Status::ok;
}

template <int D>
Status DiffeoDS<D>::velocity(const Vec& x, Vec& xdot, Vec& z) const noexcept {
  if (!x.allFinite()) return Status::invalid_argument;
  Vec p, f;
  if (direction_ == DiffeoDirection::to_demo) {
    f = velocity_undo(x, p);
  } else if (!velocity_apply(x, f, p)) {
    return Status::invalid_argument;
  }
  if (!f.allFinite() || !p.allFinite()) return Status::invalid_argument;
  xdot = f;
  z = p;
  return Status::ok;
}

template <int D>
Status DiffeoDS<D>::velocity(const Vec& x, Vec& xdot) const noexcept {
  Vec z;
  return velocity(x, xdot, z);
}

template <int D>
Status DiffeoDS<D>::rollout(const Vec& x0, double dt, std::size_t steps, Vec* out,
                            DiffeoIntegrator method) const noexcept {
  if (!x0.allFinite() || !std::isfinite(dt) || !(dt > 0.0)) return Status::invalid_argument;
  if (steps == 0) return Status::ok;
  if (out == nullptr) return Status::size_mismatch;
  out[0] = x0;
  if (method == DiffeoIntegrator::exact) {
    Vec z0;
    const Status s = inverse(x0, z0);
    if (s != Status::ok) return s;
    const Vec d0 = z0 - target_;
    for (std::size_t i = 1; i < steps; ++i) {
      const Vec z = target_ + std::exp(-speed_ * dt * static_cast<double>(i)) * d0;
      const Status si = forward(z, out[i]);
      if (si != Status::ok) return si;
    }
    return Status::ok;
  }
  Vec x = x0, k1, k2, k3, k4;
  for (std::size_t i = 1; i < steps; ++i) {
    Status s = velocity(x, k1);
    if (s != Status::ok) return s;
    if (method == DiffeoIntegrator::euler) {
      x += dt * k1;
    } else {
      if ((s = velocity(x + 0.5 * dt * k1, k2)) != Status::ok) return s;
      if ((s = velocity(x + 0.5 * dt * k2, k3)) != Status::ok) return s;
      if ((s = velocity(x + dt * k3, k4)) != Status::ok) return s;
      x += (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    if (!x.allFinite()) return Status::invalid_argument;
    out[i] = x;
  }
  return Status::ok;
}

template class DiffeoDS<2>;
template class DiffeoDS<3>;

template <int D>
Result time_velocity(const DiffeoDS<D>& ds, const double* points, std::size_t n_points, int repeats,
                     DiffeoTiming& out) {
  using Vec = typename DiffeoDS<D>::Vec;
  using clock = std::chrono::steady_clock;
  if (points == nullptr || n_points == 0 || repeats < 1) {
    return Result::failure(Status::size_mismatch, "time_velocity: needs points and repeats >= 1");
  }
  std::vector<double> times;
  times.reserve(n_points * static_cast<std::size_t>(repeats));
  Vec sink = Vec::Zero(), v;
  for (std::size_t i = 0; i < n_points; ++i) {  // warm-up, and every query must succeed
    if (ds.velocity(Eigen::Map<const Vec>(points + i * D), v) != Status::ok) {
      return Result::failure(Status::invalid_argument,
                             "time_velocity: query " + std::to_string(i) + " fails (not finite)");
    }
    sink += v;
  }
  for (int r = 0; r < repeats; ++r) {
    for (std::size_t i = 0; i < n_points; ++i) {
      const Vec x = Eigen::Map<const Vec>(points + i * D);
      const auto t0 = clock::now();
      ds.velocity(x, v);
      const auto t1 = clock::now();
      sink += v;
      times.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
    }
  }
  std::sort(times.begin(), times.end());
  const std::size_t n = times.size();
  double total = 0.0;
  for (double t : times) total += t;
  out.n = n;
  out.median_ns = n % 2 ? times[n / 2] : 0.5 * (times[n / 2 - 1] + times[n / 2]);
  out.p999_ns = times[std::min(n - 1, static_cast<std::size_t>(std::ceil(0.999 * n)) - 1)];
  out.mean_ns = total / static_cast<double>(n);
  out.max_ns = times.back();
  if (!sink.allFinite())
    return Result::failure(Status::internal_error, "time_velocity: not finite");
  return Result::success();
}

template Result time_velocity<2>(const DiffeoDS<2>&, const double*, std::size_t, int,
                                 DiffeoTiming&);
template Result time_velocity<3>(const DiffeoDS<3>&, const double*, std::size_t, int,
                                 DiffeoTiming&);

}  // namespace a2l

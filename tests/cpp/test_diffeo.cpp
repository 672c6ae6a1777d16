// The diffeomorphic DS (diffeo.hpp): inverse(forward(x)) = x, the Jacobian against finite
// differences, the velocity against an independent plain implementation (bisection inverse,
// explicit matrix products), rollouts from far outside the data, refusal of maps that break
// the invertibility bound (naming the map), non-finite input, and no allocation per call.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

#include "a2l/diffeo.hpp"
#include "alloc_counter.hpp"

namespace test_diffeo {

using a2l::DiffeoDS;
using a2l::DiffeoIntegrator;
using a2l::DiffeoMaps;
using a2l::Status;

static_assert(noexcept(std::declval<const DiffeoDS<2>&>().velocity(
                  std::declval<const Eigen::Vector2d&>(), std::declval<Eigen::Vector2d&>())),
              "velocity() must be noexcept");
static_assert(noexcept(std::declval<const DiffeoDS<3>&>().inverse(
                  std::declval<const Eigen::Vector3d&>(), std::declval<Eigen::Vector3d&>())),
              "inverse() must be noexcept");

// K random maps in [-scale, scale]^d with rho ||v|| = mu * sqrt(e/2), mu in [mu_lo, mu_hi].
DiffeoMaps random_maps(int d, int k, std::uint64_t seed, double mu_lo = 0.2, double mu_hi = 0.9,
                       double scale = 10.0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(-scale, scale), mu(mu_lo, mu_hi), len(0.5, 4.0);
  std::normal_distribution<double> n01;
  DiffeoMaps m;
  m.dim = d;
  m.speed = 1.7;
  for (int j = 0; j < d; ++j) m.target.push_back(0.5 * pos(rng));
  for (int i = 0; i < k; ++i) {
    std::vector<double> v(static_cast<std::size_t>(d));
    double nv = 0.0;
    for (double& x : v) {
      x = n01(rng);
      nv += x * x;
    }
    nv = std::sqrt(nv);
    const double l = len(rng);
    for (int j = 0; j < d; ++j) {
      m.centers.push_back(pos(rng));
      m.vectors.push_back(v[static_cast<std::size_t>(j)] / nv * l);
    }
    m.rhos.push_back(mu(rng) * a2l::kDiffeoInvertibilityBound / l);
  }
  return m;
}

// The same maps going the other way.
DiffeoMaps with_direction(DiffeoMaps m, a2l::DiffeoDirection d) {
  m.direction = d;
  return m;
}
constexpr a2l::DiffeoDirection kToDemo = a2l::DiffeoDirection::to_demo;
constexpr a2l::DiffeoDirection kToLine = a2l::DiffeoDirection::to_line;

template <int D>
DiffeoDS<D> make(const DiffeoMaps& m) {
  DiffeoDS<D> ds;
  const a2l::Result r = DiffeoDS<D>::create(m, ds);
  EXPECT_TRUE(r.ok()) << r.message;
  return ds;
}

template <int D>
typename DiffeoDS<D>::Vec random_point(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  typename DiffeoDS<D>::Vec x;
  for (int j = 0; j < D; ++j) x[j] = u(rng);
  return x;
}

// ---- an independent plain implementation: per-map bisection, explicit matrices ------------
template <int D>
struct Plain {
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  const DiffeoMaps& m;
  Vec c(int i) const { return Eigen::Map<const Vec>(m.centers.data() + i * D); }
  Vec v(int i) const { return Eigen::Map<const Vec>(m.vectors.data() + i * D); }
  double r2(int i) const { return m.rhos[static_cast<std::size_t>(i)] * m.rhos[i]; }
  Mat jac_map(int i, const Vec& x) const {
    const double k = std::exp(-r2(i) * (x - c(i)).squaredNorm());
    return Mat::Identity() - 2.0 * r2(i) * k * v(i) * (x - c(i)).transpose();
  }
  Vec apply(Vec x) const {
    for (int i = 0; i < m.n_maps(); ++i) x += std::exp(-r2(i) * (x - c(i)).squaredNorm()) * v(i);
    return x;
  }
  Mat apply_jacobian(Vec p) const {
    Mat j = Mat::Identity();
    for (int i = 0; i < m.n_maps(); ++i) {
      j = jac_map(i, p) * j;
      p += std::exp(-r2(i) * (p - c(i)).squaredNorm()) * v(i);
    }
    return j;
  }
  bool to_line() const { return m.direction == a2l::DiffeoDirection::to_line; }
  Vec forward(const Vec& x) const { return to_line() ? undo(x) : apply(x); }
  Vec inverse(const Vec& y) const { return to_line() ? apply(y) : undo(y); }
  Vec undo(Vec y) const {
    for (int i = m.n_maps() - 1; i >= 0; --i) {
      double lo = 0.0, hi = 1.0;
      for (int it = 0; it < 200; ++it) {
        const double k = 0.5 * (lo + hi);
        const double g = k - std::exp(-r2(i) * (y - c(i) - k * v(i)).squaredNorm());
        (g < 0.0 ? lo : hi) = k;
      }
      y -= 0.5 * (lo + hi) * v(i);
    }
    return y;
  }
  Vec velocity(const Vec& x) const {
    const Vec t = Eigen::Map<const Vec>(m.target.data());
    if (to_line()) {  // x_dot = speed J_C(x)^{-1} (target - C(x)), by a pivoted LU
      return apply_jacobian(x).fullPivLu().solve(m.speed * (t - apply(x)));
    }
    const Vec z = undo(x);
    return m.speed * apply_jacobian(z) * (t - z);
  }
};

template <int D>
void check_round_trip(std::uint64_t seed, a2l::DiffeoDirection way = kToDemo) {
  const DiffeoMaps m = with_direction(random_maps(D, 150, seed), way);
  const DiffeoDS<D> ds = make<D>(m);
  std::mt19937_64 rng(seed + 100);
  double worst = 0.0;
  for (int n = 0; n < 2000; ++n) {
    // half near a center (where the maps bend most), half anywhere
    typename DiffeoDS<D>::Vec x = random_point<D>(rng, 15.0);
    if (n % 2) {
      const int i = n % m.n_maps();
      x = Eigen::Map<const typename DiffeoDS<D>::Vec>(m.centers.data() + i * D) +
          random_point<D>(rng, 0.3);
    }
    typename DiffeoDS<D>::Vec y, back, fwd;
    ASSERT_EQ(ds.forward(x, y), Status::ok);
    ASSERT_EQ(ds.inverse(y, back), Status::ok);
    ASSERT_EQ(ds.forward(back, fwd), Status::ok);
    worst = std::max(worst, (back - x).template lpNorm<Eigen::Infinity>());
    EXPECT_LT((back - x).template lpNorm<Eigen::Infinity>(), 1e-10) << "x = " << x.transpose();
    EXPECT_LT((fwd - y).template lpNorm<Eigen::Infinity>(), 1e-10);
  }
  ::testing::Test::RecordProperty("worst_round_trip", std::to_string(worst));
}

TEST(Diffeo, InverseUndoesForward2D) { check_round_trip<2>(1); }
TEST(Diffeo, InverseUndoesForward3D) { check_round_trip<3>(2); }
TEST(Diffeo, InverseUndoesForwardToLine2D) { check_round_trip<2>(1, kToLine); }
TEST(Diffeo, InverseUndoesForwardToLine3D) { check_round_trip<3>(2, kToLine); }

TEST(Diffeo, InverseNearTheBoundStillConverges) {
  // rho ||v|| up to 0.99 sqrt(e/2): g' gets as small as 0.01, the bracket keeps Newton safe.
  const DiffeoMaps m = random_maps(2, 60, 3, 0.95, 0.99, 3.0);
  const DiffeoDS<2> ds = make<2>(m);
  std::mt19937_64 rng(4);
  for (int n = 0; n < 3000; ++n) {
    const Eigen::Vector2d x = random_point<2>(rng, 4.0);
    Eigen::Vector2d y, back;
    ASSERT_EQ(ds.forward(x, y), Status::ok);
    ASSERT_EQ(ds.inverse(y, back), Status::ok);
    EXPECT_LT((back - x).lpNorm<Eigen::Infinity>(), 1e-9) << x.transpose();
  }
}

template <int D>
void check_jacobian(std::uint64_t seed, a2l::DiffeoDirection way = kToDemo) {
  const DiffeoMaps m = with_direction(random_maps(D, 40, seed, 0.2, 0.9, 5.0), way);
  const DiffeoDS<D> ds = make<D>(m);
  const Plain<D> plain{m};
  std::mt19937_64 rng(seed + 7);
  using Vec = typename DiffeoDS<D>::Vec;
  for (int n = 0; n < 200; ++n) {
    const Vec x = random_point<D>(rng, 6.0);
    Vec y;
    typename DiffeoDS<D>::Mat j;
    ASSERT_EQ(ds.jacobian(x, y, j), Status::ok);
    Vec y2;
    ASSERT_EQ(ds.forward(x, y2), Status::ok);
    EXPECT_LT((y - y2).norm(), 1e-12);
    EXPECT_LT((y - plain.forward(x)).norm(), 1e-12);
    const double h = 1e-6;
    for (int c = 0; c < D; ++c) {
      Vec xp = x, xm = x, yp, ym;
      xp[c] += h;
      xm[c] -= h;
      ASSERT_EQ(ds.forward(xp, yp), Status::ok);
      ASSERT_EQ(ds.forward(xm, ym), Status::ok);
      const Vec fd = (yp - ym) / (2.0 * h);
      EXPECT_LT((fd - j.col(c)).norm(), 1e-6 * (1.0 + j.col(c).norm())) << "column " << c;
    }
  }
}

TEST(Diffeo, JacobianMatchesFiniteDifferences2D) { check_jacobian<2>(11); }
TEST(Diffeo, JacobianMatchesFiniteDifferences3D) { check_jacobian<3>(12); }
TEST(Diffeo, JacobianMatchesFiniteDifferencesToLine2D) { check_jacobian<2>(11, kToLine); }
TEST(Diffeo, JacobianMatchesFiniteDifferencesToLine3D) { check_jacobian<3>(12, kToLine); }

template <int D>
void check_velocity(std::uint64_t seed, a2l::DiffeoDirection way = kToDemo) {
  const DiffeoMaps m = with_direction(random_maps(D, 150, seed), way);
  const DiffeoDS<D> ds = make<D>(m);
  const Plain<D> plain{m};
  std::mt19937_64 rng(seed + 3);
  using Vec = typename DiffeoDS<D>::Vec;
  for (int n = 0; n < 300; ++n) {
    const Vec x = random_point<D>(rng, 15.0);
    Vec f, z;
    ASSERT_EQ(ds.velocity(x, f, z), Status::ok);
    const Vec ref = plain.velocity(x);
    EXPECT_LT((f - ref).norm(), 1e-9 * (1.0 + ref.norm())) << "x = " << x.transpose();
    EXPECT_LT((z - plain.inverse(x)).norm(), 1e-10);
  }
  // the target is the equilibrium: Phi(target) = target needs the last map; here check
  // f(Phi(target)) = 0 instead (z = target there).
  Vec t = Eigen::Map<const Vec>(m.target.data()), pt, f;
  ASSERT_EQ(ds.forward(t, pt), Status::ok);
  ASSERT_EQ(ds.velocity(pt, f), Status::ok);
  EXPECT_LT(f.norm(), 1e-9);
}

TEST(Diffeo, VelocityMatchesPlainImplementation2D) { check_velocity<2>(21); }
TEST(Diffeo, VelocityMatchesPlainImplementationGentleWideMaps) {
  // as fitted on LASA: wide maps (every weight far from underflow) with rho ||v|| well below
  // the bound, where the weight's exponential is mostly a short polynomial
  const DiffeoMaps m = random_maps(2, 150, 23, 0.01, 0.2, 3.0);
  const DiffeoDS<2> ds = make<2>(m);
  const Plain<2> plain{m};
  std::mt19937_64 rng(24);
  for (int n = 0; n < 300; ++n) {
    const Eigen::Vector2d x = random_point<2>(rng, 5.0);
    Eigen::Vector2d f, z, y, back;
    ASSERT_EQ(ds.velocity(x, f, z), Status::ok);
    const Eigen::Vector2d ref = plain.velocity(x);
    EXPECT_LT((f - ref).norm(), 1e-9 * (1.0 + ref.norm())) << "x = " << x.transpose();
    ASSERT_EQ(ds.forward(x, y), Status::ok);
    ASSERT_EQ(ds.inverse(y, back), Status::ok);
    EXPECT_LT((back - x).lpNorm<Eigen::Infinity>(), 1e-10);
  }
}
TEST(Diffeo, VelocityMatchesPlainImplementation3D) { check_velocity<3>(22); }
TEST(Diffeo, VelocityMatchesPlainImplementationToLine2D) { check_velocity<2>(21, kToLine); }
TEST(Diffeo, VelocityMatchesPlainImplementationToLine3D) { check_velocity<3>(22, kToLine); }

TEST(Diffeo, ToLineVelocityIsTheDerivativeOfTheExactFlow) {
  // to_line's velocity (forward sweep + solve) and its exact flow (the maps applied to x0, the
  // linear flow, the maps undone) are computed by different code: along the flow
  // x(t) = Phi(target + (z0 - target) e^{-speed t}), dx/dt must equal velocity(x(t)).
  const DiffeoMaps m = with_direction(random_maps(2, 150, 25), kToLine);
  const DiffeoDS<2> ds = make<2>(m);
  std::mt19937_64 rng(26);
  for (int n = 0; n < 100; ++n) {
    const Eigen::Vector2d x0 = random_point<2>(rng, 15.0);
    const double h = 1e-5;
    std::vector<Eigen::Vector2d> out(3);
    // states at t = 0, h, 2h; central difference at t = h (error O(h^2) of a stiff field)
    ASSERT_EQ(ds.rollout(x0, h, out.size(), out.data()), Status::ok);
    Eigen::Vector2d f;
    ASSERT_EQ(ds.velocity(out[1], f), Status::ok);
    const Eigen::Vector2d fd = (out[2] - out[0]) / (2.0 * h);
    EXPECT_LT((fd - f).norm(), 1e-4 * (1.0 + f.norm())) << "x0 = " << x0.transpose();
  }
}

TEST(Diffeo, EveryBranchOfTheOneMapSolveIsExact) {
  // one map, points from its center outwards: near (Halley), far (series, weight <= 1e-4) and
  // negligible (skipped, weight < exp(-40)); against 200 bisections. Along v and against it the
  // series' terms in a = 2 rho^2 z.v are largest.
  DiffeoMaps m;
  m.dim = 2;
  m.target = {0.0, 0.0};
  m.centers = {0.3, -0.2};
  m.vectors = {0.8, 0.5};
  m.rhos = {0.85 * a2l::kDiffeoInvertibilityBound / std::hypot(0.8, 0.5)};
  const DiffeoDS<2> ds = make<2>(m);
  const Plain<2> plain{m};
  const Eigen::Vector2d along = Eigen::Vector2d(0.8, 0.5).normalized();
  for (const Eigen::Vector2d dir : {Eigen::Vector2d(0.6, -0.8), along, Eigen::Vector2d(-along)}) {
    for (double r = 0.0; r < 40.0; r += 0.01) {
      const Eigen::Vector2d y = Eigen::Vector2d(0.3, -0.2) + r * dir;
      Eigen::Vector2d x;
      ASSERT_EQ(ds.inverse(y, x), Status::ok);
      EXPECT_LT((x - plain.inverse(y)).norm(), 4e-16 * (1.0 + y.norm()))
          << "r = " << r << ", direction " << dir.transpose();
    }
  }
}

TEST(Diffeo, NegligibleMapsAreSkippedWithinDoublePrecision) {
  // one map, centred so that the query point y = 0 is just beyond the cutoff's reach: the
  // default DS skips the map (inverse returns y itself) while the underflow-only DS still
  // undoes a weight in (0, exp(-40)] (visible at y = 0, invisible next to larger coordinates)
  const double rho = 0.85 * a2l::kDiffeoInvertibilityBound / std::hypot(0.8, 0.5);
  const double reach = 1.001 * std::sqrt(a2l::kDiffeoNegligible) / rho;
  DiffeoMaps one;
  one.dim = 2;
  one.target = {0.0, 0.0};
  one.centers = {-reach * 0.6, reach * 0.8};
  one.vectors = {0.8, 0.5};
  one.rhos = {rho};
  const DiffeoDS<2> cut = make<2>(one);
  DiffeoDS<2> full;
  ASSERT_TRUE(DiffeoDS<2>::create(one, full, a2l::kDiffeoUnderflow).ok());
  EXPECT_EQ(cut.negligible(), a2l::kDiffeoNegligible);
  EXPECT_EQ(full.negligible(), a2l::kDiffeoUnderflow);
  const Eigen::Vector2d y = Eigen::Vector2d::Zero();
  Eigen::Vector2d x_cut, x_full;
  ASSERT_EQ(cut.inverse(y, x_cut), Status::ok);
  ASSERT_EQ(full.inverse(y, x_full), Status::ok);
  EXPECT_EQ(x_cut, y);
  EXPECT_NE(x_full, y);
  EXPECT_LT((x_full - y).norm(), std::exp(-a2l::kDiffeoNegligible) * std::hypot(0.8, 0.5));
  // 150 random maps, points far and near: both cutoffs agree to double precision
  const DiffeoMaps m = random_maps(2, 150, 31);
  const DiffeoDS<2> a = make<2>(m);
  DiffeoDS<2> b;
  ASSERT_TRUE(DiffeoDS<2>::create(m, b, a2l::kDiffeoUnderflow).ok());
  std::mt19937_64 rng(32);
  for (int n = 0; n < 500; ++n) {
    const Eigen::Vector2d p = random_point<2>(rng, 40.0);
    Eigen::Vector2d fa, fb, ya, yb, xa, xb;
    ASSERT_EQ(a.velocity(p, fa), Status::ok);
    ASSERT_EQ(b.velocity(p, fb), Status::ok);
    EXPECT_LT((fa - fb).norm(), 1e-14 * (1.0 + fb.norm())) << "p = " << p.transpose();
    ASSERT_EQ(a.forward(p, ya), Status::ok);
    ASSERT_EQ(b.forward(p, yb), Status::ok);
    EXPECT_LT((ya - yb).norm(), 1e-14 * (1.0 + yb.norm()));
    ASSERT_EQ(a.inverse(p, xa), Status::ok);
    ASSERT_EQ(b.inverse(p, xb), Status::ok);
    EXPECT_LT((xa - xb).norm(), 1e-14 * (1.0 + xb.norm()));
  }
  // the cutoff is refused outside [kDiffeoNegligible, kDiffeoUnderflow]
  DiffeoDS<2> bad;
  EXPECT_EQ(DiffeoDS<2>::create(m, bad, 39.0).status, Status::invalid_argument);
  EXPECT_EQ(DiffeoDS<2>::create(m, bad, 747.0).status, Status::invalid_argument);
  EXPECT_EQ(DiffeoDS<2>::create(m, bad, std::nan("")).status, Status::invalid_argument);
}

TEST(Diffeo, NoMapsIsTheLinearSystem) {
  DiffeoMaps m;
  m.dim = 2;
  m.target = {1.0, -2.0};
  m.speed = 2.0;
  DiffeoDS<2> ds = make<2>(m);
  Eigen::Vector2d f;
  ASSERT_EQ(ds.velocity(Eigen::Vector2d(3.0, 0.0), f), Status::ok);
  EXPECT_NEAR(f[0], -4.0, 1e-15);
  EXPECT_NEAR(f[1], -4.0, 1e-15);
}

template <int D>
void check_rollout(DiffeoIntegrator how, double dt, std::size_t steps, double tol,
                   a2l::DiffeoDirection way = kToDemo) {
  const DiffeoMaps m = with_direction(random_maps(D, 150, 31), way);
  const DiffeoDS<D> ds = make<D>(m);
  using Vec = typename DiffeoDS<D>::Vec;
  const Vec t = Eigen::Map<const Vec>(m.target.data());
  Vec end_point;  // Phi(target): the attractor in x-space (= target once the last map matches)
  ASSERT_EQ(ds.forward(t, end_point), Status::ok);
  std::vector<Vec> out(steps);
  std::mt19937_64 rng(32);
  for (int n = 0; n < 4; ++n) {
    Vec x0 = random_point<D>(rng, 1.0).normalized() * 1000.0;  // far outside the data
    ASSERT_EQ(ds.rollout(x0, dt, steps, out.data(), how), Status::ok);
    EXPECT_EQ(out[0], x0);
    EXPECT_LT((out.back() - end_point).norm(), tol) << "from " << x0.transpose();
  }
}

TEST(Diffeo, RolloutFromFarOutsideConvergesExact) {
  check_rollout<2>(DiffeoIntegrator::exact, 0.05, 800, 1e-6);
  check_rollout<3>(DiffeoIntegrator::exact, 0.05, 800, 1e-6);
  check_rollout<2>(DiffeoIntegrator::exact, 0.05, 800, 1e-6, kToLine);
  check_rollout<3>(DiffeoIntegrator::exact, 0.05, 800, 1e-6, kToLine);
}
TEST(Diffeo, RolloutFromFarOutsideConvergesRk4) {
  check_rollout<2>(DiffeoIntegrator::rk4, 0.02, 2000, 1e-6);
  check_rollout<2>(DiffeoIntegrator::rk4, 0.02, 2000, 1e-6, kToLine);
  check_rollout<3>(DiffeoIntegrator::rk4, 0.02, 2000, 1e-6, kToLine);
}
TEST(Diffeo, RolloutFromFarOutsideConvergesEuler) {
  check_rollout<2>(DiffeoIntegrator::euler, 0.005, 8000, 1e-6);
  check_rollout<2>(DiffeoIntegrator::euler, 0.005, 8000, 1e-6, kToLine);
}

TEST(Diffeo, Rk4ConvergesToTheExactFlow) {
  // RK4's error at t = 2 shrinks as dt^4 towards the exact flow (ratio ~16 per halving).
  const DiffeoMaps m = random_maps(2, 150, 41);
  const DiffeoDS<2> ds = make<2>(m);
  const Eigen::Vector2d x0(12.0, -9.0);
  std::vector<Eigen::Vector2d> exact(2), rk(1601);
  ASSERT_EQ(ds.rollout(x0, 2.0, exact.size(), exact.data()), Status::ok);
  double err[3];
  for (int h = 0; h < 3; ++h) {
    const std::size_t n = 400u << h;
    ASSERT_EQ(ds.rollout(x0, 2.0 / static_cast<double>(n), n + 1, rk.data(), DiffeoIntegrator::rk4),
              Status::ok);
    err[h] = (rk[n] - exact[1]).norm();
  }
  EXPECT_LT(err[2], 1e-6);
  EXPECT_GT(err[0] / err[1], 8.0);
  EXPECT_GT(err[1] / err[2], 8.0);
}

// ---- refusals -----------------------------------------------------------------------------
void expect_refused(const DiffeoMaps& m, Status status, const std::string& needle) {
  DiffeoDS<2> ds2;
  const a2l::Result r = DiffeoDS<2>::create(m, ds2);
  EXPECT_EQ(r.status, status) << r.message;
  EXPECT_NE(r.message.find(needle), std::string::npos)
      << "message '" << r.message << "' does not name '" << needle << "'";
}

TEST(Diffeo, MapBreakingTheBoundIsRefusedByIndex) {
  DiffeoMaps m = random_maps(2, 20, 51);
  ASSERT_TRUE(a2l::validate_diffeo_maps(m).ok());
  // map 7 exactly at the bound, map 12 above it: the first is named
  const double l7 = std::hypot(m.vectors[14], m.vectors[15]);
  m.rhos[7] = a2l::kDiffeoInvertibilityBound / l7 * (1.0 + 1e-12);
  m.rhos[12] *= 10.0;
  expect_refused(m, Status::invalid_argument, "map 7: rho * ||v||");
  m.rhos[7] = 0.5 * a2l::kDiffeoInvertibilityBound / l7;
  expect_refused(m, Status::invalid_argument, "map 12: rho * ||v||");
}

TEST(Diffeo, BadValuesAndShapesAreRefused) {
  const DiffeoMaps good = random_maps(2, 10, 52);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  DiffeoMaps m = good;
  m.centers[7] = nan;
  expect_refused(m, Status::invalid_argument, "map 3: center is not finite");
  m = good;
  m.direction = static_cast<a2l::DiffeoDirection>(2);
  expect_refused(m, Status::invalid_argument, "direction = 2 must be to_demo (0) or to_line (1)");
  m = with_direction(good, kToLine);  // the same checks apply to the other direction
  m.rhos[4] = 2.0 * a2l::kDiffeoInvertibilityBound / std::hypot(m.vectors[8], m.vectors[9]);
  expect_refused(m, Status::invalid_argument, "map 4: rho * ||v||");
  m = good;
  m.vectors[0] = std::numeric_limits<double>::infinity();
  expect_refused(m, Status::invalid_argument, "map 0: vector is not finite");
  m = good;
  m.rhos[4] = -0.1;
  expect_refused(m, Status::invalid_argument, "map 4: rho = -0.1 < 0");
  m = good;
  m.rhos[5] = nan;
  expect_refused(m, Status::invalid_argument, "map 5: rho is not finite");
  m = good;
  m.target[1] = nan;
  expect_refused(m, Status::invalid_argument, "target");
  m = good;
  m.speed = 0.0;
  expect_refused(m, Status::invalid_argument, "speed");
  m = good;
  m.centers.pop_back();
  expect_refused(m, Status::size_mismatch, "centers has 19 values");
  m = good;
  m.vectors.push_back(1.0);
  expect_refused(m, Status::size_mismatch, "vectors has 21 values");
  m = good;
  m.target.push_back(0.0);
  expect_refused(m, Status::size_mismatch, "target has 3 values");
  m = good;
  m.dim = 4;
  EXPECT_EQ(a2l::validate_diffeo_maps(m).status, Status::size_mismatch);
  m = random_maps(3, 5, 53);
  expect_refused(m, Status::size_mismatch, "dim is 3");
  // rho = 0 is allowed (a translation by v), a huge finite v with rho > 0 is not
  m = good;
  m.rhos[2] = 0.0;
  EXPECT_TRUE(a2l::validate_diffeo_maps(m).ok());
  m.vectors[4] = 1e300;
  m.rhos[2] = 1e-10;
  expect_refused(m, Status::invalid_argument, "map 2: rho * ||v||");
}

TEST(Diffeo, NonFiniteInputGivesAStatus) {
  const DiffeoDS<2> ds = make<2>(random_maps(2, 30, 61));
  const double bad[] = {std::numeric_limits<double>::quiet_NaN(),
                        std::numeric_limits<double>::infinity(),
                        -std::numeric_limits<double>::infinity()};
  for (double b : bad) {
    const Eigen::Vector2d x(1.0, b);
    Eigen::Vector2d y = Eigen::Vector2d::Constant(7.0);
    Eigen::Matrix2d j;
    EXPECT_EQ(ds.forward(x, y), Status::invalid_argument);
    EXPECT_EQ(ds.inverse(x, y), Status::invalid_argument);
    EXPECT_EQ(ds.velocity(x, y), Status::invalid_argument);
    EXPECT_EQ(ds.jacobian(x, y, j), Status::invalid_argument);
    EXPECT_EQ(y, Eigen::Vector2d::Constant(7.0));  // outputs untouched on failure
    std::vector<Eigen::Vector2d> out(4);
    EXPECT_EQ(ds.rollout(x, 0.1, out.size(), out.data()), Status::invalid_argument);
  }
  std::vector<Eigen::Vector2d> out(4);
  EXPECT_EQ(ds.rollout(Eigen::Vector2d(1, 1), 0.0, out.size(), out.data()),
            Status::invalid_argument);
  EXPECT_EQ(ds.rollout(Eigen::Vector2d(1, 1), 0.1, out.size(), nullptr), Status::size_mismatch);
  // huge but finite input: every map underflows, the velocity overflows -> a status, not inf
  Eigen::Vector2d f;
  EXPECT_EQ(ds.velocity(Eigen::Vector2d(1.5e308, -1.5e308), f), Status::invalid_argument);
  EXPECT_EQ(ds.velocity(Eigen::Vector2d(1e150, -1e150), f), Status::ok);
  EXPECT_TRUE(f.allFinite());
}

// ---- no allocation ------------------------------------------------------------------------
// The evaluation calls stand inside the NoAlloc test's own body: make test's guarded run selects
// tests by that name, and tests/python/test_rt_test_convention.py checks that every real-time
// call appears in such a test.
template <int D>
struct NoAllocCase {
  DiffeoDS<D> ds;
  std::vector<typename DiffeoDS<D>::Vec> points, out;
};

template <int D>
NoAllocCase<D> no_alloc_case(std::uint64_t seed, a2l::DiffeoDirection way = kToDemo) {
  NoAllocCase<D> c{make<D>(with_direction(random_maps(D, 150, seed), way)),
                   std::vector<typename DiffeoDS<D>::Vec>(5000),
                   std::vector<typename DiffeoDS<D>::Vec>(64)};
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> pick(0, 9);
  for (auto& p : c.points) {
    p = random_point<D>(rng, 20.0);
    const int k = pick(rng);
    if (k == 0) p[0] = std::numeric_limits<double>::quiet_NaN();
    if (k == 1) p[D - 1] = -std::numeric_limits<double>::infinity();
    if (k == 2) p *= 1e200;
  }
  return c;
}

TEST(DiffeoNoAlloc, EvaluationAllocatesNothing) {
  NoAllocCase<2> c2 = no_alloc_case<2>(71);
  NoAllocCase<3> c3 = no_alloc_case<3>(72);
  NoAllocCase<2> l2 = no_alloc_case<2>(73, kToLine);
  NoAllocCase<3> l3 = no_alloc_case<3>(74, kToLine);
  auto evaluate = [](auto& c) {
    using Ds = std::decay_t<decltype(c.ds)>;
    std::size_t ok = 0;
    for (const auto& p : c.points) {
      typename Ds::Vec y, z;
      typename Ds::Mat j;
      ok += c.ds.forward(p, y) == Status::ok;
      ok += c.ds.inverse(p, y) == Status::ok;
      ok += c.ds.jacobian(p, y, j) == Status::ok;
      ok += c.ds.velocity(p, y, z) == Status::ok;
    }
    for (std::size_t n = 0; n < 50; ++n) {
      ok += c.ds.rollout(c.points[n], 0.05, c.out.size(), c.out.data()) == Status::ok;
      ok += c.ds.rollout(c.points[n], 0.05, c.out.size(), c.out.data(), DiffeoIntegrator::rk4) ==
            Status::ok;
    }
    return ok;
  };
  a2l::test::AllocationGuard guard;
  const std::size_t ok2 = evaluate(c2);
  const std::size_t ok3 = evaluate(c3);
  const std::size_t okl2 = evaluate(l2);  // direction to_line: the explicit velocity
  const std::size_t okl3 = evaluate(l3);
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_GT(ok2, 10000u);  // most calls succeeded: the loops did real work
  EXPECT_GT(ok3, 10000u);
  EXPECT_GT(okl2, 10000u);
  EXPECT_GT(okl3, 10000u);
}

TEST(Diffeo, TimingReportsOrderedPercentiles) {
  const DiffeoDS<2> ds = make<2>(random_maps(2, 150, 81));
  std::mt19937_64 rng(82);
  std::vector<double> pts;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector2d p = random_point<2>(rng, 12.0);
    pts.push_back(p[0]);
    pts.push_back(p[1]);
  }
  a2l::DiffeoTiming t;
  ASSERT_TRUE(a2l::time_velocity<2>(ds, pts.data(), 200, 3, t).ok());
  EXPECT_EQ(t.n, 600u);
  EXPECT_GT(t.median_ns, 0.0);
  EXPECT_LE(t.median_ns, t.p999_ns);
  EXPECT_LE(t.p999_ns, t.max_ns);
  pts[5] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(a2l::time_velocity<2>(ds, pts.data(), 200, 1, t).status, Status::invalid_argument);
}

}  // namespace test_diffeo

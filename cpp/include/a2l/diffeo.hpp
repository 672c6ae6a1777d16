//! \file diffeo.hpp
//! \brief The diffeomorphic dynamical system of fast diffeomorphic matching (Perrin &
//! Schlehuber-Caissier 2016; docs/method.md): evaluation for d = 2 and d = 3.
//!
//! K elementary maps psi_i(x) = x + exp(-rho_i^2 ||x - c_i||^2) v_i, each invertible because
//! rho_i ||v_i|| < sqrt(e/2), composed in index order: C = psi_{K-1} o ... o psi_0. The
//! diffeomorphism Phi maps the "line space", where the DS is the linear system
//! z_dot = -speed (z - target), onto the demonstration, with Phi(target) = target. The DS is
//!
//!     x_dot = speed * J_Phi(Phi^{-1}(x)) * (target - Phi^{-1}(x)),
//!
//! globally asymptotically stable at `target`. The maps can be fitted in either direction
//! (DiffeoDirection): `to_demo` (Phi = C, the paper's construction: a velocity query needs
//! Phi^{-1}, K scalar solves) or `to_line` (Phi = C^{-1}: the maps carry the demonstration onto
//! the line, and a velocity query is explicit, x_dot = -speed J_C(x)^{-1} (C(x) - target): K
//! exps and one d x d solve, no iteration). forward() is always Phi and inverse() Phi^{-1}:
//! whichever of the two needs the scalar solves depends on the direction.
//!
//! Evaluation (forward, inverse, jacobian, velocity, rollout) uses fixed-size Eigen vectors,
//! allocates nothing, throws nothing and returns a Status: `invalid_argument` for a non-finite
//! input (or a result that overflows), `size_mismatch` for a wrong buffer size. The inverse of
//! one map is a scalar equation in its weight k (see DiffeoDS::inverse), solved by safeguarded
//! Halley iterations inside a guaranteed bracket with at most kDiffeoMaxIterations iterations:
//! bounded time. A map whose weight at the point is below exp(-kDiffeoNegligible) is skipped
//! there (no exp, no solve): the result changes by less than double precision (see
//! kDiffeoNegligible); the iteration bound holds for every map that is not skipped.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "a2l/status.hpp"

namespace a2l {

//! sqrt(e / 2): an elementary map is a diffeomorphism iff rho * ||v|| < this bound.
inline constexpr double kDiffeoInvertibilityBound = 1.165821990798562;
//! Most iterations of the scalar solve of one map's inverse (bisection alone reaches double
//! precision on [0, 1] within 64 halvings).
inline constexpr int kDiffeoMaxIterations = 64;
//! A map is skipped at a point where its weight k = exp(-rho^2 ||x - c||^2) is below
//! exp(-kDiffeoNegligible) = 4.2e-18 (below the double epsilon 2.2e-16 / 50): skipping it moves
//! the point by less than 4.2e-18 ||v|| and changes the Jacobian factor I - 2 rho^2 k v w^T by
//! less than 2 (rho ||v||) (rho ||w||) k < 6.3e-17 (rho ||v|| < sqrt(e/2), rho ||w|| >= sqrt(40)).
//! The inverse skips a map when ||y - c|| >= sqrt(kDiffeoNegligible) / rho + 4.2e-18 ||v||,
//! which guarantees the root weight is below the same bound.
inline constexpr double kDiffeoNegligible = 40.0;
//! exp(-t) is exactly 0 in double for t above this: the largest cutoff DiffeoDS::create accepts
//! (it skips only maps whose weight underflows; for measuring what the cutoff saves).
inline constexpr double kDiffeoUnderflow = 746.0;
//! Most maps a DS may hold (bundles and bindings refuse more).
inline constexpr int kDiffeoMaxMaps = 100000;

//! Which way the maps go (DiffeoMaps::direction; the bundle's `ds.direction`).
enum class DiffeoDirection : int {
  to_demo = 0,  //!< the composed maps C are Phi: line space -> demonstration (velocity: solves)
  to_line = 1,  //!< C is Phi^{-1}: demonstration -> line space (velocity: explicit)
};

//! "to_demo" / "to_line".
const char* diffeo_direction_name(DiffeoDirection d) noexcept;

//! The maps of a diffeomorphic DS, dimension-agnostic (for loading, writing and bindings).
//! Arrays are row-major: map i's center is centers[i*dim .. i*dim + dim).
struct DiffeoMaps {
  int dim = 0;                                           //!< space dimension, 2 or 3
  std::vector<double> target;                            //!< (dim,) attractor; Phi(target) = target
  std::vector<double> centers;                           //!< (K, dim) centers c_i
  std::vector<double> vectors;                           //!< (K, dim) displacements v_i
  std::vector<double> rhos;                              //!< (K,) inverse widths rho_i >= 0
  double speed = 1.0;                                    //!< gain of the line-space system (> 0)
  DiffeoDirection direction = DiffeoDirection::to_demo;  //!< which way the maps go

  //! Number of maps K (rhos.size()).
  int n_maps() const noexcept { return static_cast<int>(rhos.size()); }
};

//! Check a DS description: dim in {2, 3}; sizes (target dim, centers and vectors K*dim);
//! K <= kDiffeoMaxMaps; direction to_demo or to_line; every value finite; speed > 0; per map
//! rho >= 0 and
//! rho * ||v|| < kDiffeoInvertibilityBound.
//! \return `size_mismatch` / `invalid_argument` with a message naming the first bad map
//!         ("map 7: rho * ||v|| = 1.2 >= sqrt(e/2) = 1.16582 (not invertible)"), else `ok`.
Result validate_diffeo_maps(const DiffeoMaps& maps);

//! How DiffeoDS::rollout integrates the DS.
enum class DiffeoIntegrator : int {
  exact = 0,  //!< the exact flow: z(t) = target + (z0 - target) exp(-speed t), x = Phi(z)
  euler = 1,  //!< explicit Euler on x_dot = f(x) (what a controller applying f each tick does)
  rk4 = 2,    //!< classical Runge-Kutta 4 on x_dot = f(x)
};

//! A diffeomorphic DS in dimension D (2 or 3). Immutable after create(): every method is
//! const, noexcept, allocation-free and may be called from several threads at once.
//! A default-constructed DS has no maps: Phi is the identity, the DS is x_dot = -x.
template <int D>
class DiffeoDS {
 public:
  static_assert(D == 2 || D == 3, "DiffeoDS is instantiated for d = 2 and d = 3");
  using Vec = Eigen::Matrix<double, D, 1>;  //!< a point or a velocity
  using Mat = Eigen::Matrix<double, D, D>;  //!< a Jacobian

  //! Build from `maps` after validate_diffeo_maps() (and maps.dim == D).
  //! \param negligible  the cutoff t: a map is skipped where its weight is below exp(-t);
  //!                    in [kDiffeoNegligible, kDiffeoUnderflow] (the default loses nothing
  //!                    in double; kDiffeoUnderflow skips only weights that underflow)
  //! \return the validation failure (naming the map), else `ok`; `out` is untouched on failure.
  static Result create(const DiffeoMaps& maps, DiffeoDS& out,
                       double negligible = kDiffeoNegligible);

  //! The description it was built from (same values, dim = D).
  DiffeoMaps maps() const;

  //! Number of maps K.
  int n_maps() const noexcept { return static_cast<int>(maps_.size()); }
  //! The attractor.
  const Vec& target() const noexcept { return target_; }
  //! The gain of the line-space system.
  double speed() const noexcept { return speed_; }
  //! The cutoff t of create(): maps whose weight is below exp(-t) are skipped.
  double negligible() const noexcept { return negligible_; }
  //! Which way the maps go.
  DiffeoDirection direction() const noexcept { return direction_; }

  //! y = Phi(x) (to_demo: the maps applied; to_line: the maps undone, as in inverse()).
  //! \return `invalid_argument` if x is not finite or y overflows.
  Status forward(const Vec& x, Vec& y) const noexcept;

  //! x = Phi^{-1}(y) (to_line: the maps applied; to_demo: the maps undone in reverse index
  //! order). Undoing one map, with z = y - c and x = y - k v, the weight k solves
  //! g(k) = k - exp(-rho^2 ||z - k v||^2) = 0 in (0, 1]; g(0) <= 0 <= g(1) and g is strictly
  //! increasing under the invertibility bound, so safeguarded Halley steps (bisection when a
  //! step leaves the bracket) converge within kDiffeoMaxIterations iterations.
  //! \return `invalid_argument` if y is not finite.
  Status inverse(const Vec& y, Vec& x) const noexcept;

  //! y = Phi(x) and its Jacobian J = dPhi/dx at x (to_line: J = J_C(y)^{-1}).
  //! \return `invalid_argument` if not finite.
  Status jacobian(const Vec& x, Vec& y, Mat& jac) const noexcept;

  //! The DS's velocity at x: speed * J_Phi(z) * (target - z), z = Phi^{-1}(x). to_demo: one
  //! inverse sweep, the Jacobian accumulated on the way (K scalar solves); to_line: one
  //! forward sweep of the maps (z = C(x) and J_C(x)), then x_dot = speed * J_C(x)^{-1}
  //! (target - z) by one d x d solve, no iteration. \return `invalid_argument` if x is not
  //! finite, the velocity overflows or (to_line) det J_C is 0 or not finite.
  Status velocity(const Vec& x, Vec& xdot) const noexcept;

  //! Same as velocity(), also returning z = Phi^{-1}(x).
  Status velocity(const Vec& x, Vec& xdot, Vec& z) const noexcept;

  //! A trajectory from x0: out[0] = x0, out[i] = the state at time i * dt, i < steps.
  //! \param out      `steps` points, written in order
  //! \param method   exact flow (default), explicit Euler or RK4 with step dt
  //! \return `invalid_argument` for a non-finite x0, dt <= 0 or a non-finite state on the
  //!         way (the points before it are written), else `ok`.
  Status rollout(const Vec& x0, double dt, std::size_t steps, Vec* out,
                 DiffeoIntegrator method = DiffeoIntegrator::exact) const noexcept;

 private:
  struct Map {
    Vec c;                 // center
    Vec v;                 // displacement
    double rho = 0.0;      // inverse width
    double rho2 = 0.0;     // rho^2
    double skip_zz = 0.0;  // ||y - c||^2 beyond which the root weight is negligible
    double vv = 0.0;       // ||v||^2
    double vnorm = 0.0;    // ||v||
  };
  // Undo map m at y (z = y - c): returns the weight k, x = y - k v.
  static double solve_weight(const Map& m, const Vec& z) noexcept;
  // C(x): the maps applied in index order (no finiteness checks).
  Vec apply(const Vec& x) const noexcept;
  // C(x) and J_C(x).
  Vec apply_jacobian(const Vec& x, Mat& jac) const noexcept;
  // C^{-1}(y): the maps undone in reverse index order.
  Vec undo(const Vec& y) const noexcept;
  // to_demo velocity: z = C^{-1}(x), J_C(z) accumulated on the way.
  Vec velocity_undo(const Vec& x, Vec& z) const noexcept;
  // to_line velocity: z = C(x), x_dot = speed J_C(x)^{-1} (target - z); false if singular.
  bool velocity_apply(const Vec& x, Vec& xdot, Vec& z) const noexcept;

  std::vector<Map> maps_;
  Vec target_ = Vec::Zero();
  double speed_ = 1.0;
  double negligible_ = kDiffeoNegligible;
  DiffeoDirection direction_ = DiffeoDirection::to_demo;
};

extern template class DiffeoDS<2>;
extern template class DiffeoDS<3>;

//! Per-query timing of DiffeoDS::velocity measured in C++ (std::chrono::steady_clock).
struct DiffeoTiming {
  double median_ns = 0.0;  //!< median time of one query
  double p999_ns = 0.0;    //!< 99.9th percentile
  double mean_ns = 0.0;    //!< mean
  double max_ns = 0.0;     //!< slowest query
  std::size_t n = 0;       //!< number of timed queries
};

//! Time `repeats` passes over `n_points` query points (row-major, D per point), each query
//! timed on its own (two steady_clock reads around it) after one untimed warm-up pass.
//! Not real-time (it allocates its n_points * repeats times).
//! \return `size_mismatch` / `invalid_argument` for bad sizes or a failing query.
template <int D>
Result time_velocity(const DiffeoDS<D>& ds, const double* points, std::size_t n_points, int repeats,
                     DiffeoTiming& out);

}  // namespace a2l

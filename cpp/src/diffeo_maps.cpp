// diffeo_maps.cpp:
// A diffeomorphic DS's description: validation (validate_diffeo_maps), building
// the evaluator from it (DiffeoDS::create) and back (DiffeoDS::maps). Evaluation is in
// diffeo.cpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "a2l/diffeo.hpp"

namespace a2l {
namespace {

std::string num(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

Result bad(Status s, const std::string& msg) {
  return Result::failure(s, "diffeomorphic DS: " + msg);
}

// ||v|| without overflow for large finite entries.
double stable_norm(const double* v, int d) {
  double scale = 0.0;
  for (int j = 0; j < d; ++j) scale = std::max(scale, std::abs(v[j]));
  if (scale == 0.0 || !std::isfinite(scale)) return scale;
  double s = 0.0;
  for (int j = 0; j < d; ++j) s += (v[j] / scale) * (v[j] / scale);
  return scale * std::sqrt(s);
}

bool all_finite(const double* p, std::size_t n) {
  for (std::size_t j = 0; j < n; ++j) {
    if (!std::isfinite(p[j])) return false;
  }
  return true;
}

}  // namespace

const char* diffeo_direction_name(DiffeoDirection d) noexcept {
  return d == DiffeoDirection::to_line ? "to_line" : "to_demo";
}

Result validate_diffeo_maps(const DiffeoMaps& m) {
  if (m.dim != 2 && m.dim != 3) {
    return bad(Status::size_mismatch, "dim must be 2 or 3, got " + std::to_string(m.dim));
  }
  const std::size_t d = static_cast<std::size_t>(m.dim);
  const std::size_t k = m.rhos.size();
  if (m.target.size() != d) {
    return bad(Status::size_mismatch, "target has " + std::to_string(m.target.size()) +
                                          " values, expected dim = " + std::to_string(d));
  }
  if (k > static_cast<std::size_t>(kDiffeoMaxMaps)) {
    return bad(Status::size_mismatch, std::to_string(k) + " maps, at most " +
                                          std::to_string(kDiffeoMaxMaps) + " are supported");
  }
  if (m.centers.size() != k * d) {
    return bad(Status::size_mismatch, "centers has " + std::to_string(m.centers.size()) +
                                          " values, expected " + std::to_string(k) + " maps x " +
                                          std::to_string(d) + " (as rhos)");
  }
  if (m.vectors.size() != k * d) {
    return bad(Status::size_mismatch, "vectors has " + std::to_string(m.vectors.size()) +
                                          " values, expected " + std::to_string(k) + " maps x " +
                                          std::to_string(d) + " (as rhos)");
  }
  if (m.direction != DiffeoDirection::to_demo && m.direction != DiffeoDirection::to_line) {
    return bad(Status::invalid_argument,
               "direction = " + std::to_string(static_cast<int>(m.direction)) +
                   " must be to_demo (0) or to_line (1)");
  }
  if (!all_finite(m.target.data(), d)) return bad(Status::invalid_argument, "target: not finite");
  if (!std::isfinite(m.speed) || !(m.speed > 0.0)) {
    return bad(Status::invalid_argument, "speed = " + num(m.speed) + " must be finite and > 0");
  }
  for (std::size_t i = 0; i < k; ++i) {
    const std::string map = "map " + std::to_string(i) + ": ";
    const double* c = m.centers.data() + i * d;
    const double* v = m.vectors.data() + i * d;
    const double rho = m.rhos[i];
    if (!all_finite(c, d)) return bad(Status::invalid_argument, map + "center is not finite");
    if (!all_finite(v, d)) return bad(Status::invalid_argument, map + "vector is not finite");
    if (!std::isfinite(rho)) return bad(Status::invalid_argument, map + "rho is not finite");
    if (rho < 0.0) return bad(Status::invalid_argument, map + "rho = " + num(rho) + " < 0");
    const double product = rho * stable_norm(v, m.dim);
    if (!(product < kDiffeoInvertibilityBound)) {
      return bad(Status::invalid_argument, map + "rho * ||v|| = " + num(product) +
                                               " >= sqrt(e/2) = " + num(kDiffeoInvertibilityBound) +
                                               " (the map is not invertible)");
    }
  }
  return Result::success();
}

template <int D>
Result DiffeoDS<D>::create(const DiffeoMaps& maps, DiffeoDS& out, double negligible) {
  if (!(negligible >= kDiffeoNegligible && negligible <= kDiffeoUnderflow)) {
    return bad(Status::invalid_argument, "negligible = " + num(negligible) + " must be in [" +
                                             num(kDiffeoNegligible) + ", " + num(kDiffeoUnderflow) +
                                             "]");
  }
  if (maps.dim != D) {
    return bad(Status::size_mismatch, "dim is " + std::to_string(maps.dim) + ", this DS has " +
                                          std::to_string(D) + " dimensions");
  }
  Result r = validate_diffeo_maps(maps);
  if (!r.ok()) return r;
  DiffeoDS ds;
  ds.maps_.resize(maps.rhos.size());
  for (std::size_t i = 0; i < ds.maps_.size(); ++i) {
    Map& m = ds.maps_[i];
    m.c = Eigen::Map<const Vec>(maps.centers.data() + i * D);
    m.v = Eigen::Map<const Vec>(maps.vectors.data() + i * D);
    m.rho = maps.rhos[i];
    m.rho2 = maps.rhos[i] * maps.rhos[i];
    m.vv = m.v.squaredNorm();
    m.vnorm = std::sqrt(m.vv);
    // With eps = exp(-negligible) and ||z|| >= sqrt(negligible) / rho + eps ||v||:
    // g(eps) = eps - exp(-rho^2 ||z - eps v||^2) >= eps - exp(-rho^2 (||z|| - eps ||v||)^2) >= 0,
    // and g is increasing, so the root weight is <= eps: the map is negligible there.
    const double reach = m.rho2 > 0.0
                             ? std::sqrt(negligible / m.rho2) + std::exp(-negligible) * m.vnorm
                             : std::numeric_limits<double>::infinity();
    m.skip_zz = reach * reach;
  }
  ds.target_ = Eigen::Map<const Vec>(maps.target.data());
  ds.speed_ = maps.speed;
  ds.negligible_ = negligible;
  ds.direction_ = maps.direction;
  out = std::move(ds);
  return Result::success();
}

template <int D>
DiffeoMaps DiffeoDS<D>::maps() const {
  DiffeoMaps m;
  m.dim = D;
  m.target.assign(target_.data(), target_.data() + D);
  m.speed = speed_;
  m.direction = direction_;
  for (const Map& p : maps_) {
    m.centers.insert(m.centers.end(), p.c.data(), p.c.data() + D);
    m.vectors.insert(m.vectors.end(), p.v.data(), p.v.data() + D);
    m.rhos.push_back(p.rho);
  }
  return m;
}

template Result DiffeoDS<2>::create(const DiffeoMaps&, DiffeoDS<2>&, double);
template Result DiffeoDS<3>::create(const DiffeoMaps&, DiffeoDS<3>&, double);
template DiffeoMaps DiffeoDS<2>::maps() const;
template DiffeoMaps DiffeoDS<3>::maps() const;

}  // namespace a2l

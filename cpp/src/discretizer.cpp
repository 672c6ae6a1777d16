#include "a2l/discretizer.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace a2l {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;
}  // namespace

Result check_edges(const Variable& v, const std::string& where) {
  if (v.edges.empty()) return Result::success();
  if (v.kind != VariableKind::distance) {
    return Result::failure(Status::invalid_argument,
                           where + ".edges: only a distance variable may have edges, this is " +
                               "of kind '" + variable_kind_name(v.kind) + "'");
  }
  const std::size_t n = v.edges.size();
  if (n > static_cast<std::size_t>(kMaxBins - 1)) {
    return Result::failure(Status::invalid_argument, where + ".edges: at most " +
                                                         std::to_string(kMaxBins - 1) +
                                                         " edges, got " + std::to_string(n));
  }
  for (std::size_t k = 0; k < n; ++k) {
    const double x = v.edges[k];
    if (!std::isfinite(x) || !(x > 0.0) || (k > 0 && !(x > v.edges[k - 1]))) {
      std::ostringstream ss;
      ss << where << ".edges[" << k << "]: " << x
         << " (edges must be finite, > 0 and strictly increasing)";
      return Result::failure(Status::invalid_argument, ss.str());
    }
  }
  if (static_cast<std::size_t>(v.n_bins) != n + 1) {
    return Result::failure(Status::invalid_argument,
                           where + ".n_bins: " + std::to_string(v.n_bins) + ", but " +
                               std::to_string(n) + " edges make " + std::to_string(n + 1) +
                               " bins");
  }
  return Result::success();
}

double first_bin_edge(const Variable& v) noexcept {
  if (!v.edges.empty()) return v.edges.front();
  return v.low + (v.high - v.low) / v.n_bins;
}

double range_upper_end(const Variable& v) noexcept {
  if (!v.edges.empty()) return v.edges.back();
  return v.high;
}

double bin_centre(const Variable& v, int b) noexcept {
  const std::size_t n = v.edges.size();
  if (n == 0) {
    const double w = (v.high - v.low) / v.n_bins;
    return v.low + (b + 0.5) * w;
  }
  const auto k = static_cast<std::size_t>(std::clamp(b, 0, static_cast<int>(n)));
  const double lo = k == 0 ? 0.0 : v.edges[k - 1];
  if (k < n) return 0.5 * (lo + v.edges[k]);
  const double before = n == 1 ? 0.0 : v.edges[n - 2];  // the last bin: as wide as the one before
  return lo + 0.5 * (lo - before);
}

const char* variable_kind_name(VariableKind kind) noexcept {
  switch (kind) {
    case VariableKind::effect:
      return "effect";
    case VariableKind::distance:
      return "distance";
    case VariableKind::orientation:
      return "orientation";
    case VariableKind::inclination:
      return "inclination";
    case VariableKind::high_level:
      return "high_level";
    case VariableKind::offset_x:
      return "offset_x";
    case VariableKind::offset_y:
      return "offset_y";
  }
  return "unknown_kind";
}

bool parse_variable_kind(const std::string& name, VariableKind& kind) noexcept {
  for (int i = 0; i <= static_cast<int>(VariableKind::offset_y); ++i) {
    const auto k = static_cast<VariableKind>(i);
    if (name == variable_kind_name(k)) {
      kind = k;
      return true;
    }
  }
  return false;
}

Result Discretizer::create(std::vector<Variable> variables, Discretizer& out) {
  if (variables.size() > static_cast<size_t>(kMaxVariables)) {
    return Result::failure(Status::invalid_argument,
                           "variables: " + std::to_string(variables.size()) +
                               " variables, at most " + std::to_string(kMaxVariables) +
                               " are supported");
  }
  std::set<std::string> names;
  int count[7] = {0, 0, 0, 0, 0, 0, 0};
  int effect_axis = -1;
  for (size_t i = 0; i < variables.size(); ++i) {
    Variable& v = variables[i];
    const std::string where = "variables[" + std::to_string(i) + "] ('" + v.name + "')";
    if (v.name.empty()) return Result::failure(Status::invalid_argument, where + ": empty name");
    if (!names.insert(v.name).second) {
      return Result::failure(Status::invalid_argument, where + ": duplicate name");
    }
    const int k = static_cast<int>(v.kind);
    if (k < 0 || k > static_cast<int>(VariableKind::offset_y)) {
      return Result::failure(Status::invalid_argument, where + ": unknown kind");
    }
    if (v.kind == VariableKind::effect || v.kind == VariableKind::high_level) {
      if (v.values.empty() || v.values.size() > static_cast<size_t>(kMaxBins)) {
        return Result::failure(Status::invalid_argument,
                               where + ".values: needs 1 to " + std::to_string(kMaxBins) +
                                   " values, got " + std::to_string(v.values.size()));
      }
      std::set<std::string> seen(v.values.begin(), v.values.end());
      if (seen.size() != v.values.size()) {
        return Result::failure(Status::invalid_argument, where + ".values: duplicate value");
      }
      v.n_bins = static_cast<int>(v.values.size());
    } else if (v.n_bins < 1 || v.n_bins > kMaxBins) {
      return Result::failure(Status::invalid_argument, where + ".n_bins: must be in [1, " +
                                                           std::to_string(kMaxBins) + "], got " +
                                                           std::to_string(v.n_bins));
    }
    if (has_range(v.kind)) {
      if (!std::isfinite(v.low) || !std::isfinite(v.high) || !(v.low < v.high)) {
        std::ostringstream ss;
        ss << where << ".low/high: need finite low < high, got low=" << v.low << " high=" << v.high;
        return Result::failure(Status::invalid_argument, ss.str());
      }
    }
    if (Result r = check_edges(v, where); !r.ok()) return r;
    if (v.kind != VariableKind::high_level && ++count[k] > 1) {
      return Result::failure(Status::invalid_argument, where + ": a second variable of kind '" +
                                                           variable_kind_name(v.kind) +
                                                           "' (at most one is supported)");
    }
    if (v.kind == VariableKind::effect) effect_axis = static_cast<int>(i);
  }
  out.variables_ = std::move(variables);
  out.effect_axis_ = effect_axis;
  return Result::success();
}

int Discretizer::find(const std::string& name) const noexcept {
  for (size_t i = 0; i < variables_.size(); ++i) {
    if (variables_[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int Discretizer::distance_bin(double d, double low, double high, int n) noexcept {
  if (!std::isfinite(d)) return -1;
  const double x = std::floor((d - low) / (high - low) * n);
  if (!(x >= 0.0)) return 0;
  if (x >= n - 1) return n - 1;
  return static_cast<int>(x);
}

int Discretizer::edges_bin(double d, const double* edges, int n_edges) noexcept {
  if (!std::isfinite(d)) return -1;
  return static_cast<int>(std::upper_bound(edges, edges + n_edges, d) - edges);
}

int Discretizer::orientation_bin(double theta, int n) noexcept {
  if (!std::isfinite(theta)) return -1;
  const double w = kTwoPi / n;
  double r = std::fmod(theta + kPi + 0.5 * w, kTwoPi);
  if (r < 0.0) r += kTwoPi;
  int b = static_cast<int>(std::floor(r / w));
  b %= n;
  if (b < 0) b += n;
  return b;
}

int Discretizer::inclination_bin(double phi, int n) noexcept {
  if (!std::isfinite(phi)) return -1;
  const double x = std::floor(phi / kPi * n);
  if (!(x >= 0.0)) return 0;
  if (x >= n - 1) return n - 1;
  return static_cast<int>(x);
}

int Discretizer::context_bin(const Variable& v, const Eigen::Vector3d& eef,
                             const Eigen::Vector3d& object) noexcept {
  const Eigen::Vector3d r = eef - object;  // eef relative to the object
  if (!r.allFinite()) return -1;
  // Sums written out (not Eigen's norm()): the order of the additions is part of the
  // definition, as a point on a bin edge must fall in the same bin on every path.
  const double planar2 = r.x() * r.x() + r.y() * r.y();
  switch (v.kind) {
    case VariableKind::distance: {
      const double d = std::sqrt(planar2 + r.z() * r.z());
      if (!v.edges.empty()) {
        return edges_bin(d, v.edges.data(), static_cast<int>(v.edges.size()));
      }
      return distance_bin(d, v.low, v.high, v.n_bins);
    }
    case VariableKind::orientation:
      return orientation_bin(std::atan2(r.y(), r.x()), v.n_bins);
    case VariableKind::inclination:
      return inclination_bin(std::atan2(std::sqrt(planar2), r.z()), v.n_bins);
    case VariableKind::offset_x:
      return distance_bin(r.x(), v.low, v.high, v.n_bins);
    case VariableKind::offset_y:
      return distance_bin(r.y(), v.low, v.high, v.n_bins);
    case VariableKind::effect:
    case VariableKind::high_level:
      break;
  }
  return -1;
}

Status Discretizer::discretize(const Context& c, int* bins) const noexcept {
  Status status = Status::ok;
  const int n = n_variables();
  for (int i = 0; i < n; ++i) {
    const Variable& v = variables_[static_cast<size_t>(i)];
    int b = -1;
    switch (v.kind) {
      case VariableKind::effect:
        b = (c.effect >= 0 && c.effect < v.n_bins) ? c.effect : -1;
        break;
      case VariableKind::high_level: {
        const int x = c.high_level[static_cast<size_t>(i)];
        b = (x >= 0 && x < v.n_bins) ? x : -1;
        break;
      }
      case VariableKind::distance:
      case VariableKind::orientation:
      case VariableKind::inclination:
      case VariableKind::offset_x:
      case VariableKind::offset_y:
        b = context_bin(v, c.eef, c.object);
        break;
    }
    bins[i] = b;
    if (b < 0) status = Status::unknown_context;
  }
  return status;
}

}  // namespace a2l

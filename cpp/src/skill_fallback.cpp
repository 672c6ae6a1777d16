#include "skill_fallback.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

namespace a2l {

namespace {

// The bins of table row `row` into `bins` (C order, strides of `table`).
void bins_of(const PolicyTable& table, std::size_t row, int* bins) noexcept {
  const auto& strides = table.strides();
  for (std::size_t i = 0; i < strides.size(); ++i) {
    bins[i] = static_cast<int>(row / strides[i]);
    row %= strides[i];
  }
}

}  // namespace

namespace detail {

// The nearest-cell fallback of every row (Skill::fallback_row): a row's own index where it
// is informative; else the nearest informative row with the same effect and high-level
// values, or -1.
Result compile_fallback(const Discretizer& disc, const PolicyTable& table,
                        std::vector<std::int32_t>& out) {
  const std::size_t rows = table.n_rows();
  const int na = table.n_axes();
  std::size_t uniform = 0;
  for (std::size_t r = 0; r < rows; ++r) uniform += table.argmax(r) < 0 ? 1 : 0;
  if (uniform != 0 && rows > kMaxFallbackWork / uniform) {
    return Result::failure(Status::invalid_argument,
                           "execution.fallback: 'nearest' on a table of " + std::to_string(rows) +
                               " rows with " + std::to_string(uniform) +
                               " uniform ones is too large to compile");
  }
  if (rows > static_cast<std::size_t>(INT32_MAX)) {
    return Result::failure(Status::invalid_argument,
                           "execution.fallback: too many rows for 'nearest'");
  }
  out.assign(rows, -1);
  std::vector<int> a(static_cast<std::size_t>(na)), b(static_cast<std::size_t>(na));
  for (std::size_t r = 0; r < rows; ++r) {
    if (table.argmax(r) >= 0) {
      out[r] = static_cast<std::int32_t>(r);
      continue;
    }
    bins_of(table, r, a.data());
    long best = -1;
    for (std::size_t q = 0; q < rows; ++q) {
      if (table.argmax(q) < 0) continue;
      bins_of(table, q, b.data());
      long d = 0;
      for (int i = 0; i < na && d >= 0; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const Variable& v = disc.variable(i);
        int diff = std::abs(a[k] - b[k]);
        if (!is_geometric(v.kind)) {
          if (diff != 0) d = -1;  // another effect or high-level value: not a neighbour
          continue;
        }
        if (v.kind == VariableKind::orientation) diff = std::min(diff, v.n_bins - diff);
        d += diff;
      }
      if (d >= 0 && (best < 0 || d < best)) {
        best = d;
        out[r] = static_cast<std::int32_t>(q);
      }
    }
  }
  return Result::success();
}

// The centre of every fallback row's cell (Skill::fallback_target) into `out` (2 per row),
// or `out` empty unless the discretizer's geometric variables are one distance and one
// orientation (a cell is then a sector of a ring around the object).
void compile_targets(const Discretizer& disc, const PolicyTable& table,
                     const std::vector<std::int32_t>& fallback, std::vector<double>& out) {
  out.clear();
  int id = -1, io = -1, others = 0;
  for (int i = 0; i < disc.n_variables(); ++i) {
    const VariableKind k = disc.variable(i).kind;
    if (k == VariableKind::distance && id < 0) {
      id = i;
    } else if (k == VariableKind::orientation && io < 0) {
      io = i;
    } else if (is_geometric(k)) {
      ++others;
    }
  }
  if (id < 0 || io < 0 || others > 0) return;
  const Variable& vd = disc.variable(id);
  const Variable& vo = disc.variable(io);
  const double wo = 2.0 * std::acos(-1.0) / vo.n_bins;
  const std::size_t rows = table.n_rows();
  out.assign(2 * rows, 0.0);
  std::vector<int> b(static_cast<std::size_t>(table.n_axes()));
  for (std::size_t r = 0; r < rows; ++r) {
    if (fallback[r] < 0) continue;
    bins_of(table, static_cast<std::size_t>(fallback[r]), b.data());
    const double d = bin_centre(vd, b[static_cast<std::size_t>(id)]);
    const double a = -std::acos(-1.0) + b[static_cast<std::size_t>(io)] * wo;  // bin centre
    out[2 * r] = d * std::cos(a);
    out[2 * r + 1] = d * std::sin(a);
  }
}

}  // namespace detail

const char* fallback_name(Fallback f) noexcept {
  switch (f) {
    case Fallback::nearest:
      return "nearest";
    case Fallback::approach:
      return "approach";
    case Fallback::none:
      break;
  }
  return "none";
}

bool parse_fallback(const std::string& name, Fallback& out) noexcept {
  if (name == "none") {
    out = Fallback::none;
    return true;
  }
  if (name == "nearest") {
    out = Fallback::nearest;
    return true;
  }
  if (name == "approach") {
    out = Fallback::approach;
    return true;
  }
  return false;
}

}  // namespace a2l

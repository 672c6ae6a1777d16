#include "a2l/policy_table.hpp"

#include <cmath>
#include <string>

namespace a2l {

Result PolicyTable::create(std::vector<int> shape, int n_moves, std::vector<double> posterior,
                           std::vector<std::int32_t> argmax, PolicyTable& out) {
  if (n_moves < 1) {
    return Result::failure(Status::invalid_argument, "policy table: needs at least one movement");
  }
  std::size_t rows = 1;
  for (size_t i = 0; i < shape.size(); ++i) {
    if (shape[i] < 1 || shape[i] > kMaxBins) {
      return Result::failure(
          Status::invalid_argument,
          "policy table: axis " + std::to_string(i) + " has " + std::to_string(shape[i]) + " bins");
    }
    rows *= static_cast<std::size_t>(shape[i]);
    if (rows > argmax.size()) break;  // cannot match; avoids overflow on absurd shapes
  }
  if (argmax.size() != rows) {
    return Result::failure(Status::size_mismatch,
                           "policy table: argmax has " + std::to_string(argmax.size()) +
                               " entries, the shape needs " + std::to_string(rows));
  }
  if (posterior.size() != rows * static_cast<std::size_t>(n_moves)) {
    return Result::failure(Status::size_mismatch,
                           "policy table: posterior has " + std::to_string(posterior.size()) +
                               " entries, the shape needs " +
                               std::to_string(rows * static_cast<std::size_t>(n_moves)));
  }
  for (std::size_t r = 0; r < rows; ++r) {
    if (argmax[r] < -1 || argmax[r] >= n_moves) {
      return Result::failure(Status::invalid_argument, "policy table: argmax[" + std::to_string(r) +
                                                           "] = " + std::to_string(argmax[r]) +
                                                           " is outside [-1, " +
                                                           std::to_string(n_moves) + ")");
    }
    double sum = 0.0;
    for (int m = 0; m < n_moves; ++m) {
      const double p = posterior[r * static_cast<std::size_t>(n_moves) + static_cast<size_t>(m)];
      if (!std::isfinite(p) || p < 0.0) {
        return Result::failure(Status::invalid_argument,
                               "policy table: posterior row " + std::to_string(r) +
                                   " has a negative or non-finite probability");
      }
      sum += p;
    }
    if (std::abs(sum - 1.0) > 1e-9) {
      return Result::failure(Status::invalid_argument, "policy table: posterior row " +
                                                           std::to_string(r) + " sums to " +
                                                           std::to_string(sum) + ", not 1");
    }
  }
  out.strides_.assign(shape.size(), 1);
  for (int i = static_cast<int>(shape.size()) - 2; i >= 0; --i) {
    out.strides_[static_cast<size_t>(i)] =
        out.strides_[static_cast<size_t>(i) + 1] *
        static_cast<std::size_t>(shape[static_cast<size_t>(i) + 1]);
  }
  out.shape_ = std::move(shape);
  out.n_moves_ = n_moves;
  out.posterior_ = std::move(posterior);
  out.argmax_ = std::move(argmax);
  return Result::success();
}

bool PolicyTable::in_range(const int* bins) const noexcept {
  for (size_t i = 0; i < shape_.size(); ++i) {
    if (bins[i] < 0 || bins[i] >= shape_[i]) return false;
  }
  return true;
}

}  // namespace a2l

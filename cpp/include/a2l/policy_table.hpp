//! \file policy_table.hpp
//! \brief The compiled policy table: P(move | evidence) and its argmax for every combination.
//!
//! The table is a dense C-order array over the evidence variables' bins (axis order of the
//! skill's variables) with the movements as the last axis of the posterior. Lookups are a
//! dot product of the bins with precomputed strides: no allocation, no branch on the data.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "a2l/discretizer.hpp"
#include "a2l/status.hpp"

namespace a2l {

//! Dense posterior and argmax tables over every evidence combination. Immutable once created.
class PolicyTable {
 public:
  //! An empty table.
  PolicyTable() = default;

  //! Build a table.
  //! \param shape     the number of bins of each evidence variable, in axis order
  //! \param n_moves   the number of movements (last axis of the posterior)
  //! \param posterior product(shape) * n_moves probabilities, C order
  //! \param argmax    product(shape) movement indices in [-1, n_moves), -1 = uniform row
  //! \return `size_mismatch` or `invalid_argument` naming the check, else `ok`.
  static Result create(std::vector<int> shape, int n_moves, std::vector<double> posterior,
                       std::vector<std::int32_t> argmax, PolicyTable& out);

  //! Number of evidence axes.
  int n_axes() const noexcept { return static_cast<int>(shape_.size()); }
  //! Bins of each evidence axis.
  const std::vector<int>& shape() const noexcept { return shape_; }
  //! Stride of each evidence axis in rows (C order).
  const std::vector<std::size_t>& strides() const noexcept { return strides_; }
  //! Number of movements.
  int n_moves() const noexcept { return n_moves_; }
  //! Number of rows (evidence combinations).
  std::size_t n_rows() const noexcept { return argmax_.size(); }

  //! Row of the evidence combination `bins[0 .. n_axes())`; every bin must be in range.
  std::size_t row_index(const int* bins) const noexcept {
    std::size_t r = 0;
    for (size_t i = 0; i < strides_.size(); ++i)
      r += strides_[i] * static_cast<std::size_t>(bins[i]);
    return r;
  }
  //! True if every bins[i] is in [0, shape[i]).
  bool in_range(const int* bins) const noexcept;
  //! The posterior row (n_moves() probabilities) of row `row`.
  const double* posterior_row(std::size_t row) const noexcept {
    return posterior_.data() + row * static_cast<std::size_t>(n_moves_);
  }
  //! The most probable movement of row `row`, or -1 where the row is uniform.
  int argmax(std::size_t row) const noexcept { return argmax_[row]; }
  //! The most probable movement of the combination `bins`, or -1 where the row is uniform or
  //! a bin is out of range.
  int lookup(const int* bins) const noexcept {
    return in_range(bins) ? argmax_[row_index(bins)] : -1;
  }

  //! The whole posterior, C order, product(shape) * n_moves values.
  const std::vector<double>& posterior() const noexcept { return posterior_; }
  //! The whole argmax table, C order, product(shape) values.
  const std::vector<std::int32_t>& argmax() const noexcept { return argmax_; }

 private:
  std::vector<int> shape_;
  std::vector<std::size_t> strides_;
  int n_moves_ = 0;
  std::vector<double> posterior_;
  std::vector<std::int32_t> argmax_;
};

}  // namespace a2l

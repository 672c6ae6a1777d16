//! \file movement_repertoire.hpp
//! \brief The discrete movements a skill chooses from (the last axis of its policy table).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "a2l/status.hpp"

namespace a2l {

//! Most movements a repertoire may hold.
constexpr int kMaxMoves = 1024;

//! Movement i displaces the end-effector by step * d_i / ||d_i||, d_i a 3-vector of signs.
//! Immutable once created.
class MovementRepertoire {
 public:
  //! An empty repertoire.
  MovementRepertoire() = default;

  //! Build a repertoire.
  //! \param step       movement length (m), finite and > 0
  //! \param directions sign vectors, entries in {-1, 0, 1}, not all zero
  //! \param labels     one name per movement (empty: "m0", "m1", ...)
  //! \return `invalid_argument` or `size_mismatch` naming the movement, else `ok`.
  static Result create(double step, std::vector<Eigen::Vector3i> directions,
                       std::vector<std::string> labels, MovementRepertoire& out);

  //! Number of movements.
  int size() const noexcept { return static_cast<int>(directions_.size()); }
  //! Movement length (m).
  double step() const noexcept { return step_; }
  //! Sign vector of movement i.
  const Eigen::Vector3i& direction(int i) const noexcept {
    return directions_[static_cast<size_t>(i)];
  }
  //! Displacement of movement i: step * d / ||d|| (m).
  const Eigen::Vector3d& displacement(int i) const noexcept {
    return displacements_[static_cast<size_t>(i)];
  }
  //! Name of movement i.
  const std::string& label(int i) const noexcept { return labels_[static_cast<size_t>(i)]; }
  //! All sign vectors.
  const std::vector<Eigen::Vector3i>& directions() const noexcept { return directions_; }
  //! All labels.
  const std::vector<std::string>& labels() const noexcept { return labels_; }

 private:
  double step_ = 0.0;
  std::vector<Eigen::Vector3i> directions_;
  std::vector<Eigen::Vector3d> displacements_;
  std::vector<std::string> labels_;
};

}  // namespace a2l

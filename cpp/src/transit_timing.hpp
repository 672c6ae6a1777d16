//! \file transit_timing.hpp
//! \brief Private to the core: the joint limits a transit's trajectory is timed within
//! (transit_timing.cpp, beside time_parameterize), for TransitPlanner::plan (transit.cpp).
#pragma once

#include <Eigen/Core>

#include "a2l/kinematics.hpp"
#include "a2l/transit.hpp"

namespace a2l::detail {

//! The trajectory's joint limits into `vel` and `acc` (n each): velocity (the URDF's, else
//! default_velocity, times velocity_scale) and acceleration.
void trajectory_limits(const Kinematics& kin, const TransitOptions& o, Eigen::VectorXd& vel,
                       Eigen::VectorXd& acc);

}  // namespace a2l::detail

// a2l-run's scene (internal): the object by task and the C++ scene the skill runs against.
#pragma once

#include <Eigen/Core>
#include <memory>

#include "a2l/scene/virtual.hpp"
#include "options.hpp"
#include "task.hpp"

namespace a2l_run {

//! Half extents of the object (m): the push box, the grasp scene's block or the press scene's
//! button (a2l.sim's defaults).
Eigen::Vector3d object_half_size(Task task);

//! The scene of --scene: the virtual scene with the task's object semantics (`virt` then
//! points to it, else nullptr), or the Bullet scene. 0, or 2 after a message (a build
//! without Bullet).
int make_scene(const Args& args, Task task, const Eigen::Vector3d& half, double table_z,
               std::unique_ptr<a2l::Scene>& scene, a2l::VirtualScene*& virt);

}  // namespace a2l_run

// a2l-run's scene: virtual or Bullet, with the task's object.
#include "scene.hpp"

#include <iostream>

#include "a2l/scene/bullet.hpp"

namespace a2l_run {

Eigen::Vector3d object_half_size(Task task) {
  return task == Task::grasp   ? Eigen::Vector3d(0.015, 0.015, 0.03)
         : task == Task::press ? Eigen::Vector3d(0.03, 0.03, 0.01)
                               : Eigen::Vector3d(0.035, 0.0425, 0.04);
}

int make_scene(const Args& args, Task task, const Eigen::Vector3d& half, double table_z,
               std::unique_ptr<a2l::Scene>& scene, a2l::VirtualScene*& virt) {
  virt = nullptr;
  if (args.scene == "virtual") {
    a2l::VirtualSceneOptions vo;
    vo.half_size = half;
    vo.table_z = table_z;
    vo.object_kind = task == Task::grasp   ? a2l::ObjectKind::graspable
                     : task == Task::press ? a2l::ObjectKind::button
                                           : a2l::ObjectKind::box;
    auto v = std::make_unique<a2l::VirtualScene>(vo);
    virt = v.get();
    scene = std::move(v);
    return 0;
  }
#if A2L_HAVE_BULLET
  a2l::BulletSceneOptions bo;
  bo.half_size = half;
  bo.table_z = table_z;
  scene = std::make_unique<a2l::BulletScene>(bo);
  return 0;
#else
  std::cerr << "a2l-run: --scene bullet: this build has no Bullet (libbullet-dev)\n";
  return 2;
#endif
}

}  // namespace a2l_run

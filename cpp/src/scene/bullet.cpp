#include "a2l/scene/bullet.hpp"

#if A2L_HAVE_BULLET
#include <btBulletDynamicsCommon.h>

#include <cmath>
#endif

namespace a2l {

#if !A2L_HAVE_BULLET
bool bullet_scene_available() noexcept { return false; }
#else
bool bullet_scene_available() noexcept { return true; }

struct BulletScene::Impl {
  BulletSceneOptions options;
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  btBoxShape table_shape{btVector3(2.0, 2.0, 0.05)};
  btBoxShape box_shape{btVector3(0.035, 0.0425, 0.04)};
  btSphereShape eef_shape{0.01};
  btDefaultMotionState table_motion, box_motion, eef_motion;
  std::unique_ptr<btRigidBody> table, box, eef;
  long long steps = 0;

  explicit Impl(const BulletSceneOptions& o)
      : options(o),
        box_shape(btVector3(o.half_size.x(), o.half_size.y(), o.half_size.z())),
        eef_shape(o.eef_radius) {
    world.setGravity(btVector3(0, 0, -9.81));
    table_motion.setWorldTransform(
        btTransform(btQuaternion::getIdentity(), btVector3(0, 0, o.table_z - 0.05)));
    table.reset(new btRigidBody(
        btRigidBody::btRigidBodyConstructionInfo(0.0, &table_motion, &table_shape)));
    table->setFriction(o.friction);
    world.addRigidBody(table.get());

    btVector3 inertia(0, 0, 0);
    box_shape.calculateLocalInertia(o.box_mass, inertia);
    btRigidBody::btRigidBodyConstructionInfo bi(o.box_mass, &box_motion, &box_shape, inertia);
    bi.m_friction = o.friction;
    box.reset(new btRigidBody(bi));
    box->setActivationState(DISABLE_DEACTIVATION);
    world.addRigidBody(box.get());

    eef.reset(
        new btRigidBody(btRigidBody::btRigidBodyConstructionInfo(0.0, &eef_motion, &eef_shape)));
    eef->setCollisionFlags(eef->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
    eef->setActivationState(DISABLE_DEACTIVATION);
    eef->setFriction(o.friction);
    world.addRigidBody(eef.get());
  }
  ~Impl() {
    world.removeRigidBody(eef.get());
    world.removeRigidBody(box.get());
    world.removeRigidBody(table.get());
  }

  void place_box(const Eigen::Vector3d& c) {
    const btTransform t(btQuaternion::getIdentity(), btVector3(c.x(), c.y(), c.z()));
    box_motion.setWorldTransform(t);
    box->setWorldTransform(t);
    box->setCenterOfMassTransform(t);
    box->setLinearVelocity(btVector3(0, 0, 0));
    box->setAngularVelocity(btVector3(0, 0, 0));
    box->clearForces();
  }
  void place_eef(const Eigen::Vector3d& p) {
    const btTransform t(btQuaternion::getIdentity(), btVector3(p.x(), p.y(), p.z()));
    eef_motion.setWorldTransform(t);
    eef->setWorldTransform(t);
  }
  Eigen::Vector3d eef_pos() const {
    const btVector3& v = eef->getWorldTransform().getOrigin();
    return {v.x(), v.y(), v.z()};
  }
  Eigen::Vector3d box_pos() const {
    const btVector3& v = box->getWorldTransform().getOrigin();
    return {v.x(), v.y(), v.z()};
  }
  void step() {
    world.stepSimulation(static_cast<btScalar>(options.time_step), 0);
    ++steps;
  }
};

BulletScene::BulletScene(const BulletSceneOptions& options)
    : impl_(std::make_unique<Impl>(options)) {
  reset(Eigen::Vector3d(0.0, 0.0, options.table_z + 0.2),
        Eigen::Vector3d(0.0, 0.0, options.table_z + options.half_size.z()));
}

BulletScene::~BulletScene() = default;

void BulletScene::reset(const Eigen::Vector3d& eef, const Eigen::Vector3d& object) {
  impl_->place_box(object);
  impl_->place_eef(eef);
  impl_->world.getBroadphase()->resetPool(&impl_->dispatcher);
  impl_->solver.reset();
}

bool BulletScene::move(const Eigen::Vector3d& d) {
  Impl& s = *impl_;
  const Eigen::Vector3d start = s.eef_pos();
  const Eigen::Vector3d box_before = s.box_pos();
  if (!d.allFinite()) return false;
  const double per_step = std::max(s.options.eef_speed * s.options.time_step, 1e-6);
  // At most 1e5 physics steps per move (a move of more than 25 km at the default speed).
  const double substeps = std::ceil(d.norm() / per_step);
  const int n = substeps > 1e5 ? 100000 : std::max(1, static_cast<int>(substeps));
  for (int i = 1; i <= n; ++i) {
    s.place_eef(start + d * (static_cast<double>(i) / n));
    s.step();
  }
  for (int i = 0; i < s.options.settle_steps; ++i) {
    s.step();
    if (s.box->getLinearVelocity().length() < 1e-3 && s.box->getAngularVelocity().length() < 1e-2) {
      break;
    }
  }
  return (s.box_pos() - box_before).head<2>().norm() > s.options.moved_threshold;
}

Eigen::Vector3d BulletScene::eef_position() const { return impl_->eef_pos(); }
Eigen::Vector3d BulletScene::object_position() const { return impl_->box_pos(); }
long long BulletScene::physics_steps() const noexcept { return impl_->steps; }
const BulletSceneOptions& BulletScene::options() const noexcept { return impl_->options; }
#endif

}  // namespace a2l

//! \file collision_world.hpp
//! \brief Private to the core: the Bullet world of a CollisionModel (its flattened link tree,
//! collision objects, pair rules and contact detection) and building it from a URDF
//! (collision_build.cpp). Only built with Bullet (A2L_HAVE_BULLET).
#pragma once

#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <btBulletCollisionCommon.h>

#include <Eigen/Core>
#include <functional>
#include <kdl/segment.hpp>
#include <memory>
#include <string>
#include <vector>

#include "a2l/collision_model.hpp"
#include "a2l/kinematics.hpp"
#include "collision_shapes.hpp"

namespace a2l {
namespace detail {

// One node of the flattened kinematic tree.
struct LinkNode {
  std::string name;
  int parent = -1;       // index in the node list, -1 for the root
  KDL::Segment segment;  // joint + tip frame relative to the parent link
  int arm_index = -1;    // index of the segment's joint in the arm's q, or -1
  std::string joint;     // the segment's joint name (movable joints only)
  bool moving = false;   // pose depends on the arm's joints
  int last_arm = -1;     // the last arm joint between the root and this link (-1: none)
  btTransform offset = btTransform::getIdentity();  // shape frame in the link frame
  int object = -1;                                  // index in objects (links with geometry), or -1
};

// A pair-rule filter: Bullet asks it before creating a broadphase pair.
struct PairFilter : public btOverlapFilterCallback {
  const std::vector<std::vector<char> >* check = nullptr;
  bool needBroadphaseCollision(btBroadphaseProxy* a, btBroadphaseProxy* b) const override {
    const auto* oa = static_cast<const btCollisionObject*>(a->m_clientObject);
    const auto* ob = static_cast<const btCollisionObject*>(b->m_clientObject);
    const size_t a_index = static_cast<size_t>(oa->getUserIndex());
    const size_t b_index = static_cast<size_t>(ob->getUserIndex());
    // objects added since the last rule update are tested until the rules are rebuilt
    if (!check || a_index >= check->size() || b_index >= check->size()) return true;
    return (*check)[a_index][b_index] != 0;
  }
};

}  // namespace detail

struct CollisionModel::Impl {
  Kinematics kin;
  std::vector<detail::LinkNode> nodes;  // parents before children
  int base_node = -1;
  std::vector<double> fixed_q;  // per node: position of a movable non-arm joint
  // Bullet
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btCollisionWorld world{&dispatcher, &broadphase, &config};
  detail::PairFilter filter;
  std::vector<std::unique_ptr<btCollisionShape> > shapes;    // owns every shape
  std::vector<std::unique_ptr<btCollisionObject> > objects;  // links first, then obstacles
  std::vector<std::string> object_names;
  std::vector<char> object_moving;
  int n_link_objects = 0;
  std::vector<std::vector<char> > allowed;  // link x link
  std::vector<std::vector<char> > check;    // object x object: the pair is tested
  std::vector<std::pair<int, int> > pairs;  // the tested pairs (i < j), for pairwise checks
  size_t last_hit = 0;                      // index in pairs of the last colliding pair
  bool pairwise = true;                     // detect(): pair by pair, not Bullet's world pass
  long long checks = 0;
  std::vector<KDL::Frame> frames;           // per node: its pose at the last check
  std::vector<int> moving_nodes;            // indices of the moving nodes, parents first
  std::vector<btVector3> aabb_lo, aabb_hi;  // per object: bounding boxes in detect_pairwise()
  bool static_moved = true;  // a static object moved (or came) since its box was computed

  Impl() {
    world.getPairCache()->setOverlapFilterCallback(&filter);
    world.setForceUpdateAllAabbs(false);
  }
  ~Impl() {
    for (auto& o : objects) world.removeCollisionObject(o.get());
  }

  void rebuild_check() {
    const size_t n = objects.size();
    check.assign(n, std::vector<char>(n, 0));
    for (size_t i = 0; i < n; ++i)
      for (size_t j = 0; j < n; ++j) {
        if (i == j || (!object_moving[i] && !object_moving[j])) continue;
        const bool links =
            static_cast<int>(i) < n_link_objects && static_cast<int>(j) < n_link_objects;
        check[i][j] = links ? !allowed[i][j] : 1;
      }
    filter.check = &check;
    static_moved = true;  // objects may have come or gone
    pairs.clear();
    // pairs with an obstacle first: near the table they collide most often
    for (int pass = 0; pass < 2; ++pass)
      for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 1; j < n; ++j) {
          const bool obstacle = static_cast<int>(j) >= n_link_objects;
          if (check[i][j] && obstacle == (pass == 0))
            pairs.emplace_back(static_cast<int>(i), static_cast<int>(j));
        }
    last_hit = 0;
  }

  // Poses of every node in the base link's frame for arm configuration q (and the other joints
  // at fixed_q); also lists the moving nodes for forward_moving().
  void forward(const Eigen::Ref<const Eigen::VectorXd>& q) {
    frames.resize(nodes.size());
    moving_nodes.clear();
    for (size_t i = 0; i < nodes.size(); ++i) {
      const detail::LinkNode& n = nodes[i];
      const double qi = n.arm_index >= 0 ? q[n.arm_index] : fixed_q[i];
      const KDL::Frame local = n.segment.pose(qi);
      frames[i] = n.parent < 0 ? local : frames[n.parent] * local;
      if (n.moving) moving_nodes.push_back(static_cast<int>(i));
    }
    const KDL::Frame base_inv = frames[base_node].Inverse();
    for (auto& f : frames) f = base_inv * f;
  }

  // Poses of the moving nodes only (the others keep those of the last forward(), which the
  // other joints' positions do not change in between): a moving node's parent comes first
  // and is either moving (updated just before) or static.
  void forward_moving(const Eigen::Ref<const Eigen::VectorXd>& q) {
    for (const int i : moving_nodes) {
      const detail::LinkNode& n = nodes[i];
      const double qi = n.arm_index >= 0 ? q[n.arm_index] : fixed_q[i];
      frames[i] = frames[n.parent] * n.segment.pose(qi);
    }
  }

  void place(bool moving_only) {
    for (const detail::LinkNode& n : nodes) {
      if (n.object < 0 || (moving_only && !n.moving)) continue;
      btCollisionObject* o = objects[n.object].get();
      o->setWorldTransform(detail::to_bt(frames[&n - nodes.data()]) * n.offset);
      if (!n.moving) world.updateSingleAabb(o);  // static objects are not updated per check
    }
    if (!moving_only) static_moved = true;
  }

  // Calls `hit(a, b)` for every tested pair in contact at q; stops if it returns true.
  void detect(const Eigen::Ref<const Eigen::VectorXd>& q,
              const std::function<bool(int, int)>& hit) {
    ++checks;
    forward_moving(q);
    place(true);
    if (pairwise)
      detect_pairwise(hit);
    else
      detect_world(hit);
  }

  // Penetration (distance < 0) reported by Bullet's narrow phase for one pair.
  struct PenetrationCallback : public btCollisionWorld::ContactResultCallback {
    bool hit = false;
    btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper*, int, int,
                             const btCollisionObjectWrapper*, int, int) override {
      if (cp.getDistance() < 0.0) hit = true;
      return 0;
    }
  };

  // The tested pairs one by one: their exact bounding boxes first (no contact threshold), the
  // narrow phase (the same convex algorithms as the world pass) only where they overlap, the
  // pair that collided last time first. Stateless: no contact cache between calls.
  void detect_pairwise(const std::function<bool(int, int)>& hit) {
    const size_t n = objects.size();
    const bool all = aabb_lo.size() != n || static_moved;  // static boxes: once per change
    aabb_lo.resize(n);
    aabb_hi.resize(n);
    for (size_t i = 0; i < n; ++i)
      if (all || object_moving[i])
        objects[i]->getCollisionShape()->getAabb(objects[i]->getWorldTransform(), aabb_lo[i],
                                                 aabb_hi[i]);
    static_moved = false;
    const size_t m = pairs.size(), first = last_hit;
    for (size_t k = 0; k < m; ++k) {
      const size_t idx = (first + k) % m;
      const int a = pairs[idx].first, b = pairs[idx].second;
      if (!TestAabbAgainstAabb2(aabb_lo[a], aabb_hi[a], aabb_lo[b], aabb_hi[b])) continue;
      PenetrationCallback cb;
      world.contactPairTest(objects[a].get(), objects[b].get(), cb);
      if (!cb.hit) continue;
      last_hit = idx;
      if (hit(a, b)) return;
    }
  }

  // Bullet's world pass: its broad phase, persistent contact manifolds.
  void detect_world(const std::function<bool(int, int)>& hit) {
    world.performDiscreteCollisionDetection();
    const int m = dispatcher.getNumManifolds();
    for (int k = 0; k < m; ++k) {
      const btPersistentManifold* man = dispatcher.getManifoldByIndexInternal(k);
      const int a = man->getBody0()->getUserIndex();
      const int b = man->getBody1()->getUserIndex();
      if (!check[a][b]) continue;  // a pair allowed after Bullet created it (a rule change)
      for (int c = 0; c < man->getNumContacts(); ++c) {
        if (man->getContactPoint(c).getDistance() < 0.0) {
          if (hit(a, b)) return;
          break;
        }
      }
    }
  }

  void add_object(std::unique_ptr<btCollisionShape> shape, const std::string& name, bool moving,
                  const btTransform& pose = btTransform::getIdentity()) {
    auto obj = std::make_unique<btCollisionObject>();
    obj->setCollisionShape(shape.get());
    obj->setWorldTransform(pose);
    // only moving objects get their bounding boxes updated at every check
    obj->forceActivationState(moving ? DISABLE_DEACTIVATION : ISLAND_SLEEPING);
    obj->setUserIndex(static_cast<int>(objects.size()));
    shapes.push_back(std::move(shape));
    object_names.push_back(name);
    object_moving.push_back(moving ? 1 : 0);
    world.addCollisionObject(obj.get());
    objects.push_back(std::move(obj));
  }
};

namespace detail {

//! Fill `m` from the URDF text `xml` (`source` names it in messages): the kinematic chain
//! base_link -> tip_link, the link tree flattened parents first, one collision object per link
//! with geometry, and the pairs never tested (adjacent links, links rigid to each other).
Result build_collision_model(const std::string& xml, const std::string& source,
                             const std::string& base_link, const std::string& tip_link,
                             const MeshVertices& meshes, CollisionModel::Impl& m);

}  // namespace detail
}  // namespace a2l

#include "a2l/collision_model.hpp"

#if A2L_HAVE_BULLET
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <btBulletCollisionCommon.h>
#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include "a2l/urdf_to_kdl.hpp"
#include "collision_shapes.hpp"
#endif

namespace a2l {

#if !A2L_HAVE_BULLET
bool collision_model_available() noexcept { return false; }
#else
bool collision_model_available() noexcept { return true; }

using detail::kShapeMargin;
using detail::make_shape;
using detail::to_bt;

namespace {

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

}  // namespace

struct CollisionModel::Impl {
  Kinematics kin;
  std::vector<LinkNode> nodes;  // parents before children
  int base_node = -1;
  std::vector<double> fixed_q;  // per node: position of a movable non-arm joint
  // Bullet
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btCollisionWorld world{&dispatcher, &broadphase, &config};
  PairFilter filter;
  std::vector<std::unique_ptr<btCollisionShape> > shapes;    // owns every shape
  std::vector<std::unique_ptr<btCollisionObject> > objects;  // links first, then obstacles
  std::vector<std::string> object_names;
  std::vector<char> object_moving;
  int n_link_objects = 0;
  std::vector<std::vector<char> > allowed;  // link x link
  std::vector<std::vector<char> > check;    // object x object: the pair is tested
  long long checks = 0;
  std::vector<KDL::Frame> frames;  // per node, scratch

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
  }

  // Poses of every node in the base link's frame for arm configuration q.
  void forward(const Eigen::Ref<const Eigen::VectorXd>& q) {
    frames.resize(nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i) {
      const LinkNode& n = nodes[i];
      const double qi = n.arm_index >= 0 ? q[n.arm_index] : fixed_q[i];
      const KDL::Frame local = n.segment.pose(qi);
      frames[i] = n.parent < 0 ? local : frames[n.parent] * local;
    }
    const KDL::Frame base_inv = frames[base_node].Inverse();
    for (auto& f : frames) f = base_inv * f;
  }

  void place(bool moving_only) {
    for (const LinkNode& n : nodes) {
      if (n.object < 0 || (moving_only && !n.moving)) continue;
      btCollisionObject* o = objects[n.object].get();
      o->setWorldTransform(to_bt(frames[&n - nodes.data()]) * n.offset);
      if (!n.moving) world.updateSingleAabb(o);  // static objects are not updated per check
    }
  }

  // Runs Bullet; calls `hit(a, b)` for every tested pair in contact; stops if it returns true.
  void detect(const Eigen::Ref<const Eigen::VectorXd>& q,
              const std::function<bool(int, int)>& hit) {
    ++checks;
    forward(q);
    place(true);
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

namespace {

Result read_file(const std::string& path, std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Result::failure(Status::file_error, "cannot read URDF '" + path + "'");
  std::ostringstream ss;
  ss << in.rdbuf();
  text = ss.str();
  return Result::success();
}

Result build(const std::string& xml, const std::string& source, const std::string& base_link,
             const std::string& tip_link, const MeshVertices& meshes, CollisionModel::Impl& m) {
  Result r = Kinematics::load_from_string(xml, base_link, tip_link, m.kin);
  if (!r.ok()) return Result::failure(r.status, source + ": " + r.message);
  KDL::Tree tree;
  r = urdf_string_to_kdl_tree(xml, tree, source);
  if (!r.ok()) return r;
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(xml);
  if (!model) return Result::failure(Status::parse_error, source + ": cannot parse the URDF");
  const auto& names = m.kin.joint_names();
  // flatten the tree, parents first
  std::function<void(KDL::SegmentMap::const_iterator, int)> visit =
      [&](KDL::SegmentMap::const_iterator it, int parent) {
        LinkNode n;
        n.name = it->first;
        n.parent = parent;
        n.segment = GetTreeElementSegment(it->second);
        const KDL::Joint& j = n.segment.getJoint();
        if (j.getType() != KDL::Joint::None) {
          n.joint = j.getName();
          const auto a = std::find(names.begin(), names.end(), n.joint);
          if (a != names.end()) n.arm_index = static_cast<int>(a - names.begin());
        }
        n.moving = n.arm_index >= 0 || (parent >= 0 && m.nodes[parent].moving);
        n.last_arm = n.arm_index >= 0 ? n.arm_index : (parent >= 0 ? m.nodes[parent].last_arm : -1);
        const int self = static_cast<int>(m.nodes.size());
        m.nodes.push_back(n);
        for (const auto& child : GetTreeElementChildren(it->second)) visit(child, self);
      };
  visit(tree.getRootSegment(), -1);
  m.fixed_q.assign(m.nodes.size(), 0.0);
  for (size_t i = 0; i < m.nodes.size(); ++i)
    if (m.nodes[i].name == base_link) m.base_node = static_cast<int>(i);
  // one compound shape per link with geometry
  for (LinkNode& n : m.nodes) {
    const urdf::LinkConstSharedPtr link = model->getLink(n.name);
    if (!link || link->collision_array.empty()) continue;
    std::vector<std::pair<btTransform, std::unique_ptr<btCollisionShape> > > parts;
    for (const auto& col : link->collision_array) {
      if (!col || !col->geometry) continue;
      std::string error;
      auto shape = make_shape(*col->geometry, meshes, n.name, error);
      if (!shape) return Result::failure(Status::invalid_argument, source + ": " + error);
      parts.emplace_back(to_bt(col->origin), std::move(shape));
    }
    if (parts.empty()) continue;
    n.object = static_cast<int>(m.objects.size());
    if (parts.size() == 1) {  // one shape: no compound, its origin goes into the link offset
      n.offset = parts[0].first;
      m.add_object(std::move(parts[0].second), n.name, n.moving);
      continue;
    }
    auto compound = std::make_unique<btCompoundShape>();
    for (auto& [origin, shape] : parts) {
      compound->addChildShape(origin, shape.get());
      m.shapes.push_back(std::move(shape));
    }
    m.add_object(std::move(compound), n.name, n.moving);
  }
  m.n_link_objects = static_cast<int>(m.objects.size());
  const size_t L = m.objects.size();
  m.allowed.assign(L, std::vector<char>(L, 0));
  // adjacent: a link and its nearest ancestor with geometry
  for (const LinkNode& n : m.nodes) {
    if (n.object < 0) continue;
    int a = n.parent;
    while (a >= 0 && m.nodes[a].object < 0) a = m.nodes[a].parent;
    if (a >= 0) m.allowed[n.object][m.nodes[a].object] = m.allowed[m.nodes[a].object][n.object] = 1;
  }
  // rigid: two moving links after the same last arm joint never move relative to each other
  for (const LinkNode& a : m.nodes)
    for (const LinkNode& b : m.nodes)
      if (a.object >= 0 && b.object >= 0 && a.moving && b.moving && a.last_arm == b.last_arm)
        m.allowed[a.object][b.object] = 1;
  m.rebuild_check();
  m.forward(JointVector::Zero(m.kin.n_joints()));
  m.place(false);
  return Result::success();
}

}  // namespace

CollisionModel::CollisionModel() = default;
CollisionModel::~CollisionModel() = default;
CollisionModel::CollisionModel(CollisionModel&&) noexcept = default;
CollisionModel& CollisionModel::operator=(CollisionModel&&) noexcept = default;

Result CollisionModel::load(const std::string& urdf_path, const std::string& base_link,
                            const std::string& tip_link, const MeshVertices& meshes,
                            CollisionModel& out) {
  std::string xml;
  Result r = read_file(urdf_path, xml);
  if (!r.ok()) return r;
  auto impl = std::make_unique<Impl>();
  r = build(xml, "'" + urdf_path + "'", base_link, tip_link, meshes, *impl);
  if (r.ok()) out.impl_ = std::move(impl);
  return r;
}

Result CollisionModel::load_from_string(const std::string& urdf_xml, const std::string& base_link,
                                        const std::string& tip_link, const MeshVertices& meshes,
                                        CollisionModel& out) {
  auto impl = std::make_unique<Impl>();
  Result r = build(urdf_xml, "<string>", base_link, tip_link, meshes, *impl);
  if (r.ok()) out.impl_ = std::move(impl);
  return r;
}

bool CollisionModel::loaded() const noexcept { return impl_ != nullptr; }

const Kinematics& CollisionModel::kinematics() const noexcept { return impl_->kin; }

std::vector<std::string> CollisionModel::links() const {
  return {impl_->object_names.begin(), impl_->object_names.begin() + impl_->n_link_objects};
}

std::vector<std::string> CollisionModel::moving_links() const {
  std::vector<std::string> out;
  for (int i = 0; i < impl_->n_link_objects; ++i)
    if (impl_->object_moving[i]) out.push_back(impl_->object_names[i]);
  return out;
}

Result CollisionModel::set_joint_positions(const std::map<std::string, double>& positions) {
  Impl& m = *impl_;
  std::vector<double> q = m.fixed_q;
  for (const auto& entry : positions) {
    // (no structured binding: clang 14 cannot capture one in the lambda below)
    const std::string& name = entry.first;
    const double value = entry.second;
    const auto it = std::find_if(m.nodes.begin(), m.nodes.end(),
                                 [&](const LinkNode& n) { return n.joint == name; });
    if (it == m.nodes.end())
      return Result::failure(Status::invalid_argument,
                             "set_joint_positions: '" + name + "' is not a movable joint");
    if (it->arm_index >= 0)
      return Result::failure(Status::invalid_argument,
                             "set_joint_positions: '" + name + "' is a joint of the arm");
    if (!std::isfinite(value))
      return Result::failure(Status::invalid_argument,
                             "set_joint_positions: '" + name + "' is not finite");
    q[it - m.nodes.begin()] = value;
  }
  m.fixed_q = q;
  m.forward(JointVector::Zero(m.kin.n_joints()));
  m.place(false);
  return Result::success();
}

Result CollisionModel::set_obstacles(const std::vector<CollisionBox>& boxes, double padding) {
  Impl& m = *impl_;
  if (!(padding >= 0.0) || !std::isfinite(padding))
    return Result::failure(Status::invalid_argument, "set_obstacles: padding must be >= 0");
  for (const CollisionBox& b : boxes) {
    if (!(b.half_extents.array() > 0.0).all() || !b.half_extents.allFinite() ||
        !b.pose.matrix().allFinite())
      return Result::failure(Status::invalid_argument,
                             "set_obstacles: box '" + b.name +
                                 "' needs positive, finite half-extents and a finite pose");
  }
  while (static_cast<int>(m.objects.size()) > m.n_link_objects) {
    m.world.removeCollisionObject(m.objects.back().get());
    m.objects.pop_back();
    m.shapes.pop_back();
    m.object_names.pop_back();
    m.object_moving.pop_back();
  }
  for (const CollisionBox& b : boxes) {
    const Eigen::Vector3d h = b.half_extents.array() + padding;
    auto shape = std::make_unique<btBoxShape>(btVector3(h.x(), h.y(), h.z()));
    shape->setMargin(kShapeMargin);
    m.add_object(std::move(shape), b.name, false, to_bt(b.pose));
  }
  m.rebuild_check();
  return Result::success();
}

Result CollisionModel::allow_collisions_at(const Eigen::Ref<const Eigen::VectorXd>& q) {
  Impl& m = *impl_;
  if (q.size() != m.kin.n_joints())
    return Result::failure(Status::size_mismatch, "allow_collisions_at: q has the wrong size");
  if (!q.allFinite()) return Result::failure(Status::invalid_argument, "q contains NaN or inf");
  std::vector<std::pair<int, int> > found;
  m.detect(q, [&](int a, int b) {
    if (a < m.n_link_objects && b < m.n_link_objects) found.emplace_back(a, b);
    return false;
  });
  for (const auto& [a, b] : found) m.allowed[a][b] = m.allowed[b][a] = 1;
  m.rebuild_check();
  return Result::success();
}

std::vector<CollisionPair> CollisionModel::allowed_pairs() const {
  std::vector<CollisionPair> out;
  for (int i = 0; i < impl_->n_link_objects; ++i)
    for (int j = i + 1; j < impl_->n_link_objects; ++j)
      if (impl_->allowed[i][j]) {
        auto p = std::minmax(impl_->object_names[i], impl_->object_names[j]);
        out.emplace_back(p.first, p.second);
      }
  std::sort(out.begin(), out.end());
  return out;
}

bool CollisionModel::in_collision(const Eigen::Ref<const Eigen::VectorXd>& q) {
  bool hit = false;
  impl_->detect(q, [&](int, int) { return hit = true; });
  return hit;
}

std::vector<CollisionPair> CollisionModel::colliding_pairs(
    const Eigen::Ref<const Eigen::VectorXd>& q) {
  std::vector<CollisionPair> out;
  impl_->detect(q, [&](int a, int b) {
    out.emplace_back(impl_->object_names[a], impl_->object_names[b]);
    return false;
  });
  std::sort(out.begin(), out.end());  // a compound shape may touch through several children
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

long long CollisionModel::checks() const noexcept { return impl_->checks; }

Result CollisionModel::link_pose(const Eigen::Ref<const Eigen::VectorXd>& q,
                                 const std::string& link, Eigen::Isometry3d& pose) {
  Impl& m = *impl_;
  if (q.size() != m.kin.n_joints())
    return Result::failure(Status::size_mismatch, "link_pose: q has the wrong size");
  const auto it = std::find_if(m.nodes.begin(), m.nodes.end(),
                               [&](const LinkNode& n) { return n.name == link; });
  if (it == m.nodes.end())
    return Result::failure(Status::unknown_link, "link_pose: no link '" + link + "'");
  m.forward(q);
  const KDL::Frame& f = m.frames[it - m.nodes.begin()];
  pose = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    pose.translation()[i] = f.p[i];
    for (int j = 0; j < 3; ++j) pose.linear()(i, j) = f.M(i, j);
  }
  return Result::success();
}

#endif  // A2L_HAVE_BULLET

}  // namespace a2l

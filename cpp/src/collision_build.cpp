// Building a CollisionModel's Bullet world from a URDF (collision_world.hpp).
#include "a2l/collision_model.hpp"

#if A2L_HAVE_BULLET
#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <functional>

#include "a2l/urdf_to_kdl.hpp"
#include "collision_shapes.hpp"
#include "collision_world.hpp"

namespace a2l::detail {

Result build_collision_model(const std::string& xml, const std::string& source,
                             const std::string& base_link, const std::string& tip_link,
                             const MeshVertices& meshes, CollisionModel::Impl& m) {
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

}  // namespace a2l::detail

#endif  // A2L_HAVE_BULLET

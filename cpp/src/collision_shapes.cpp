// Bullet shapes from URDF geometry (see collision_shapes.hpp).
#include "a2l/collision_model.hpp"

#if A2L_HAVE_BULLET
#include <BulletCollision/CollisionShapes/btShapeHull.h>
#include <urdf_model/link.h>

#include "collision_shapes.hpp"

namespace a2l::detail {

btTransform to_bt(const Eigen::Isometry3d& t) {
  const Eigen::Matrix3d r = t.linear();
  btMatrix3x3 m(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2));
  return btTransform(m, btVector3(t.translation().x(), t.translation().y(), t.translation().z()));
}

btTransform to_bt(const KDL::Frame& f) {
  const KDL::Rotation& r = f.M;
  btMatrix3x3 m(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2));
  return btTransform(m, btVector3(f.p.x(), f.p.y(), f.p.z()));
}

btTransform to_bt(const urdf::Pose& p) {
  return btTransform(btQuaternion(p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w),
                     btVector3(p.position.x, p.position.y, p.position.z));
}

std::unique_ptr<btCollisionShape> make_shape(const urdf::Geometry& g, const MeshVertices& meshes,
                                             const std::string& link, std::string& error) {
  std::unique_ptr<btConvexShape> s;
  switch (g.type) {
    case urdf::Geometry::BOX: {
      const auto& b = static_cast<const urdf::Box&>(g);
      s = std::make_unique<btBoxShape>(btVector3(
          b.dim.x / 2 + kLinkPadding, b.dim.y / 2 + kLinkPadding, b.dim.z / 2 + kLinkPadding));
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(g);
      const double r = c.radius + kLinkPadding;
      s = std::make_unique<btCylinderShapeZ>(btVector3(r, r, c.length / 2 + kLinkPadding));
      break;
    }
    case urdf::Geometry::SPHERE: {
      s = std::make_unique<btSphereShape>(static_cast<const urdf::Sphere&>(g).radius +
                                          kLinkPadding);
      return s;  // a sphere's margin is its radius
    }
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(g);
      const auto it = meshes.find(mesh.filename);
      if (it == meshes.end() || it->second.rows() < 4) {
        error = "collision mesh '" + mesh.filename + "' of link '" + link +
                "': no vertices given (need at least 4)";
        return nullptr;
      }
      btConvexHullShape raw;
      for (Eigen::Index i = 0; i < it->second.rows(); ++i) {
        raw.addPoint(btVector3(it->second(i, 0) * mesh.scale.x, it->second(i, 1) * mesh.scale.y,
                               it->second(i, 2) * mesh.scale.z),
                     false);
      }
      raw.recalcLocalAabb();
      raw.setMargin(0);
      btShapeHull hull(&raw);  // at most ~42 vertices: far faster than the full mesh
      hull.buildHull(0);
      auto h = std::make_unique<btConvexHullShape>();
      for (int i = 0; i < hull.numVertices(); ++i) h->addPoint(hull.getVertexPointer()[i], false);
      h->recalcLocalAabb();
      h->setMargin(kShapeMargin + kLinkPadding);  // a hull grows by its margin
      return h;
    }
    default:
      error = "link '" + link + "': unsupported collision geometry";
      return nullptr;
  }
  s->setMargin(kShapeMargin);
  return s;
}

}  // namespace a2l::detail

#endif  // A2L_HAVE_BULLET

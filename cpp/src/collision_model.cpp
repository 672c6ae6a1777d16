#include "a2l/collision_model.hpp"

#if A2L_HAVE_BULLET
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "collision_shapes.hpp"
#include "collision_world.hpp"
#endif

namespace a2l {

#if !A2L_HAVE_BULLET
bool collision_model_available() noexcept { return false; }
#else
bool collision_model_available() noexcept { return true; }

using detail::kShapeMargin;
using detail::to_bt;

namespace {

Result read_file(const std::string& path, std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Result::failure(Status::file_error, "cannot read URDF '" + path + "'");
  std::ostringstream ss;
  ss << in.rdbuf();
  text = ss.str();
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
  r = detail::build_collision_model(xml, "'" + urdf_path + "'", base_link, tip_link, meshes, *impl);
  if (r.ok()) out.impl_ = std::move(impl);
  return r;
}

Result CollisionModel::load_from_string(const std::string& urdf_xml, const std::string& base_link,
                                        const std::string& tip_link, const MeshVertices& meshes,
                                        CollisionModel& out) {
  auto impl = std::make_unique<Impl>();
  Result r =
      detail::build_collision_model(urdf_xml, "<string>", base_link, tip_link, meshes, *impl);
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
                                 [&](const detail::LinkNode& n) { return n.joint == name; });
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

void CollisionModel::set_pairwise(bool pairwise) noexcept { impl_->pairwise = pairwise; }

bool CollisionModel::pairwise() const noexcept { return impl_->pairwise; }

long long CollisionModel::checks() const noexcept { return impl_->checks; }

Result CollisionModel::link_pose(const Eigen::Ref<const Eigen::VectorXd>& q,
                                 const std::string& link, Eigen::Isometry3d& pose) {
  Impl& m = *impl_;
  if (q.size() != m.kin.n_joints())
    return Result::failure(Status::size_mismatch, "link_pose: q has the wrong size");
  const auto it = std::find_if(m.nodes.begin(), m.nodes.end(),
                               [&](const detail::LinkNode& n) { return n.name == link; });
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

// Bindings of the collision model and the transit planner (collision_model.hpp, transit.hpp).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "a2l/collision_model.hpp"
#include "a2l/transit.hpp"
#include "common.hpp"

namespace py = pybind11;

namespace a2l::bindings {

namespace {

#if A2L_HAVE_BULLET && A2L_HAVE_OMPL
void check_q(const TransitPlanner& p, const Eigen::VectorXd& q, const char* what) {
  const int n = const_cast<TransitPlanner&>(p).model().kinematics().n_joints();
  if (q.size() != n)
    raise(Status::size_mismatch, std::string(what) + " must have shape (" + std::to_string(n) +
                                     ",), got (" + std::to_string(q.size()) + ",)");
  if (!q.allFinite()) raise(Status::invalid_argument, std::string(what) + " contains NaN or inf");
}
#endif

}  // namespace

void bind_transit(py::module_& m) {
  m.def("transit_available", &transit_available,
        "True if this build has the transit planner (Bullet and OMPL).");

  py::enum_<TransitStatus>(m, "TransitStatus", "Outcome of TransitPlanner.plan().")
      .value("ok", TransitStatus::ok)
      .value("invalid_argument", TransitStatus::invalid_argument)
      .value("start_out_of_limits", TransitStatus::start_out_of_limits)
      .value("goal_out_of_limits", TransitStatus::goal_out_of_limits)
      .value("start_in_collision", TransitStatus::start_in_collision)
      .value("goal_in_collision", TransitStatus::goal_in_collision)
      .value("no_path", TransitStatus::no_path);
  m.def("transit_status_name", &transit_status_name, py::arg("status"));

  py::class_<CollisionBox>(m, "CollisionBox", "An obstacle box in the arm's base frame.")
      .def(py::init([](const std::string& name, const Eigen::Vector3d& center,
                       const Eigen::Vector3d& half_extents, const Eigen::Matrix3d& rotation) {
             CollisionBox b;
             b.name = name;
             b.pose.linear() = rotation;
             b.pose.translation() = center;
             b.half_extents = half_extents;
             return b;
           }),
           py::arg("name"), py::arg("center"), py::arg("half_extents"),
           py::arg("rotation") = Eigen::Matrix3d::Identity())
      .def_readwrite("name", &CollisionBox::name)
      .def_property_readonly(
          "center", [](const CollisionBox& b) { return Eigen::Vector3d(b.pose.translation()); })
      .def_readwrite("half_extents", &CollisionBox::half_extents);

  py::class_<TransitOptions>(m, "TransitOptions", "Options of TransitPlanner.plan().")
      .def(py::init<>())
      .def_readwrite("time_limit", &TransitOptions::time_limit)
      .def_readwrite("resolution", &TransitOptions::resolution)
      .def_readwrite("coarse_resolution", &TransitOptions::coarse_resolution)
      .def_readwrite("shorten", &TransitOptions::shorten)
      .def_readwrite("shortcut_rounds", &TransitOptions::shortcut_rounds)
      .def_readwrite("shortcut_patience", &TransitOptions::shortcut_patience)
      .def_readwrite("velocity_scale", &TransitOptions::velocity_scale)
      .def_readwrite("acceleration", &TransitOptions::acceleration)
      .def_readwrite("sample_period", &TransitOptions::sample_period)
      .def_readwrite("default_velocity", &TransitOptions::default_velocity)
      .def_readwrite("seed", &TransitOptions::seed);

  py::class_<TransitResult>(m, "TransitResult", "A planned transit (see transit.hpp).")
      .def(py::init<>())
      .def_readonly("status", &TransitResult::status)
      .def_readonly("message", &TransitResult::message)
      .def_readonly("planning_time", &TransitResult::planning_time)
      .def_readonly("waypoints", &TransitResult::waypoints)
      .def_readonly("path_length", &TransitResult::path_length)
      .def_readonly("times", &TransitResult::times)
      .def_readonly("positions", &TransitResult::positions)
      .def_readonly("velocities", &TransitResult::velocities)
      .def_readonly("accelerations", &TransitResult::accelerations)
      .def_readonly("duration", &TransitResult::duration)
      .def_readonly("collision_checks", &TransitResult::collision_checks);

  m.def(
      "time_parameterize",
      [](const Eigen::MatrixXd& waypoints, const Eigen::VectorXd& velocity,
         const Eigen::VectorXd& acceleration, double sample_period) {
        TransitResult out;
        check(time_parameterize(waypoints, velocity, acceleration, sample_period, out));
        out.status = TransitStatus::ok;
        out.waypoints = waypoints;
        return out;
      },
      py::arg("waypoints"), py::arg("velocity"), py::arg("acceleration"),
      py::arg("sample_period") = 0.01,
      "Rest-to-rest trajectory (TransitResult) along a joint-space polyline (m, n).");

#if A2L_HAVE_BULLET && A2L_HAVE_OMPL
  py::class_<TransitPlanner>(m, "TransitPlanner", R"doc(
Collision-free joint-space transit of one arm of a URDF (OMPL RRT-Connect + Bullet shapes).

Parameters
----------
urdf : str
    URDF file; its collision geometry is used (meshes as convex hulls).
base_link, tip_link : str
    The arm's chain.
meshes : dict of str to ndarray, shape (k, 3)
    Vertices of every collision mesh, keyed by the URDF's filename attribute.
)doc")
      .def(py::init([](const std::string& urdf, const std::string& base, const std::string& tip,
                       const MeshVertices& meshes) {
             CollisionModel model;
             check(CollisionModel::load(urdf, base, tip, meshes, model));
             return TransitPlanner(std::move(model));
           }),
           py::arg("urdf"), py::arg("base_link"), py::arg("tip_link"),
           py::arg("meshes") = MeshVertices())
      .def_property_readonly("n_joints",
                             [](TransitPlanner& p) { return p.model().kinematics().n_joints(); })
      .def_property_readonly("joint_names",
                             [](TransitPlanner& p) { return p.model().kinematics().joint_names(); })
      .def_property_readonly("links", [](TransitPlanner& p) { return p.model().links(); })
      .def_property_readonly("moving_links",
                             [](TransitPlanner& p) { return p.model().moving_links(); })
      .def_property_readonly("allowed_pairs",
                             [](TransitPlanner& p) { return p.model().allowed_pairs(); })
      .def_property_readonly("collision_checks",
                             [](TransitPlanner& p) { return p.model().checks(); })
      .def(
          "set_joint_positions",
          [](TransitPlanner& p, const std::map<std::string, double>& q) {
            check(p.model().set_joint_positions(q));
          },
          py::arg("positions"), "Positions of joints outside the arm (dict name -> value).")
      .def(
          "set_obstacles",
          [](TransitPlanner& p, const std::vector<CollisionBox>& boxes, double padding) {
            check(p.model().set_obstacles(boxes, padding));
          },
          py::arg("boxes"), py::arg("padding") = 0.01,
          "Replace the obstacle boxes; each grows by `padding` (m) on every side.")
      .def(
          "allow_collisions_at",
          [](TransitPlanner& p, const Eigen::VectorXd& q) {
            check_q(p, q, "q");
            check(p.model().allow_collisions_at(q));
          },
          py::arg("q"), "Ignore from now on every pair of links in collision at q (n,).")
      .def(
          "in_collision",
          [](TransitPlanner& p, const Eigen::VectorXd& q) {
            check_q(p, q, "q");
            return p.model().in_collision(q);
          },
          py::arg("q"))
      .def(
          "set_pairwise",
          [](TransitPlanner& p, bool pairwise) { p.model().set_pairwise(pairwise); },
          py::arg("pairwise"),
          "Checks pair by pair (True, the default) or by Bullet's world pass (False).")
      .def(
          "pairwise", [](TransitPlanner& p) { return p.model().pairwise(); },
          "True if checks run pair by pair.")
      .def(
          "colliding_pairs",
          [](TransitPlanner& p, const Eigen::VectorXd& q) {
            check_q(p, q, "q");
            return p.model().colliding_pairs(q);
          },
          py::arg("q"))
      .def(
          "link_pose",
          [](TransitPlanner& p, const Eigen::VectorXd& q, const std::string& link) {
            check_q(p, q, "q");
            Eigen::Isometry3d pose;
            check(p.model().link_pose(q, link, pose));
            return Eigen::Matrix4d(pose.matrix());
          },
          py::arg("q"), py::arg("link"), "Pose (4, 4) of `link` in the base frame at q.")
      .def(
          "plan",
          [](TransitPlanner& p, const Eigen::VectorXd& q_start, const Eigen::VectorXd& q_goal,
             const TransitOptions& options) {
            py::gil_scoped_release release;
            return p.plan(q_start, q_goal, options);
          },
          py::arg("q_start"), py::arg("q_goal"), py::arg("options") = TransitOptions(),
          "Plan a transit; the result's status says why when there is no path.");
#endif
}

}  // namespace a2l::bindings

// Bindings of the C++ scenes (scene/virtual.hpp, scene/bullet.hpp) and the executor.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "a2l/executor.hpp"
#include "a2l/scene/bullet.hpp"
#include "a2l/scene/virtual.hpp"
#include "common.hpp"

namespace py = pybind11;

namespace a2l::bindings {

void bind_scene(py::module_& m) {
  py::enum_<ObjectKind>(m, "ObjectKind", "What the virtual scene's object is.")
      .value("box", ObjectKind::box)
      .value("graspable", ObjectKind::graspable)
      .value("button", ObjectKind::button);

  py::class_<VirtualScene>(m, "VirtualScene", R"doc(
The fast kinematic model (docs/virtual_scene.md): an end-effector point and a box (pushed),
a graspable block or a button toggling a light.

Parameters
----------
half_size : array_like, shape (3,)
    Half-extents of the box (m).
table_z : float
    Height of the table plane (m).
eef_radius : float
    The end-effector is a sphere of this radius (m).
tie_tolerance : float
    |dx| and |dy| closer than this (m) are a tie, pushed along x (so a diagonal movement
    executed by a controller pushes like the exact diagonal).
object_kind : ObjectKind
    box (pushed), graspable (also held by a closed gripper that reached it), button (fixed;
    going down on it toggles the light).
grasp_margin : float
    A closing gripper holds a graspable object when the end-effector lies within its box grown
    by this (m).

Notes
-----
``move(d)`` moves the end-effector by ``d`` (3,). If it ends strictly inside the box grown
by ``eef_radius``, the box is pushed along the dominant planar axis of ``d`` until its face
touches the end-effector; a purely vertical ``d`` never moves the box. Deterministic.
)doc")
      .def(py::init([](const Eigen::Vector3d& half_size, double table_z, double eef_radius,
                       double tie_tolerance, ObjectKind kind, double grasp_margin) {
             if (!half_size.allFinite() || (half_size.array() <= 0.0).any() ||
                 !std::isfinite(table_z) || !(eef_radius >= 0.0) || !std::isfinite(eef_radius) ||
                 !(tie_tolerance >= 0.0) || !std::isfinite(tie_tolerance) ||
                 !(grasp_margin >= 0.0) || !std::isfinite(grasp_margin)) {
               raise(Status::invalid_argument,
                     "VirtualScene: half_size must be positive, table_z finite, eef_radius, "
                     "tie_tolerance and grasp_margin finite and >= 0");
             }
             VirtualSceneOptions o;
             o.half_size = half_size;
             o.table_z = table_z;
             o.eef_radius = eef_radius;
             o.tie_tolerance = tie_tolerance;
             o.object_kind = kind;
             o.grasp_margin = grasp_margin;
             return VirtualScene(o);
           }),
           py::arg("half_size") = Eigen::Vector3d(0.035, 0.0425, 0.04), py::arg("table_z") = 0.0,
           py::arg("eef_radius") = 0.01, py::arg("tie_tolerance") = 1e-5,
           py::arg("object_kind") = ObjectKind::box, py::arg("grasp_margin") = 0.01)
      .def("reset", &VirtualScene::reset, py::arg("eef"), py::arg("object"),
           "Put the end-effector at `eef` (3,) and the box centre at `object` (3,).")
      .def("move", &VirtualScene::move, py::arg("displacement"),
           "Move the end-effector by `displacement` (3,); True if the box moved.")
      .def_property_readonly("eef_position", &VirtualScene::eef_position,
                             "End-effector position, shape (3,).")
      .def_property_readonly("object_position", &VirtualScene::object_position,
                             "Box centre, shape (3,).")
      .def_property_readonly("half_size", &VirtualScene::half_size)
      .def_property_readonly("table_z", &VirtualScene::table_z)
      .def_property_readonly("eef_radius", &VirtualScene::eef_radius)
      .def_property_readonly("tie_tolerance", &VirtualScene::tie_tolerance)
      .def("in_contact", &VirtualScene::in_contact, py::arg("p"),
           "True if point p (3,) lies strictly inside the box grown by eef_radius.")
      .def("set_gripper", &VirtualScene::set_gripper, py::arg("closed"),
           "Close (hold a graspable object within reach) or open (drop it); True if held.")
      .def_property_readonly("gripper_closed", &VirtualScene::gripper_closed)
      .def_property_readonly("holding", &VirtualScene::holding)
      .def_property_readonly("object_kind", &VirtualScene::object_kind)
      .def_property("light_on", &VirtualScene::light_on, &VirtualScene::set_light,
                    "The light (a button press toggles it).")
      .def_property_readonly("presses", &VirtualScene::presses, "Button presses so far.");

  m.def("bullet_scene_available", &bullet_scene_available,
        "True if this build has BulletScene (Debian Bullet found at build time).");
#if A2L_HAVE_BULLET
  py::class_<BulletScene>(m, "BulletScene", R"doc(
Physics scene with Debian Bullet: static table, dynamic box, kinematic end-effector sphere.

``move(d)`` drives the end-effector along ``d`` at ``eef_speed``, then lets the box come to
rest; True if the box moved more than ``moved_threshold`` in the table plane.
)doc")
      .def(py::init([](const Eigen::Vector3d& half_size, double table_z, double eef_radius,
                       double box_mass, double friction, double time_step, double eef_speed,
                       int settle_steps) {
             if (!half_size.allFinite() || (half_size.array() <= 0.0).any() || !(box_mass > 0.0) ||
                 !(time_step > 0.0) || !(eef_speed > 0.0) || !(eef_radius > 0.0) ||
                 !(friction >= 0.0) || settle_steps < 0 || !std::isfinite(table_z)) {
               raise(Status::invalid_argument, "BulletScene: an option is out of its domain");
             }
             BulletSceneOptions o;
             o.half_size = half_size;
             o.table_z = table_z;
             o.eef_radius = eef_radius;
             o.box_mass = box_mass;
             o.friction = friction;
             o.time_step = time_step;
             o.eef_speed = eef_speed;
             o.settle_steps = settle_steps;
             return std::make_unique<BulletScene>(o);
           }),
           py::arg("half_size") = Eigen::Vector3d(0.035, 0.0425, 0.04), py::arg("table_z") = 0.0,
           py::arg("eef_radius") = 0.01, py::arg("box_mass") = 0.5, py::arg("friction") = 0.5,
           py::arg("time_step") = 1.0 / 240, py::arg("eef_speed") = 0.25,
           py::arg("settle_steps") = 120)
      .def("reset", &BulletScene::reset, py::arg("eef"), py::arg("object"))
      .def("move", &BulletScene::move, py::arg("displacement"))
      .def_property_readonly("eef_position", &BulletScene::eef_position)
      .def_property_readonly("object_position", &BulletScene::object_position)
      .def_property_readonly("physics_steps", &BulletScene::physics_steps);
#endif

  py::class_<ExecutorOptions>(m, "ExecutorOptions", "Options of Executor.")
      .def(py::init<>())
      .def_readwrite("period", &ExecutorOptions::period)
      .def_readwrite("max_speed", &ExecutorOptions::max_speed)
      .def_readwrite("damping", &ExecutorOptions::damping)
      .def_readwrite("orientation_gain", &ExecutorOptions::orientation_gain)
      .def_readwrite("position_tolerance", &ExecutorOptions::position_tolerance)
      .def_readwrite("velocity_margin", &ExecutorOptions::velocity_margin)
      .def_readwrite("limit_margin", &ExecutorOptions::limit_margin)
      .def_readwrite("workspace_min", &ExecutorOptions::workspace_min)
      .def_readwrite("workspace_max", &ExecutorOptions::workspace_max)
      .def_readwrite("watchdog_ticks", &ExecutorOptions::watchdog_ticks)
      .def_readwrite("max_angular_speed", &ExecutorOptions::max_angular_speed)
      .def_readwrite("scale_velocity", &ExecutorOptions::scale_velocity,
                     "Scale a command over a joint's velocity limit down to it (default) "
                     "instead of refusing it.")
      .def_readwrite("limit_band", &ExecutorOptions::limit_band,
                     "Share of each joint's range next to a limit where it is pushed back "
                     "(default 0.1; chains of more than 6 joints).")
      .def_readwrite("limit_avoidance", &ExecutorOptions::limit_avoidance,
                     "How fast a joint at its limit is pushed back, in the task's null space, "
                     "as a share of its velocity limit (default 0.5; 0: off).");

  py::class_<Executor>(m, "Executor", R"doc(
Differential-IK executor: end-effector position targets -> joint commands, one tick at a
time, with joint velocity, joint limit and workspace checks (a command over a joint's
velocity limit is scaled down to it: the end-effector slows and keeps its direction).

Parameters
----------
kinematics : Kinematics
    The arm (kept alive by the executor).
q0 : array_like, shape (n,)
    Start configuration, within the limits.
options : ExecutorOptions
)doc")
      .def(py::init([](const Kinematics& k, const Eigen::VectorXd& q0, const ExecutorOptions& o) {
             Executor e;
             check(e.init(k, q0, o));
             return e;
           }),
           py::arg("kinematics"), py::arg("q0"), py::arg("options") = ExecutorOptions(),
           py::keep_alive<1, 2>())
      .def("reset", &Executor::reset, py::arg("q0"))
      .def("set_orientation", &Executor::set_orientation, py::arg("rotation"),
           "Aim at this orientation (3, 3) until the next reset; a Status.")
      .def("set_target", &Executor::set_target, py::arg("position"))
      .def("tick", &Executor::tick, "One control tick; returns a Status.")
      .def_property_readonly("reached", &Executor::reached)
      .def_property_readonly("q", [](const Executor& e) { return Eigen::VectorXd(e.q()); })
      .def_property_readonly("position", &Executor::position)
      .def_property_readonly("target", &Executor::target)
      .def_property_readonly("orientation",
                             [](const Executor& e) { return Eigen::Matrix3d(e.orientation()); })
      .def_property_readonly("ticks", &Executor::ticks)
      .def_property_readonly("scaled_ticks", &Executor::scaled_ticks,
                             "Ticks since reset whose command was scaled to the velocity limits.");
}

}  // namespace a2l::bindings

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <sstream>

#include "a2l/kinematics.hpp"
#include "common.hpp"

namespace py = pybind11;

namespace a2l::bindings {
namespace {

JointVector to_joints(const Kinematics& k, const py::array_t<double, py::array::forcecast>& q,
                      const char* what) {
  const py::buffer_info info = q.request();
  if (info.ndim != 1 || info.shape[0] != k.n_joints()) {
    std::ostringstream ss;
    ss << what << " must have shape (" << k.n_joints() << ",) for the chain '" << k.base_link()
       << "' -> '" << k.tip_link() << "', got shape (";
    for (py::ssize_t i = 0; i < info.ndim; ++i) ss << (i ? ", " : "") << info.shape[i];
    ss << (info.ndim == 1 ? ",)" : ")");
    raise(Status::size_mismatch, ss.str());
  }
  JointVector v(k.n_joints());
  auto r = q.unchecked<1>();
  for (int i = 0; i < k.n_joints(); ++i) v[i] = r(i);
  if (!v.allFinite()) raise(Status::invalid_argument, std::string(what) + " contains NaN or inf");
  return v;
}

Eigen::Isometry3d to_pose(const py::array_t<double, py::array::forcecast>& t) {
  const py::buffer_info info = t.request();
  if (info.ndim != 2 || info.shape[0] != 4 || info.shape[1] != 4) {
    raise(Status::size_mismatch, "target must be a (4, 4) homogeneous transform");
  }
  auto r = t.unchecked<2>();
  Eigen::Matrix4d m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m(i, j) = r(i, j);
  if (!m.allFinite()) raise(Status::invalid_argument, "target contains NaN or inf");
  const Eigen::Matrix3d rot = m.topLeftCorner<3, 3>();
  if (!(rot.transpose() * rot).isApprox(Eigen::Matrix3d::Identity(), 1e-6) ||
      rot.determinant() < 0) {
    raise(Status::invalid_argument, "target's upper-left 3x3 block is not a rotation matrix");
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rot;
  pose.translation() = m.topRightCorner<3, 1>();
  return pose;
}

Eigen::VectorXd to_numpy(const JointVector& v) { return Eigen::VectorXd(v); }

// IK from Python arrays, without the GIL; never raises for an unreachable target.
std::pair<JointVector, IkReport> solve_ik(const Kinematics& k,
                                          const py::array_t<double, py::array::forcecast>& target,
                                          const py::array_t<double, py::array::forcecast>& q_seed,
                                          const IkOptions& options) {
  const Eigen::Isometry3d pose = to_pose(target);
  const JointVector seed = to_joints(k, q_seed, "q_seed");
  JointVector q;
  IkReport report;
  {
    py::gil_scoped_release release;
    k.ik(pose, seed, q, options, &report);
  }
  return {q, report};
}

}  // namespace

void bind_kinematics(py::module_& m) {
  py::class_<IkOptions>(m, "IkOptions", "Options of Kinematics.ik().")
      .def(py::init<>())
      .def_readwrite("max_iterations", &IkOptions::max_iterations)
      .def_readwrite("max_attempts", &IkOptions::max_attempts)
      .def_readwrite("position_tolerance", &IkOptions::position_tolerance)
      .def_readwrite("orientation_tolerance", &IkOptions::orientation_tolerance)
      .def_readwrite("orientation_weight", &IkOptions::orientation_weight)
      .def_readwrite("seed", &IkOptions::seed);

  py::class_<IkReport>(m, "IkReport", "What happened during one IK call.")
      .def_readonly("status", &IkReport::status)
      .def_readonly("attempts", &IkReport::attempts)
      .def_readonly("iterations", &IkReport::iterations)
      .def_readonly("position_error", &IkReport::position_error)
      .def_readonly("orientation_error", &IkReport::orientation_error);

  py::class_<Kinematics>(m, "Kinematics", R"doc(
Kinematics of the serial chain between two links of a URDF (C++: urdfdom -> KDL).

Parameters
----------
urdf_path : str or os.PathLike
    Path of the URDF file.
base_link, tip_link : str
    The chain's first and last links.

Raises
------
FileNotFoundError
    The URDF file does not exist or cannot be read.
a2l.URDFError
    The URDF is malformed (the message gives urdfdom's reason).
a2l.UnknownLinkError
    A link is not in the URDF, or no chain joins the two links.

Notes
-----
Poses are (4, 4) transforms of the tip frame in the base frame. The Jacobian is (6, n),
rows (vx, vy, vz, wx, wy, wz), reference point at the tip, in the base frame.
)doc")
      .def(py::init([](const py::object& path, const std::string& base, const std::string& tip) {
             const std::string p = py::str(py::module_::import("os").attr("fspath")(path));
             Kinematics k;
             check(Kinematics::load(p, base, tip, k));
             return k;
           }),
           py::arg("urdf_path"), py::arg("base_link"), py::arg("tip_link"))
      .def_property_readonly("n_joints", &Kinematics::n_joints, "Number of movable joints.")
      .def_property_readonly("joint_names", &Kinematics::joint_names,
                             "Names of the movable joints, base to tip.")
      .def_property_readonly(
          "lower", [](const Kinematics& k) { return to_numpy(k.lower()); },
          "Lower position limits, shape (n,); -inf for continuous joints.")
      .def_property_readonly(
          "upper", [](const Kinematics& k) { return to_numpy(k.upper()); },
          "Upper position limits, shape (n,); +inf for continuous joints.")
      .def_property_readonly(
          "velocity_limits", [](const Kinematics& k) { return to_numpy(k.velocity_limits()); },
          "Velocity limits, shape (n,); 0 where the URDF gives none.")
      .def_property_readonly("base_link", &Kinematics::base_link)
      .def_property_readonly("tip_link", &Kinematics::tip_link)
      .def_property_readonly("robot_name", &Kinematics::robot_name)
      .def(
          "fk",
          [](const Kinematics& k, const py::array_t<double, py::array::forcecast>& q) {
            const JointVector v = to_joints(k, q, "q");
            Eigen::Isometry3d pose;
            const Status s = k.fk(v, pose);
            if (s != Status::ok) raise(s, std::string("fk failed: ") + status_name(s));
            return Eigen::Matrix4d(pose.matrix());
          },
          py::arg("q"), "Pose of the tip in the base frame, shape (4, 4), for q of shape (n,).")
      .def(
          "jacobian",
          [](const Kinematics& k, const py::array_t<double, py::array::forcecast>& q) {
            const JointVector v = to_joints(k, q, "q");
            Jacobian jac;
            const Status s = k.jacobian(v, jac);
            if (s != Status::ok) raise(s, std::string("jacobian failed: ") + status_name(s));
            return Eigen::MatrixXd(jac);
          },
          py::arg("q"), "Geometric Jacobian, shape (6, n), for q of shape (n,).")
      .def(
          "within_limits",
          [](const Kinematics& k, const py::array_t<double, py::array::forcecast>& q, double tol) {
            const JointVector v = to_joints(k, q, "q");
            return k.within_limits(v, tol);
          },
          py::arg("q"), py::arg("tol") = 0.0, "True if q lies within the joint limits (+- tol).")
      .def(
          "ik_report",
          [](const Kinematics& k, const py::array_t<double, py::array::forcecast>& target,
             const py::array_t<double, py::array::forcecast>& q_seed, const IkOptions& options) {
            const auto [q, report] = solve_ik(k, target, q_seed, options);
            return py::make_tuple(to_numpy(q), report);
          },
          py::arg("target"), py::arg("q_seed"), py::arg("options") = IkOptions(),
          "Like ik() but never raises for an unreachable target: returns (q, IkReport).")
      .def(
          "ik",
          [](const Kinematics& k, const py::array_t<double, py::array::forcecast>& target,
             const py::array_t<double, py::array::forcecast>& q_seed, const IkOptions& options) {
            const auto [q, report] = solve_ik(k, target, q_seed, options);
            if (report.status != Status::ok) {
              const Eigen::Isometry3d pose = to_pose(target);
              std::ostringstream ss;
              ss << "IK found no solution within the joint limits of '" << k.base_link() << "' -> '"
                 << k.tip_link() << "' for target position (" << pose.translation().transpose()
                 << ") after " << report.attempts << " attempts; best error "
                 << report.position_error << " m, " << report.orientation_error << " rad";
              raise(report.status, ss.str());
            }
            return to_numpy(q);
          },
          py::arg("target"), py::arg("q_seed"), py::arg("options") = IkOptions(),
          R"doc(Joint positions, shape (n,), that put the tip at `target` (4, 4).

Position and orientation, within the joint limits: Levenberg-Marquardt from `q_seed`, then
random restarts (reproducible from options.seed).

Raises
------
a2l.IKError
    No solution within the tolerances and the joint limits.
ValueError
    Wrong shapes, NaN, or a target that is not a rigid transform.
)doc")
      .def("__repr__", [](const Kinematics& k) {
        return "<a2l.Kinematics '" + k.robot_name() + "' " + k.base_link() + " -> " + k.tip_link() +
               ", " + std::to_string(k.n_joints()) + " joints>";
      });
}

}  // namespace a2l::bindings

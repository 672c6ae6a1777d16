// Bindings of the effect vocabulary (effects.hpp): the push effects' names and directions, the
// classification of a displacement, the effect tests (push, away) and their constants, under
// the C++ names (constants: kAwayRadius -> AWAY_RADIUS, ...). a2l.skills.effects and
// a2l.rollout.effect_tests read them; nothing in Python repeats them.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <utility>

#include "a2l/effects.hpp"
#include "common.hpp"

namespace py = pybind11;

namespace a2l::bindings {

void bind_effects(py::module_& m) {
  m.attr("MAX_PUSH_EFFECTS") = kMaxPushEffects;
  m.attr("EFFECT_THRESHOLD") = kEffectThreshold;
  m.attr("EFFECT_RATIO") = kEffectRatio;
  m.attr("LIFT_THRESHOLD") = kLiftThreshold;
  m.attr("PUSH_DISTANCE") = kPushDistance;
  m.attr("AWAY_RADIUS") = kAwayRadius;
  m.attr("AWAY_TOLERANCE") = kAwayTolerance;
  m.def("retreat_offset", &retreat_offset,
        "Where the `away` behaviour waits relative to the object (m), shape (3,): back and up.");
  m.def("effect_name", &effect_name, py::arg("index"),
        "Name of push effect `index` (classify_effect's order); 'none' for any other index.");
  m.def("effect_names", &effect_names, py::arg("n_effects"),
        "Names of the n_effects (4 or 8) push effects in index order: left, right, close, far, "
        "then close_left, close_right, far_left, far_right ([] for another count).");
  m.def("effect_index", &effect_index, py::arg("name"),
        "Index of the push effect `name` among the 8, or -1.");
  m.def("effect_direction", &effect_direction, py::arg("index"),
        "Planar direction (x, y) the object moves for push effect `index`, shape (2,).");
  m.def("classify_effect", &classify_effect, py::arg("displacement"), py::arg("n_effects") = 4,
        py::arg("threshold") = kEffectThreshold, py::arg("ratio") = kEffectRatio, R"doc(
Effect index of an object displacement (3,), as a2l.skills.EffectDiscretizer: left (+y),
right (-y), close (-x), far (+x), then close_left, close_right, far_left, far_right with 8
effects; -1 below `threshold` (m) or when not finite.
)doc");
  m.def(
      "push_test",
      [](const Eigen::Vector2d& produced, int index, double distance) {
        const TestOutcome t = push_test(produced, index, distance);
        return std::make_pair(t.done, t.success);
      },
      py::arg("produced"), py::arg("index"), py::arg("distance") = kPushDistance, R"doc(
The push test of axis effect `index` (0..3), ``(done, success)``: done when the produced
planar displacement (2,) reaches `distance` (m) along the effect's direction (success when
that axis dominates) or `distance` across it (failure).
)doc");
  m.def("stayed_away", &stayed_away, py::arg("eef"), py::arg("object"), py::arg("moved"),
        py::arg("retreat") = retreat_offset(), py::arg("radius") = kAwayRadius,
        py::arg("tolerance") = kAwayTolerance, R"doc(
The `away` test: the end-effector (3,) within `radius` of ``object + retreat`` and the
object's displacement `moved` (3,) shorter than `tolerance` (m). False for a non-finite value.
)doc");
}

}  // namespace a2l::bindings

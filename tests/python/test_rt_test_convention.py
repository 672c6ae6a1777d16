"""The C++ real-time tests follow the convention `make test` relies on to run them again with
Eigen's allocation guard (tests/cpp/alloc_counter.hpp): every gtest that counts allocations
has ``NoAlloc`` in its suite or test name, and every real-time entry point of the runtime is
called inside such a test."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TESTS = ROOT / "tests" / "cpp"
#: The guarded run's ctest pattern (Makefile: GUARD_TESTS).
GUARD_PATTERN = "NoAlloc|AllocationCounter"
#: Real-time entry points (their C++ spelling at a call site) -> what they are.
REAL_TIME_CALLS = {
    "a2l::step(": "skill step (with and without smoothing)",
    "a2l::step_ds(": "skill step of the DS phases",
    ".tick()": "executor control tick",
    ".set_target(": "executor target (each new movement of a control tick)",
    "scene.move(": "virtual scene move",
    "Discretizer::context_bin(": "context bins (the step's, and the learning side's through "
    "a2l._core.context_bins)",
    "classify_effect(": "effect classification (a2l-run's loop; a2l._core.classify_effects)",
    "stayed_away(": "the away test (a2l-run's effect detection; a2l._core.stayed_away)",
    "push_test(": "the push test (a2l._core.push_test)",
    ".fk(": "forward kinematics",
    ".jacobian(": "Jacobian",
    ".ik(": "inverse kinematics",
    ".forward(": "diffeomorphic DS: forward map",
    ".inverse(": "diffeomorphic DS: inverse map",
    ".velocity(": "diffeomorphic DS: velocity",
    ".rollout(": "diffeomorphic DS: rollout",
}
_TEST = re.compile(r"^TEST(?:_P|_F)?\(\s*(\w+)\s*,\s*(\w+)\s*\)", re.MULTILINE)


def _tests() -> list[tuple[str, str, str, str]]:
    """(file, suite, name, body) of every gtest in tests/cpp."""
    out = []
    for path in sorted(TESTS.glob("test_*.cpp")):
        text = path.read_text()
        heads = list(_TEST.finditer(text))
        for i, m in enumerate(heads):
            end = heads[i + 1].start() if i + 1 < len(heads) else len(text)
            out.append((path.name, m.group(1), m.group(2), text[m.end():end]))
    return out


def test_the_guard_pattern_is_the_makefiles() -> None:
    assert f"GUARD_TESTS := {GUARD_PATTERN}" in (ROOT / "Makefile").read_text()


def test_every_allocation_counting_test_is_in_the_guarded_run() -> None:
    tests = _tests()
    assert len(tests) > 20
    counting = [(f, s, n) for f, s, n, body in tests if "AllocationGuard" in body]
    assert len(counting) >= 4
    missed = [t for t in counting if not re.search(GUARD_PATTERN, f"{t[1]}.{t[2]}")]
    assert not missed, f"rename these to hold 'NoAlloc' (make test's guarded run): {missed}"


def test_every_real_time_call_is_inside_a_no_alloc_test() -> None:
    guarded = [body for _, s, n, body in _tests()
               if re.search(GUARD_PATTERN, f"{s}.{n}") and "AllocationGuard" in body]
    for call, what in REAL_TIME_CALLS.items():
        assert any(call in body for body in guarded), f"{what} ({call}) is in no NoAlloc test"

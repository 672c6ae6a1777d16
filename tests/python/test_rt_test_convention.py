"""The C++ real-time tests follow the convention `make test` relies on to run them again with
Eigen's allocation guard (tests/cpp/alloc_counter.hpp): every gtest that counts allocations
has ``NoAlloc`` in its suite or test name, and every real-time entry point of the runtime is
called inside the guarded section of such a test: between ``AllocationGuard NAME`` and the
first ``NAME.allocations()`` after it (a call of a lambda defined in the same test counts with
the lambda's body), not merely somewhere in the test's text."""

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
_GUARD = re.compile(r"\bAllocationGuard\s+(\w+)\s*[;{(]")
_LAMBDA = re.compile(r"\bauto\s+(\w+)\s*=\s*\[[^\]]*\]\s*\([^)]*\)[^{;]*\{")


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


def _block(text: str, open_brace: int) -> str:
    """The text from the brace at `open_brace` to its matching closing brace."""
    depth = 0
    for i in range(open_brace, len(text)):
        depth += {"{": 1, "}": -1}.get(text[i], 0)
        if depth == 0:
            return text[open_brace:i + 1]
    raise ValueError("unbalanced braces")


def guarded_sections(body: str) -> list[str]:
    """The guarded sections of a test body: from each ``AllocationGuard NAME`` to the first
    ``NAME.allocations()`` after it (the section the assertion counts), with the bodies of
    the lambdas defined earlier in the test and called inside the section appended.
    A guard whose count is never read guards nothing and yields no section."""
    lambdas = {m.group(1): _block(body, m.end() - 1) for m in _LAMBDA.finditer(body)}
    out = []
    for g in _GUARD.finditer(body):
        end = body.find(f"{g.group(1)}.allocations()", g.end())
        if end < 0:
            continue
        section = body[g.end():end]
        called = [lam for name, lam in lambdas.items()
                  if re.search(rf"\b{name}\s*\(", section)]
        out.append("\n".join([section, *called]))
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


def test_every_real_time_call_is_inside_a_guarded_section() -> None:
    guarded = [section for _, s, n, body in _tests() if re.search(GUARD_PATTERN, f"{s}.{n}")
               for section in guarded_sections(body)]
    assert len(guarded) >= 6
    for call, what in REAL_TIME_CALLS.items():
        assert any(call in section for section in guarded), \
            f"{what} ({call}) is called in no NoAlloc test's guarded section"


def test_the_section_ends_where_the_count_is_read() -> None:
    body = """
  auto run = [&](int k) { return ds.velocity(p, v); };
  auto unused = [&]() { return a2l::step_ds(s, st, e, o, v, out); };
  a.fk(q, pose);
  {
    a2l::test::AllocationGuard guard;
    scene.move(d);
    run(3);
    EXPECT_EQ(guard.allocations(), 0u);
  }
  ex.tick();
  a2l::test::AllocationGuard never_read;
  kin.ik(t, q, sol);
"""
    (section,) = guarded_sections(body)
    assert "scene.move(" in section and ".velocity(" in section  # directly, through run()
    for outside in (".fk(", ".tick()", ".ik(", "a2l::step_ds("):
        assert outside not in section, outside

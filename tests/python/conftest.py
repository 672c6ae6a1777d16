"""Shared pytest fixtures, and ``A2L_NO_SKIPS``: with it set to 1 (``make test`` sets it), a
skipped test fails the run, so that a missing optional extra (ROS 2, Rerun) cannot pass
silently by skipping its tests."""

from __future__ import annotations

import os

import numpy as np
import pytest

import a2l
from a2l.robot import arm_spec


@pytest.fixture(scope="session")
def baxter_right() -> a2l.Kinematics:
    """C++ kinematics of Baxter's right arm (base -> right_gripper)."""
    spec = arm_spec("baxter", "right")
    return a2l.Kinematics(spec.urdf, spec.base_link, spec.tip_link)


@pytest.fixture
def rng() -> np.random.Generator:
    """A seeded generator: every test is reproducible."""
    return np.random.default_rng(12345)


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    """Fail the run on any skipped test when ``A2L_NO_SKIPS=1`` (see the module)."""
    if os.environ.get("A2L_NO_SKIPS") != "1":
        return
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    skipped = reporter.stats.get("skipped", []) if reporter is not None else []
    if skipped:
        for r in skipped:
            reason = r.longrepr[2] if isinstance(r.longrepr, tuple) else str(r.longrepr)
            reporter.write_line(f"A2L_NO_SKIPS: skipped {r.nodeid}: {reason}", red=True)
        session.exitstatus = pytest.ExitCode.TESTS_FAILED

"""Shared pytest fixtures."""

from __future__ import annotations

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

"""NovEB's parts, without a simulator: novelty, the adaptive archive threshold, the
(mu + lambda) loop told only image descriptors, and the baselines' ask/tell contracts."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import a2l
from a2l.acquisition import (
    ArchiveThreshold,
    GoalBabbling,
    NovEB,
    NovEBConfig,
    RandomTrajectories,
    Strategy,
    WaypointEncoding,
    drive,
    image_descriptor,
    novelty,
)


def test_a_duplicated_behaviour_is_less_novel_than_a_new_one() -> None:
    rng = np.random.default_rng(0)
    crowd = rng.normal(0.0, 0.01, (30, 64))            # many near-identical "nothing moved"
    duplicate = crowd[0] + rng.normal(0.0, 0.01, 64)
    new = crowd[0] + 0.5                                 # an image that changed a lot
    b = np.vstack([duplicate, new])
    scores = novelty(b, np.vstack([b, crowd]), k=15)
    assert scores[0] < scores[1] / 10
    # and an exact copy of an archived behaviour is less novel than a slightly moved one
    s = novelty(np.vstack([crowd[:1], crowd[:1] + 0.05]), crowd, k=15,
                self_in_reference=False)
    assert s[0] < s[1]


def test_novelty_is_the_mean_distance_to_the_k_nearest() -> None:
    ref = np.array([[0.0], [1.0], [2.0], [4.0]])
    # behaviour 0 (at 0) is ref row 0: its neighbours are 1 and 2 (k = 2) -> mean 1.5
    assert novelty(ref[:1], ref, k=2)[0] == pytest.approx(1.5)
    assert novelty(np.array([[3.0]]), ref, k=2, self_in_reference=False)[0] == \
        pytest.approx(1.0)
    with pytest.raises(ValueError, match="dimension"):
        novelty(np.zeros((1, 2)), np.zeros((3, 3)))


def test_threshold_rises_after_many_entries_and_falls_after_ten_idle_generations() -> None:
    t = ArchiveThreshold(value=0.1)
    assert t.update(4) == pytest.approx(0.12)            # 4 entered: x 1.2
    assert t.update(3) == pytest.approx(0.12)            # 3 entered: unchanged
    for _ in range(9):
        assert t.update(0) == pytest.approx(0.12)        # 9 idle generations: unchanged
    assert t.update(0) == pytest.approx(0.114)           # the 10th: x 0.95
    for _ in range(9):
        t.update(0)
    t.update(1)                                          # an entry resets the idle count
    for _ in range(9):
        assert t.update(0) == pytest.approx(0.114)
    assert t.update(0) == pytest.approx(0.114 * 0.95)
    low = ArchiveThreshold(value=1.5e-3, floor=1e-3)
    for _ in range(200):
        low.update(0)
    assert low.value == pytest.approx(1e-3)              # never below the floor


def _toy_world(genotypes: list[np.ndarray]) -> np.ndarray:
    """A toy 'camera': only genotypes whose first gene is above 0.8 change the image, and
    the change depends on the second gene (like a box pushed to different places)."""
    out = np.zeros((len(genotypes), 16))
    for i, g in enumerate(genotypes):
        if g[0] > 0.8:
            out[i, int(g[1] * 15.999)] = 1.0
    return out


def test_noveb_archive_and_threshold_follow_the_rule_and_selection_seeks_novelty() -> None:
    noveb = NovEB(4, seed=3, budget=400, config=NovEBConfig(mu=10, lambda_=10, k=5,
                                                            threshold=0.05))
    assert isinstance(noveb, Strategy)
    drive(noveb, _toy_world, batch=10)
    assert noveb.generation == 40 and noveb.told == 400
    h = noveb.history
    for a, b in zip(h, h[1:], strict=False):             # the threshold as specified
        if a["admitted"] >= 4:
            assert b["threshold"] == pytest.approx(a["threshold"] * 1.2)
        elif a["admitted"] > 0:
            assert b["threshold"] == pytest.approx(a["threshold"])
    assert len(noveb.archive) == sum(x["admitted"] for x in h)
    # the population ends where images change: most of it above 0.8 on the first gene,
    # where a uniform draw puts 20 %
    share = np.mean([ind[0] > 0.8 for ind in noveb.population])
    assert share >= 0.6


def test_noveb_is_told_image_descriptors_only() -> None:
    noveb = NovEB(4, seed=0, budget=10, config=NovEBConfig(mu=5, lambda_=5))
    asked = noveb.ask(5)
    with pytest.raises(TypeError, match="image descriptors only"):
        noveb.tell(asked, [{"box": (0.6, -0.2, -0.16)}] * 5)   # object state: refused
    with pytest.raises(TypeError, match="image descriptors only"):
        noveb.tell(asked, np.zeros((5, 3), dtype=int))
    with pytest.raises(ValueError, match="out of ask order"):
        noveb.tell(asked[::-1], np.zeros((5, 8)))
    noveb.tell(asked, np.zeros((5, 8)))
    for cls in (RandomTrajectories, GoalBabbling):
        s = cls(4, 0, 10)
        with pytest.raises(TypeError, match="image descriptors only"):
            s.tell(s.ask(2), [(0.1, 0.2)] * 2)


@pytest.mark.parametrize("make", [
    lambda seed: NovEB(4, seed, 60, NovEBConfig(mu=10, lambda_=10, k=5)),
    lambda seed: GoalBabbling(4, seed, 60, bootstrap=10),
    lambda seed: RandomTrajectories(4, seed, 60),
])
def test_a_seed_reproduces_the_genotypes(make) -> None:  # noqa: ANN001
    def run(seed: int) -> np.ndarray:
        asked: list[np.ndarray] = []

        def evaluate(g: list[np.ndarray]) -> np.ndarray:
            asked.extend(g)
            return _toy_world(g)

        drive(make(seed), evaluate, batch=10)
        return np.array(asked)

    a, b, c = run(7), run(7), run(8)
    assert a.shape == (60, 4)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)
    assert np.all((a >= 0) & (a <= 1))


def test_goal_babbling_reuses_what_it_saw() -> None:
    """After its bootstrap, goal babbling perturbs remembered genotypes: every new genotype
    lies within a few sigma of one it was told about."""
    gb = GoalBabbling(4, 1, 80, bootstrap=20, sigma=0.02)
    drive(gb, _toy_world, batch=10)
    memory = np.array(gb.genotypes[:20])
    later = np.array(gb.genotypes[20:30])                 # asked from the bootstrap memory
    d = np.min(np.linalg.norm(later[:, None, :] - memory[None], axis=2), axis=1)
    assert np.all(d < 0.02 * 6)


def test_waypoint_encoding_and_image_descriptor() -> None:
    enc = WaypointEncoding((0.4, -0.6, -0.2), (0.8, 0.0, 0.0), n_waypoints=3)
    pts = enc.decode(np.array([0, 0, 0, 1, 1, 1, 0.5, 0.5, 0.5]))
    assert np.allclose(pts, [[0.4, -0.6, -0.2], [0.8, 0.0, 0.0], [0.6, -0.3, -0.1]])
    with pytest.raises(ValueError, match="9 finite numbers"):
        enc.decode(np.zeros(6))
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        enc.decode(np.full(9, 1.5))
    img = np.zeros((120, 160, 3), np.uint8)
    moved = img.copy()
    moved[40:60, 60:80] = 255
    d = image_descriptor(moved, img, size=32)
    assert d.shape == (1024,) and d.max() > 0.5 and d.min() == 0.0
    assert np.all(image_descriptor(img, img) == 0)
    with pytest.raises(ValueError, match="RGB array of uint8"):
        image_descriptor(np.zeros((10, 10)), None)


def test_drive_is_the_loop_written_by_hand() -> None:
    """The babbling experiment and NovEB's acquisition are driven by ``drive``
    (told a part of each outcome, recording the rest after each batch): it asks, evaluates,
    tells and records in the order of the loop they wrote by hand, so a seed gives the same
    genotypes, archive and records."""
    def outcomes(g: list[np.ndarray]) -> list[tuple[np.ndarray, float]]:
        return [(d, float(d.sum())) for d in _toy_world(g)]

    by_hand = NovEB(4, 3, 60, NovEBConfig(mu=10, lambda_=10, k=5))
    hand_records: list[tuple[np.ndarray, float]] = []
    while not by_hand.done:
        asked = by_hand.ask(10)
        out = outcomes(asked)
        by_hand.tell(asked, np.array([d for d, _ in out]))
        hand_records += [(g, s) for g, (_, s) in zip(asked, out, strict=True)]
    driven = NovEB(4, 3, 60, NovEBConfig(mu=10, lambda_=10, k=5))
    records: list[tuple[np.ndarray, float]] = []
    drive(driven, outcomes, 10, told=lambda out: np.array([d for d, _ in out]),
          on_batch=lambda asked, out: records.extend(
              (g, s) for g, (_, s) in zip(asked, out, strict=True)))
    assert len(records) == len(hand_records) == 60
    for (g, s), (hg, hs) in zip(records, hand_records, strict=True):
        assert np.array_equal(g, hg) and s == hs
    assert len(driven.archive) == len(by_hand.archive) > 0
    assert np.array_equal(np.array(driven.archive), np.array(by_hand.archive))


def test_only_drive_asks_and_tells() -> None:
    """No module of the package writes the ask/tell loop again: ``drive`` and
    ``drive_ahead`` (:mod:`a2l.acquisition.protocol`) are the only callers."""
    root = Path(a2l.__file__).parent
    home = root / "acquisition" / "protocol.py"
    loops = [p.relative_to(root).as_posix() for p in sorted(root.rglob("*.py"))
             if p != home and re.search(r"\.(ask|tell)\(", p.read_text(encoding="utf-8"))]
    assert loops == []

"""Demonstrations: validation, resampling, CSV and Parquet files."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from a2l.lfd import Demonstration, load_demonstrations, save_demonstrations


def _demo(d: int = 2, n: int = 50, frame: str = "object",
          states: dict[str, str] | None = None) -> Demonstration:
    t = np.linspace(0.0, 2.0, n) ** 1.5            # not uniform: resampling has work to do
    pos = np.column_stack([np.cos(t), np.sin(t), t][:d]) * 0.1
    return Demonstration(pos, t, frame, states or {})


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_roundtrip_several_demonstrations(tmp_path, suffix):
    demos = [_demo(3, 40, "object", {"light": "on"}), _demo(3, 25, "table", {})]
    path = save_demonstrations(tmp_path / f"demos{suffix}", demos)
    back = load_demonstrations(path)
    assert len(back) == 2
    for a, b in zip(demos, back, strict=True):
        assert np.array_equal(a.positions, b.positions)
        assert np.array_equal(a.times, b.times)
        assert (a.frame, a.states) == (b.frame, b.states)
    assert list(pd.read_csv(path).columns if suffix == ".csv" else
                pd.read_parquet(path).columns) == ["demo", "t", "x", "y", "z", "frame",
                                                   "states"]


def test_two_dimensional_files_have_no_z(tmp_path):
    path = save_demonstrations(tmp_path / "d.csv", _demo(2))
    assert "z" not in pd.read_csv(path).columns
    assert load_demonstrations(path)[0].dim == 2


def test_resample_by_time_and_by_arc_length():
    demo = _demo(2, 80)
    by_t = demo.resample(30, "time")
    assert len(by_t.times) == 30
    assert np.allclose(np.diff(by_t.times), by_t.duration / 29)
    assert np.allclose(by_t.positions[[0, -1]], demo.positions[[0, -1]])
    by_s = demo.resample(30, "arclength")
    steps = np.linalg.norm(np.diff(by_s.positions, axis=0), axis=1)
    assert steps.std() < 0.02 * steps.mean()        # equal steps along the path
    assert np.all(np.diff(by_s.times) > 0)
    with pytest.raises(ValueError, match="by"):
        demo.resample(10, "speed")


@pytest.mark.parametrize("positions, times, message", [
    (np.zeros((5, 4)), np.arange(5.0), "shape"),
    (np.zeros((5, 2)), np.arange(4.0), "times"),
    (np.zeros((5, 2)), np.array([0, 1, 1, 2, 3.0]), "increasing"),
    (np.full((5, 2), np.nan), np.arange(5.0), "non-finite"),
])
def test_bad_demonstrations_are_refused(positions, times, message):
    with pytest.raises(ValueError, match=message):
        Demonstration(positions, times)


def _write(tmp_path, frame: pd.DataFrame, name: str = "bad.csv"):
    path = tmp_path / name
    frame.to_csv(path, index=False)
    return path


def test_bad_files_are_refused_with_the_problem_named(tmp_path):
    good = _demo(2, 10).to_frame()
    with pytest.raises(ValueError, match=r"missing column.*'states'"):
        load_demonstrations(_write(tmp_path, good.drop(columns="states")))
    times = good.copy()
    times.loc[5, "t"] = times.loc[4, "t"]
    with pytest.raises(ValueError, match="demo 0.*increasing"):
        load_demonstrations(_write(tmp_path, times))
    frames = good.copy()
    frames.loc[3, "frame"] = "table"
    with pytest.raises(ValueError, match="'frame' changes"):
        load_demonstrations(_write(tmp_path, frames))
    states = good.copy()
    states["states"] = "{not json"
    with pytest.raises(ValueError, match="not valid JSON"):
        load_demonstrations(_write(tmp_path, states))
    text = good.copy()
    text["x"] = "a"
    with pytest.raises(ValueError, match="'x' is not numeric"):
        load_demonstrations(_write(tmp_path, text))
    with pytest.raises(ValueError, match="unknown demonstration file type"):
        load_demonstrations(tmp_path / "demos.txt")
    with pytest.raises(FileNotFoundError):
        load_demonstrations(tmp_path / "missing.csv")
    garbage = tmp_path / "garbage.parquet"
    garbage.write_bytes(b"not a parquet file")
    with pytest.raises(ValueError, match="cannot read as parquet"):
        load_demonstrations(garbage)

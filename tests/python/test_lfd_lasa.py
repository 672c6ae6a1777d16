"""A short LASA benchmark run (2 shapes, small settings) and the metrics it reports."""

from __future__ import annotations

import json

import numpy as np
import pytest

from a2l.cli import main
from a2l.experiments.lasa import LasaConfig, lasa_shapes, load_lasa_shape
from a2l.lfd import DiffeoDS
from a2l.lfd.metrics import dtw_mean_distance, swept_error_area, velocity_rmse


def test_the_dataset_has_30_shapes_of_7_demonstrations():
    shapes = lasa_shapes()
    assert len(shapes) == 30 and "GShape" in shapes
    demos, durations = load_lasa_shape("Angle")
    assert len(demos) == len(durations) == 7
    assert demos[0].shape == (1000, 2) and np.allclose(demos[0][-1], 0.0)
    with pytest.raises(ValueError, match="unknown LASA shape"):
        load_lasa_shape("Circle")


def test_metrics_on_known_cases():
    t = np.linspace(0.0, 1.0, 101)
    a = np.column_stack([t, np.zeros_like(t)])
    b = a + [0.0, 0.5]                              # the same segment, 0.5 above
    assert dtw_mean_distance(a, b) == pytest.approx(0.5)
    assert dtw_mean_distance(a, a) == 0.0
    # every other sample: the odd ones align with a neighbour 0.01 away
    assert dtw_mean_distance(a, a[::2]) == pytest.approx(0.01 * 50 / 101)
    assert swept_error_area(a, b) == pytest.approx(0.5)      # a 1 x 0.5 rectangle
    assert velocity_rmse(a, b, 1.0) == pytest.approx(0.0, abs=1e-12)
    assert velocity_rmse(2 * a, a, 1.0) == pytest.approx(1.0)


def test_short_lasa_run_writes_the_run_directory(tmp_path):
    out = tmp_path / "lasa"
    code = main(["experiment", "lasa", "--out", str(out), "--shapes", "Angle,Line",
                 "--K", "40", "--mu", "0.6", "--starts", "40", "--workers", "2", "--quiet"])
    assert code == 0
    metrics = json.loads((out / "metrics.json").read_text())
    for section in ("shapes", "dmp", "linear", "demo_spread"):
        assert set(metrics[section]) == {"Angle", "Line"}
    a2l = metrics["shapes"]["Angle"]
    assert {"dtw", "sea", "vrmse", "fit_ms", "eval_us", "converged", "converged_euler",
            "roundtrip_max"} <= set(a2l)
    assert set(metrics["dmp"]["Line"]) == {"dtw", "sea", "vrmse"}
    assert set(metrics["linear"]["Line"]) == {"dtw", "sea", "vrmse"}
    assert set(metrics["demo_spread"]["Line"]) == {"dtw"}
    for name in ("Angle", "Line"):
        m = metrics["shapes"][name]
        assert m["converged"] == 1.0                         # every start reached the target
        assert m["converged_euler"] == 1.0                   # also with coarse Euler steps
        assert m["worst_end_distance"] < 0.5 and m["roundtrip_max"] < 1e-9
        assert 0 < m["dtw"] < metrics["linear"][name]["dtw"] or name == "Line"
        assert m["fit_ms"] > 0 and m["eval_us"] > 0
    # the angle is far from a straight line: the DS must beat the linear floor clearly
    assert metrics["shapes"]["Angle"]["dtw"] < 0.5 * metrics["linear"]["Angle"]["dtw"]
    report = (out / "report.md").read_text()
    assert "| Angle |" in report and "lasa.png" in report
    assert (out / "lasa.png").stat().st_size > 10_000
    ds = DiffeoDS.load(out / "ds" / "Angle.a2lb")
    assert ds.n_maps <= 40 and ds.metadata["shape"] == "Angle"
    config = json.loads((out / "config.json").read_text())
    assert config["lasa"]["K"] == 40 and config["lasa"]["n_starts"] == 40


def test_lasa_command_refuses_unknown_shapes(tmp_path, capsys):
    with pytest.raises(SystemExit):
        main(["experiment", "lasa", "--out", str(tmp_path / "x"), "--shapes", "Circle"])
    assert "unknown shape" in capsys.readouterr().err


def test_config_validation_names_the_parameter():
    with pytest.raises(ValueError, match="mu"):
        LasaConfig(mu=1.5).validate()
    for bad, name in (({"n_starts": 0}, "n_starts"), ({"start_steps": 0}, "start_steps"),
                      ({"tolerance": 0.0}, "tolerance"), ({"horizon": -1.0}, "horizon"),
                      ({"arrival": 1.0}, "arrival"), ({"direction": "up"}, "direction")):
        with pytest.raises(ValueError, match=name):
            LasaConfig(**bad).validate()


@pytest.mark.parametrize("direction", ["to_demo", "to_line"])
def test_exact_flow_check_matches_a_fine_rollout(direction):
    """``converged`` follows the exact flow: its end points are those of a fine RK4 rollout."""
    from a2l.experiments.lasa import _exact_flow_check

    demos, durations = load_lasa_shape("Angle")
    ds = DiffeoDS.fit(demos[0], K=30, beta=0.5, mu=0.6, duration=durations[0],
                      direction=direction)
    starts = np.array([[-40.0, 10.0], [5.0, -8.0], [ds.target[0] + 0.1, ds.target[1]]])
    horizon = 0.3 * durations[0]                   # short: not every start gets there
    check = _exact_flow_check(ds, starts, horizon, tolerance=0.5)
    ends = np.array([ds.rollout(s, horizon / 2000, 2001, "rk4")[-1] for s in starts])
    dist = np.linalg.norm(ends - ds.target, axis=1)
    assert check["worst_end_distance"] == pytest.approx(dist.max(), rel=1e-6)
    assert check["converged"] == pytest.approx(np.mean(dist < 0.5))
    assert check["roundtrip_max"] < 1e-9

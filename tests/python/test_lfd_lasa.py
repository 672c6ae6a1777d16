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
                 "--K", "40", "--mu", "0.6", "--starts", "40", "--workers", "2",
                 "--tune", "false", "--query_points", "20", "--quiet"])
    assert code == 0
    metrics = json.loads((out / "metrics.json").read_text())
    for section in ("shapes", "dmp", "linear", "demo_spread"):
        assert set(metrics[section]) == {"Angle", "Line"}
    a2l = metrics["shapes"]["Angle"]
    assert {"dtw", "heldout_dtw", "sea", "vrmse", "fit_ms", "eval_us", "eval_p999_us",
            "converged", "tolerance", "fit_mean_error", "other_direction_mean_error",
            "direction", "heldout_direction"} <= set(a2l)
    assert set(metrics["dmp"]["Line"]) == {"dtw", "heldout_dtw", "sea", "vrmse"}
    assert set(metrics["linear"]["Line"]) == {"dtw", "sea", "vrmse"}
    assert set(metrics["demo_spread"]["Line"]) == {"dtw"}
    assert metrics["tuning"] is None and metrics["summary"]["n_shapes"] == 2
    from a2l.experiments.lasa_report import headline_table

    assert headline_table(metrics).splitlines()[2].startswith("| 2 (0) | ")
    for name in ("Angle", "Line"):
        m = metrics["shapes"][name]
        demos, _ = load_lasa_shape(name)
        scale = np.ptp(np.vstack(demos), axis=0).max()
        assert m["tolerance"] == pytest.approx(0.01 * scale)
        assert m["converged"] == 1.0                         # every start reached the target
        assert m["worst_end_distance"] <= m["tolerance"]
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


def test_tuning_split_and_choice():
    from a2l.experiments.lasa_tuning import DMP_CANDIDATES, DS_CANDIDATES, choose, tuning_split

    shapes = lasa_shapes()
    split = tuning_split(shapes, 10)
    assert len(set(split)) == 10 and set(split) <= set(shapes)
    assert split == tuning_split(shapes, 10) != tuning_split(shapes, 10, seed=1)
    assert len(DS_CANDIDATES) == len(DMP_CANDIDATES)        # the same budget
    n = len(DS_CANDIDATES)
    per_shape = {"A": {"ds": [3.0] * n, "dmp": [2.0] * n},
                 "B": {"ds": [3.0] * n, "dmp": [2.0] * n}}
    per_shape["A"]["ds"][5] = 1.0
    per_shape["B"]["dmp"][2] = 0.0
    chosen = choose(per_shape)
    assert chosen["ds"] == DS_CANDIDATES[5] and chosen["dmp"] == DMP_CANDIDATES[2]
    with pytest.raises(ValueError, match="tuning_shapes"):
        tuning_split(shapes, 30)


def test_lasa_command_refuses_unknown_shapes(tmp_path, capsys):
    with pytest.raises(SystemExit):
        main(["experiment", "lasa", "--out", str(tmp_path / "x"), "--shapes", "Circle"])
    assert "unknown shape" in capsys.readouterr().err


def test_config_validation_names_the_parameter():
    with pytest.raises(ValueError, match="mu"):
        LasaConfig(mu=1.5).validate()
    for bad, name in (({"n_starts": 0}, "n_starts"), ({"control_dt": 0.0}, "control_dt"),
                      ({"tolerance": 0.0}, "tolerance"), ({"horizon": -1.0}, "horizon"),
                      ({"arrival": 1.0}, "arrival"), ({"direction": "up"}, "direction"),
                      ({"dmp_regularisation": -1.0}, "dmp_regularisation"),
                      ({"tuning_shapes": 30}, "tuning_shapes")):
        with pytest.raises(ValueError, match=name):
            LasaConfig(**bad).validate()


@pytest.mark.parametrize("direction", ["to_demo", "to_line"])
def test_arrival_is_the_euler_rollout_stopped_at_the_tolerance(direction):
    """``converged`` integrates the C++ DS as ``rollout(..., "euler")`` does and stops at the
    first state within the tolerance."""
    demos, durations = load_lasa_shape("Angle")
    ds = DiffeoDS.fit(demos[0], K=30, beta=0.5, mu=0.6, duration=durations[0],
                      direction=direction)
    starts = np.array([[-40.0, 10.0], [5.0, -8.0], [ds.target[0] + 0.1, ds.target[1]]])
    steps, dist = ds.arrival(starts, 1e-3, 20_000, 0.4)
    assert steps[2] == 0 and dist[2] == pytest.approx(0.1)  # already there
    for i in range(2):
        assert 100 < steps[i] < 20_000
        path = ds.rollout(starts[i], 1e-3, steps[i] + 1, "euler")
        gaps = np.linalg.norm(path - ds.target, axis=1)
        assert gaps[-1] == dist[i] <= 0.4 < gaps[:-1].min()
    short, sdist = ds.arrival(starts[:2], 1e-3, 50, 0.4)   # too few steps: not arrived
    assert (short == 50).all() and (sdist > 0.4).all()
    with pytest.raises(ValueError, match="dt > 0"):
        ds.arrival(starts, 0.0, 10, 0.4)


@pytest.mark.parametrize("name", ["Angle", "JShape"])
def test_the_ds_beats_the_tuned_dmp_on_held_out_demonstrations(name):
    """The held-out protocol (learn from demonstrations 1-4, DTW on 5-7): the DS with its
    default settings against the DMP with the best of every tuning candidate on this very
    shape (a DMP tuned at least as well as the experiment's). Measured with this code at
    56846ef: the DS's DTW 1.06 (Angle) and 1.37 (JShape), 0.69 and 0.54 of the best DMP's
    (1.53, 2.53); a regression that loses a fifth of that lead fails (with K = 3: 2.89 and
    8.22)."""
    from a2l.experiments.lasa_methods import (
        dmp_reproductions,
        ds_reproductions,
        fit_ds,
        scores,
        split,
    )
    from a2l.experiments.lasa_tuning import DMP_CANDIDATES

    cfg = LasaConfig()
    train, train_t, test, test_t = split(*load_lasa_shape(name), "heldout")
    ds, _ = fit_ds(train, train_t, cfg.fit_parameters(), cfg.arrival, {})
    ds_dtw = scores(ds_reproductions(ds, test, test_t), test, test_t)["dtw"]
    dmp_dtw = min(scores(dmp_reproductions(train, train_t, test, c["dmp_weights"],
                                           c["dmp_regularisation"]), test, test_t)["dtw"]
                  for c in DMP_CANDIDATES)
    assert ds_dtw < 0.8 * dmp_dtw, (ds_dtw, dmp_dtw)

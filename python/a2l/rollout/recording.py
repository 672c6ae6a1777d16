"""Recordings a person can watch: a run written as a Rerun recording (``.rrd``, opened by
``a2l view FILE.rrd``; the ``ros`` extra installs ``rerun-sdk``).

:class:`RerunRecorder` logs, per rollout ``i`` and per step (timelines ``step`` and
``time``), under ``rollout/<i>/`` (``<group>/rollout/<i>/`` in a recording of several runs,
e.g. ``seed/3/rollout/0/`` for a sweep):

============================  ===================  ==========================================
entity                        archetype            what
============================  ===================  ==========================================
``world/eef``                 Points3D             the end-effector
``world/eef_path``            LineStrips3D         its path so far
``world/objects/<name>``      Boxes3D              the object the skill acts on
``world/target``              Points3D             the commanded target (when one is known)
``world/robot/<link>``        Transform3D          the robot's link frames (PyBullet scenes)
``camera``                    Image                a camera image (when asked)
``bins/<variable>``           Scalars              the context's bin of every variable
``movement``                  TextLog              the chosen movement and the step status
``movement_index``            Scalars              its index in the repertoire (-1: none)
``effect/<axis>``             Scalars              the object's displacement so far (m), x, y
``plane/<name>[_path]``       Points2D/LineStrips  planar paths over time (``paths2d``)
============================  ===================  ==========================================

:func:`record_run` writes a finished :class:`a2l.rollout.run.SkillRun` (``a2l skill run
--record``) with the :func:`scene_frame` taken before each step; the bins are the runtime's
(:func:`a2l._core.context_bins`, the C++ bin math).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l import _core
from a2l.errors import A2LValueError

__all__ = ["RerunRecorder", "context_variables", "read_recording", "record_rollouts",
           "record_run", "record_trajectories", "scene_frame", "step_bins"]

#: Half extents of an object whose size the recording does not know (m).
DEFAULT_HALF = (0.035, 0.0425, 0.04)


class RerunRecorder:
    """A Rerun recording written to `path` (``.rrd``) while it is logged.

    Parameters
    ----------
    path : str or PathLike
        The ``.rrd`` file (its directory must exist).
    name : str
        The application id shown by the viewer.
    """

    def __init__(self, path: str | os.PathLike[str], name: str = "a2l") -> None:
        import rerun as rr

        self.path = Path(path)
        if self.path.suffix != ".rrd":
            raise A2LValueError(f"recording '{self.path}': a Rerun recording ends in .rrd")
        if not self.path.resolve().parent.is_dir():
            raise A2LValueError(f"recording '{self.path}': its directory does not exist")
        self.rr = rr
        self.rec = rr.RecordingStream(name)
        self.tmp = self.path.with_name(f".{self.path.name}.tmp")
        self.rec.save(self.tmp)
        self.prefix = "rollout/0"
        self.path_points: list[list[float]] = []
        self.start: NDArray[np.float64] | None = None

    def rollout(self, index: int, group: str = "") -> None:
        """Log what follows as rollout `index` (a new path, a new effect origin), under
        ``<group>/rollout/<index>/`` when a `group` is given (a recording of several runs:
        a sweep's seeds, a study's cells, an experiment's skills)."""
        self.prefix = f"{group.strip('/')}/rollout/{int(index)}" if group.strip("/") \
            else f"rollout/{int(index)}"
        self.path_points, self.start = [], None

    def time(self, step: int, seconds: float | None = None) -> None:
        """Set the timelines: ``step`` (sequence) and ``time`` (seconds since the start)."""
        self.rec.set_time("step", sequence=int(step))
        if seconds is not None:
            self.rec.set_time("time", duration=float(seconds))

    def step(self, step: int, eef: ArrayLike, obj: ArrayLike, *, seconds: float | None = None,
             label: str = "", movement: int = -1, status: str = "ok",
             bins: Mapping[str, int] | None = None, target: ArrayLike | None = None,
             object_name: str = "object", half_extents: Sequence[float] = DEFAULT_HALF,
             others: Mapping[str, ArrayLike] | None = None) -> None:
        """Log one step: end-effector and object (3,) (NaN: not seen), the movement chosen
        (its label and index), the step status, the context bins, the target (3,) and
        other objects (name -> (3,), boxes without an effect of their own)."""
        rr, rec, pre = self.rr, self.rec, self.prefix
        self.time(step, seconds)
        e = np.asarray(eef, dtype=float).reshape(3)
        o = np.asarray(obj, dtype=float).reshape(3)
        rec.log(f"{pre}/world/eef", rr.Points3D([e], radii=0.01, colors=[(230, 120, 20)]))
        self.path_points.append(e.tolist())
        if len(self.path_points) > 1:
            rec.log(f"{pre}/world/eef_path", rr.LineStrips3D([self.path_points]))
        if np.all(np.isfinite(o)):
            rec.log(f"{pre}/world/objects/{object_name}",
                    rr.Boxes3D(centers=[o], half_sizes=[list(half_extents)],
                               labels=[object_name], colors=[(150, 40, 220)]))
            if self.start is None:
                self.start = o.copy()
            moved = o - self.start
            for axis, v in zip("xy", moved[:2], strict=True):
                rec.log(f"{pre}/effect/{axis}", rr.Scalars([float(v)]))
        for name, pos in (others or {}).items():
            p = np.asarray(pos, dtype=float).reshape(3)
            if np.all(np.isfinite(p)):
                rec.log(f"{pre}/world/objects/{name}",
                        rr.Boxes3D(centers=[p], half_sizes=[list(half_extents)],
                                   labels=[name], colors=[(40, 160, 90)]))
        if target is not None:
            rec.log(f"{pre}/world/target", rr.Points3D([np.asarray(target, dtype=float)],
                                                       radii=0.006, colors=[(20, 160, 60)]))
        for name, b in (bins or {}).items():
            rec.log(f"{pre}/bins/{name}", rr.Scalars([float(b)]))
        rec.log(f"{pre}/movement", rr.TextLog(f"{status}: {label or '-'}",
                                              level="INFO" if status == "ok" else "WARN"))
        rec.log(f"{pre}/movement_index", rr.Scalars([float(movement)]))

    def paths2d(self, paths: Mapping[str, ArrayLike], duration: float, samples: int = 100,
                target: ArrayLike | None = None) -> None:
        """Planar paths traced over time, under ``<rollout>/plane/<name>``: each path
        (name -> (T, 2)) resampled to at most `samples` points spread over `duration` (s),
        its point now (Points2D) and its path so far (LineStrips2D) at every sample
        (timelines ``step`` and ``time``); `target` (2,) a point of its own, ``plane/target``
        (e.g. a demonstration and the DS integrated from its start)."""
        rr, rec, pre = self.rr, self.rec, self.prefix
        colors = [(40, 110, 220), (230, 120, 20), (40, 160, 90), (150, 40, 220)]
        arrays = {n: np.asarray(p, dtype=float).reshape(-1, 2) for n, p in paths.items()}
        n_max = max(len(a) for a in arrays.values())
        keep = np.unique(np.linspace(0, n_max - 1, min(samples, n_max)).round().astype(int))
        for k in keep:
            self.time(int(k), duration * k / max(n_max - 1, 1))
            if target is not None and k == keep[0]:
                rec.log(f"{pre}/plane/target", rr.Points2D([np.asarray(target, dtype=float)],
                                                           radii=1.0, colors=[(0, 0, 0)]))
            for j, (name, a) in enumerate(arrays.items()):
                upto = a[:min(int(k), len(a) - 1) + 1]
                color = colors[j % len(colors)]
                rec.log(f"{pre}/plane/{name}", rr.Points2D([upto[-1]], radii=0.8,
                                                           colors=[color]))
                if len(upto) > 1:
                    rec.log(f"{pre}/plane/{name}_path", rr.LineStrips2D([upto],
                                                                        colors=[color]))

    def note(self, text: str) -> None:
        """A line of text about the current rollout (what it wanted, how it ended)."""
        self.rec.log(f"{self.prefix}/summary", self.rr.TextLog(text))

    def links(self, poses: Mapping[str, tuple[ArrayLike, ArrayLike]]) -> None:
        """The robot's link frames: ``{name: (position (3,), quaternion (4,) x, y, z, w)}``."""
        for name, (pos, quat) in poses.items():
            self.rec.log(f"{self.prefix}/world/robot/{name}", self.rr.Transform3D(
                translation=np.asarray(pos, dtype=float),
                quaternion=self.rr.Quaternion(xyzw=np.asarray(quat, dtype=float))))

    def image(self, rgb: NDArray[np.uint8]) -> None:
        """A camera image (H, W, 3)."""
        self.rec.log(f"{self.prefix}/camera", self.rr.Image(np.asarray(rgb, dtype=np.uint8)))

    def close(self) -> Path:
        """Finish the file (written to a temporary file, then renamed); its path."""
        self.rec.flush()
        self.rec.disconnect()
        os.replace(self.tmp, self.path)
        return self.path


def scene_frame(scene: Any, image: bool = True) -> dict[str, Any]:
    """What a recording shows of `scene` now (a frame of :func:`record_run`): the link
    frames and a camera image (PyBullet scenes), the simulated time; keys missing where the
    scene has none."""
    out: dict[str, Any] = {}
    if hasattr(scene, "link_poses"):
        out["links"] = scene.link_poses()
    if image and hasattr(scene, "render"):
        out["image"] = scene.render()[0]
    if hasattr(scene, "sim_time"):
        out["t"] = float(scene.sim_time)
    return out


def context_variables(skill: Any) -> list[tuple[str, tuple[Any, ...]]]:
    """The context variables of a loaded :class:`a2l._core.Skill`: ``(name, (kind, n_bins,
    low, high))``, or ``(name, (kind, n_bins, low, high, edges))`` for a distance with
    explicit edges, as :func:`a2l._core.context_bins` takes them."""
    out: list[tuple[str, tuple[Any, ...]]] = []
    for v in skill.variables:
        kind = v.kind.name
        if kind in ("effect", "high_level"):
            continue
        low = float(v.low) if v.low is not None else 0.0
        high = float(v.high) if v.high is not None else 0.0
        edges = tuple(float(x) for x in getattr(v, "edges", ()))
        core = (kind, int(v.n_bins), low, high) + ((edges,) if edges else ())
        out.append((str(v.name), core))
    return out


def step_bins(skill: Any, eef: ArrayLike, obj: ArrayLike) -> list[dict[str, int]]:
    """The context bins of every step, ``eef`` and ``obj`` of shape (T, 3): one dict per
    step, by variable name (-1: unknown context)."""
    variables = context_variables(skill)
    e = np.atleast_2d(np.asarray(eef, dtype=float))
    o = np.atleast_2d(np.asarray(obj, dtype=float))
    if not variables or len(e) == 0:
        return [{} for _ in range(len(e))]
    bins = np.asarray(_core.context_bins(e, o, [v for _, v in variables])).reshape(len(e), -1)
    return [{n: int(b) for (n, _), b in zip(variables, row, strict=True)} for row in bins]


def record_run(recorder: RerunRecorder, run: Any, skill: Any, object_name: str = "object",
               frames: Sequence[Mapping[str, Any]] | None = None, rollout: int = 0,
               group: str = "") -> None:
    """Log a finished run (:class:`a2l.rollout.run.SkillRun`) as rollout `rollout`.

    Parameters
    ----------
    recorder : RerunRecorder
    run : SkillRun
    skill : a2l._core.Skill
        The bundle's skill (its context variables give the bins).
    object_name : str
    frames : sequence of dict, optional
        Per step (before it), what the scene looked like: ``{"links": {...}, "image": rgb,
        "t": seconds}``; any key may be missing.
    rollout : int
    group : str
        The entity path the rollout goes under (:meth:`RerunRecorder.rollout`).
    """
    recorder.rollout(rollout, group)
    bins = step_bins(skill, run.eef, run.obj)
    for k, st in enumerate(run.steps):
        frame = frames[k] if frames is not None and k < len(frames) else {}
        recorder.step(k, st.eef, st.obj, seconds=frame.get("t"), label=st.label,
                      movement=st.movement, status=st.status if st.status != "ok"
                      else (st.move_status or "ok"), bins=bins[k] if k < len(bins) else None,
                      target=st.eef + st.displacement if st.status == "ok" else None,
                      object_name=object_name)
        if frame.get("links"):
            recorder.links(frame["links"])
        if frame.get("image") is not None:
            recorder.image(frame["image"])


def record_rollouts(recorder: RerunRecorder, rollouts: Sequence[Any], skill: Any,
                    group: str = "") -> int:
    """Log trajectories of the framework (:class:`a2l.acquisition.interactions.Rollout`, or the
    rows of the validation table: ``eef`` and ``obj`` (T + 1, 3) or flattened, ``moves``
    (T,), ``start``, ``wanted``, ``outcome``, ``stop``), one rollout each (``a2l experiment
    push --record``), under `group` (:meth:`RerunRecorder.rollout`); the movement labels,
    effect names and bins are `skill`'s. Returns the number of rollouts."""
    labels = list(skill.movements.labels)
    effects = list(skill.effect_values)
    for i, ro in enumerate(rollouts):
        recorder.rollout(i, group)
        eef = np.asarray(ro.eef, dtype=float).reshape(-1, 3)
        obj = np.asarray(ro.obj, dtype=float).reshape(-1, 3)
        bins = step_bins(skill, eef, obj)
        n = len(ro.moves)
        for k in range(len(eef)):
            m = int(ro.moves[k]) if k < n else -1
            recorder.step(k, eef[k], obj[k], label=labels[m] if m >= 0 else "", movement=m,
                          status="ok" if k < n else (ro.outcome or ro.stop or "end"),
                          bins=bins[k], target=eef[k + 1] if k < n else None,
                          object_name="object")
        wanted = effects[ro.wanted] if 0 <= ro.wanted < len(effects) else "-"
        recorder.note(f"start {ro.start}, wanted {wanted}: {ro.outcome or '-'} ({ro.stop})")
    return len(rollouts)


def record_trajectories(recorder: RerunRecorder, trajectories: Mapping[str, tuple[ArrayLike,
                        ArrayLike]], notes: Mapping[str, str] | None = None,
                        object_name: str = "object", group: str = "",
                        labels: Mapping[str, Sequence[str]] | None = None,
                        others: Mapping[str, Mapping[str, ArrayLike]] | None = None) -> int:
    """Log finished trials known only by their paths, one rollout each, in the mapping's
    order (e.g. ``a2l experiment perturbations --record``).

    Parameters
    ----------
    recorder : RerunRecorder
    trajectories : mapping of str to (eef, obj)
        Per trial, the end-effector and object positions before each step and after the
        last, each of shape (T + 1, 3) (NaN where the object was not seen).
    notes : mapping of str to str, optional
        Per trial, a line about it (its name, how it ended); default its name.
    object_name : str
    group : str
        The entity path the rollouts go under (:meth:`RerunRecorder.rollout`).
    labels : mapping of str to sequence of str, optional
        Per trial, what was done at each step (T,) (e.g. the plan step), shown as the step's
        movement; default none.
    others : mapping of str to (mapping of str to array), optional
        Per trial, other objects' positions, name -> (T + 1, 3) (NaN: not seen).

    Returns
    -------
    int
        The number of rollouts logged.
    """
    for i, (name, (eef, obj)) in enumerate(trajectories.items()):
        recorder.rollout(i, group)
        e = np.asarray(eef, dtype=float).reshape(-1, 3)
        o = np.asarray(obj, dtype=float).reshape(-1, 3)
        done = list((labels or {}).get(name, ()))
        more = {n: np.asarray(p, dtype=float).reshape(-1, 3)
                for n, p in (others or {}).get(name, {}).items()}
        for k in range(len(e)):
            recorder.step(k, e[k], o[k], label=done[k] if k < len(done) else "",
                          others={n: p[k] for n, p in more.items()},
                          status="ok" if k + 1 < len(e) else "end",
                          target=e[k + 1] if k + 1 < len(e) else None,
                          object_name=object_name)
        recorder.note((notes or {}).get(name, name))
    return len(trajectories)


def read_recording(path: str | os.PathLike[str], index: str = "step") -> dict[str, list]:
    """Every column of a recording on timeline `index`, read back with Rerun's dataframe
    API (a local, in-process server: ``rerun-sdk[catalog]``), as Python lists by column
    name (``/rollout/0/effect/x:Scalars:scalars``...; None where a step logged nothing).

    Raises
    ------
    a2l.A2LValueError
        `path` is not a file.
    """
    import rerun as rr

    if not Path(path).is_file():
        raise A2LValueError(f"recording '{path}' is not a file")
    with rr.server.Server(host="127.0.0.1", datasets={"run": [str(path)]}) as srv:
        client = srv.client()  # kept alive while the query runs
        table = client.get_dataset("run").reader(index=index).to_arrow_table()
    return {name: table.column(name).to_pylist() for name in table.column_names}

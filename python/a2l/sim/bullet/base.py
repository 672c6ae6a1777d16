"""The base of the PyBullet scenes: connecting, resetting an episode, the objects and what
the cameras see."""

from __future__ import annotations

import os
import sys
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l.errors import A2LError, A2LValueError
from a2l.sim._pybullet import p
from a2l.sim.bodies import BodyCache
from a2l.sim.bullet.build import PARK, BuildMixin, SceneObject
from a2l.sim.bullet.motion import MotionMixin
from a2l.sim.bullet.transit import TransitMixin
from a2l.sim.observation import Observation
from a2l.sim.perception import Camera, ColorTarget, Perception
from a2l.sim.scene import Scene
from a2l.sim.scene_config import SceneConfig
from a2l.sim.tracking import Footprint, Sighting

__all__ = ["BulletScene"]


class BulletScene(MotionMixin, TransitMixin, BuildMixin, Scene):
    """A PyBullet scene; subclasses add the objects. Use :func:`a2l.sim.make_scene`."""

    config: SceneConfig

    def __init__(self, config: SceneConfig, seed: int = 0) -> None:
        super().__init__(config, seed)
        self._client = -1
        cfg = config
        if cfg.gui and sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
            # PyBullet would print "cannot connect to X server" and end the process
            raise A2LError("gui=True needs a display (DISPLAY is not set); run without the "
                           "GUI or under xvfb-run")
        self._client = p.connect(p.GUI if cfg.gui else p.DIRECT)
        if self._client < 0:
            raise A2LError("cannot connect to PyBullet" + (" in GUI mode: is there a display?"
                                                           if cfg.gui else ""))
        c = self._client
        if cfg.gui:
            p.configureDebugVisualizer(p.COV_ENABLE_GUI, 0, physicsClientId=c)
            p.resetDebugVisualizerCamera(1.6, 120, -25, (0.65, -0.15, -0.15), physicsClientId=c)
        p.setGravity(0, 0, -9.81, physicsClientId=c)
        p.setTimeStep(cfg.time_step, physicsClientId=c)
        # Contacts solved in an order that does not depend on the world's history (with the
        # objects rebuilt at every reset, see a2l.sim.bodies): same start, same rollout.
        p.setPhysicsEngineParameter(deterministicOverlappingPairs=1, physicsClientId=c)
        self._tick = 0
        self._perceived_cache: tuple[int, Observation] | None = None
        #: What the cameras saw (each object's sighting, the lamp) in each world state met
        #: right after a reset, by that state (:meth:`_world_key`): see :meth:`_perceive`.
        self._start_views: dict[Any, tuple[dict[str, Sighting], bool | None]] = {}
        #: Where each object was last seen well (a2l.sim.tracking), while it is hidden.
        self._footprints: dict[str, Footprint] = {}
        self._reset_tick = -1
        self._objects: dict[str, SceneObject] = {}
        self._states: dict[str, str] = cfg.initial_states()
        #: Every body but the robot, rebuilt at each reset (a2l.sim.bodies).
        self._bodies = BodyCache(c)
        self._build_world()
        self._build_robot()
        self._fit_tall_objects()
        self._build_objects()
        targets = [ColorTarget(o.name, o.rgba, o.size[2] / 2, o.size[0] * o.size[1])
                   for o in self._objects.values()]
        #: The cameras: the main one first, then the ones looked at when an object is
        #: hidden from it (see :meth:`perceive`).
        self.cameras = [Camera(c, cfg.camera_width, cfg.camera_height, eye,
                               cfg.camera_target, cfg.camera_fov)
                        for eye in (cfg.camera_eye, *cfg.extra_camera_eyes)]
        self.perceptions = [Perception(cam, targets, lamp_rgba=self._lamp_rgba())
                            for cam in self.cameras]
        self.camera = self.cameras[0]
        self.perception = self.perceptions[0]
        self.reset()

    # --- Scene interface ------------------------------------------------------------
    def reset(self, eef: ArrayLike | None = None,
              objects: dict[str, ArrayLike] | None = None) -> None:
        c, cfg = self._client, self.config
        # check the arguments before touching the world: a bad reset leaves it as it was
        q_arm = self._neutral_q.copy()
        if eef is not None:
            q_arm = self._ik_down(eef, "reset")
        placed = dict(objects or {})
        for name in placed:
            if name not in self._objects:
                raise A2LValueError(f"reset: unknown object '{name}'; this scene has "
                                    f"{sorted(self._objects)}")
        moves = []
        for o in self._objects.values():
            xy = np.asarray(placed.get(o.name, o.xy), dtype=float).reshape(2)
            if o.movable and cfg.object_jitter > 0:
                xy = xy + self._rng.uniform(-cfg.object_jitter, cfg.object_jitter, 2)
            if o.name in placed or (o.movable and cfg.object_jitter > 0):
                cfg.check_on_table(f"{o.name} position", (float(xy[0]), float(xy[1])),
                                   (o.size[0] / 2, o.size[1] / 2))
                moves.append((o, xy))
        # New bodies but the robot: no contact or pair cache survives from earlier episodes
        # (restoreState would not clear them, a2l.sim.bodies); the robot's joints are all
        # reset below, its base is fixed.
        ids = self._bodies.rebuild()
        for o in self._objects.values():
            o.body = ids[o.name]
        self._removed = set()
        self._hold = 0
        self._states = cfg.initial_states()
        self._set_arm_targets(q_arm)
        self._set_fingers(self._states["gripper"] == "closed")
        for j, v in self._targets.items():
            p.resetJointState(self._robot, j, v, 0.0, physicsClientId=c)
        self._command()
        for o, xy in moves:
            self._place_base(o, xy)
        self._reset_extra()
        self._tick += 1
        self._perceived_cache = None
        self._footprints.clear()
        self._reset_tick = self._tick
        self._episode_start = self._snapshot()
        self._step_start = self._episode_start

    def _place_base(self, o: SceneObject, xy: NDArray[np.float64]) -> None:
        pos, orn = p.getBasePositionAndOrientation(o.body, physicsClientId=self._client)
        if o.link == -1:
            z = self.config.table_z + o.size[2] / 2
        else:
            z = pos[2]
        self._teleport(o.body, (float(xy[0]), float(xy[1]), z),
                       orn if o.link != -1 else (0, 0, 0, 1))

    def _teleport(self, body: int, pos: Any, orn: Any) -> None:
        c = self._client
        p.resetBasePositionAndOrientation(body, pos, orn, physicsClientId=c)
        p.resetBaseVelocity(body, (0, 0, 0), (0, 0, 0), physicsClientId=c)

    def _reset_extra(self) -> None:
        """Scene-specific reset (light, button)."""

    def _object_names(self) -> list[str]:
        return list(self._objects)

    def _object_position(self, o: SceneObject) -> tuple[float, float, float]:
        c = self._client
        if o.link == -1:
            pos = p.getBasePositionAndOrientation(o.body, physicsClientId=c)[0]
        else:
            pos = p.getLinkState(o.body, o.link, computeForwardKinematics=True,
                                 physicsClientId=c)[4]
        return (float(pos[0]), float(pos[1]), float(pos[2]))

    def _ground_truth(self) -> Observation:
        objs = {n: self._object_position(o) for n, o in self._objects.items()
                if n not in self._removed}
        return Observation(objs, dict(self._states), self.eef_position(),
                           self._states["gripper"] == "closed")

    #: Most world states whose views :meth:`_perceive` keeps (then it starts over).
    START_VIEWS = 1024

    def _world_key(self) -> tuple[Any, ...]:
        """Everything the cameras' frames depend on: every body's pose and joint
        positions, and the high-level states (the lamp's colour follows ``light``)."""
        c = self._client
        bodies = []
        for i in range(p.getNumBodies(physicsClientId=c)):
            b = p.getBodyUniqueId(i, physicsClientId=c)
            n = p.getNumJoints(b, physicsClientId=c)
            q = tuple(js[0] for js in p.getJointStates(b, range(n), physicsClientId=c)) \
                if n else ()
            bodies.append((b, p.getBasePositionAndOrientation(b, physicsClientId=c), q))
        return tuple(bodies), tuple(sorted(self._states.items()))

    def _perceive(self) -> Observation:
        if self._perceived_cache is not None and self._perceived_cache[0] == self._tick:
            return self._perceived_cache[1]
        # Right after a reset the world is often in a state met before (an experiment's
        # rollouts start from a few start positions, the object at home): the same bodies
        # at the same poses give the same frames to the bit, so what the cameras saw then
        # is reused instead of rendered again (a tenth of a rollout's frames).
        key = self._world_key() if self._reset_tick == self._tick else None
        seen = self._start_views.get(key) if key is not None else None
        if seen is None:
            seen = self._look()
            if key is not None:
                if len(self._start_views) >= self.START_VIEWS:
                    self._start_views.clear()
                self._start_views[key] = seen
        sightings, lit = seen
        objs = self._follow(sightings)
        states = dict(self._states)
        if lit is not None:
            states["light"] = "on" if lit else "off"
        obs = Observation(dict(objs), states, self.eef_position(),
                          self._states["gripper"] == "closed")
        self._perceived_cache = (self._tick, obs)
        return obs

    def _look(self) -> tuple[dict[str, Sighting], bool | None]:
        """Render the cameras and locate the objects: what they saw of each object, and
        whether the lamp is lit (None without a lamp)."""
        # every view's top-face points of an object, joined: a face the arm hides in part
        # from one camera is completed by the others (the smallest rectangle around the
        # union, where the best single view's clipped rectangle was off by up to 1 cm). A
        # view that sees only the object's sides (the arm hides its top from that camera)
        # is left out of the join while another sees the top: its points would make the
        # joined face not flat, and the object never well seen.
        tops: dict[str, list[NDArray[np.float64]]] = {}
        sides: dict[str, list[NDArray[np.float64]]] = {}
        points: dict[str, list[NDArray[np.float64]]] = {}
        best: dict[str, tuple[tuple[float, float, float], float, NDArray[np.float64]]] = {}
        lit: bool | None = None
        for perception in self.perceptions:
            seen, lamp = perception.segment(*perception.camera.render())
            for name, pts in seen.items():
                face = perception.top_face(pts)
                (tops if perception.is_flat(face) else sides).setdefault(name, []).append(face)
                points.setdefault(name, []).append(pts)
                faces = tops.get(name) or sides[name]
                top = faces[0] if len(faces) == 1 else np.vstack(faces)
                best[name] = (*perception.estimate(name, top), top)
            if "light_on" in lamp:
                lit = bool(lit) or lamp["light_on"]
            if len(best) == len(perception.targets) and all(
                    share >= self.config.min_visible for _, share, _ in best.values()):
                break  # every object well seen: no need for another view
        return {name: Sighting(pos, share, top, np.vstack(points[name]),
                               self.perception.is_flat(top))
                for name, (pos, share, top) in best.items()}, lit

    def _follow(self, sightings: dict[str, Sighting]) -> dict[str, tuple[float, float, float]]:
        """Each object's position from what the cameras saw of it (``sightings``): its
        sighting's when well seen (its footprint then remembered), its footprint followed
        while the hand hides it, its footprint's when no camera sees it (module
        :mod:`a2l.sim.tracking`; ``track_hidden`` off: the sightings' positions only)."""
        if not self.config.track_hidden:
            return {name: s.position for name, s in sightings.items()}
        out: dict[str, tuple[float, float, float]] = {}
        for name, s in sightings.items():
            known = self._footprints.get(name)
            if s.well_seen(self.config.min_visible):
                self._footprints[name] = Footprint.of(s.top, s.position[2])
                out[name] = s.position
            elif known is None:
                out[name] = s.position
            else:
                self._footprints[name] = known.follow(s.points, s.position[2])
                out[name] = self._footprints[name].position
        for name, known in self._footprints.items():
            out.setdefault(name, known.position)
        return out

    def render(self, camera: int = 0) -> tuple[NDArray[np.uint8], NDArray[np.float32]]:
        """One frame of camera `camera` (0: the main one): RGB (H, W, 3) uint8 and the
        depth buffer (H, W) float32."""
        return self.cameras[camera].render()

    def _place(self, name: str, xyz: NDArray[np.float64]) -> None:
        o = self._objects[name]
        self.config.check_on_table("delta", (float(xyz[0]), float(xyz[1])),
                                   (o.size[0] / 2, o.size[1] / 2))
        c = self._client
        pos, orn = p.getBasePositionAndOrientation(o.body, physicsClientId=c)
        shift = np.asarray(xyz, dtype=float) - np.asarray(self._object_position(o))
        self._teleport(o.body, tuple(np.asarray(pos) + shift), orn)
        self._footprints.pop(name, None)
        self._tick += 1

    def _park(self, name: str) -> None:
        o = self._objects[name]
        c = self._client
        orn = p.getBasePositionAndOrientation(o.body, physicsClientId=c)[1]
        k = list(self._objects).index(name)
        z = self._floor_z + o.size[2] / 2 + 0.05
        self._teleport(o.body, (PARK[0], PARK[1] + 0.5 * k, z),
                       orn)
        self._footprints.pop(name, None)
        self._tick += 1

    def _toggle(self, state: str) -> None:
        if state == "gripper":
            closed = self._states["gripper"] != "closed"
            self._states["gripper"] = "closed" if closed else "open"
            self._set_fingers(closed)
            self._command()
        self._tick += 1

    def contacts(self, name: str) -> bool:
        """Whether object `name` touches one of the gripper's fingers (ground truth)."""
        o = self._objects[name]
        pts = p.getContactPoints(self._robot, o.body, physicsClientId=self._client)
        return any(pt[3] in self._finger_links for pt in pts)

    def close(self) -> None:
        if getattr(self, "_client", -1) >= 0:
            try:
                p.disconnect(physicsClientId=self._client)
            except p.error:
                pass
            self._client = -1

    @property
    def sim_time(self) -> float:
        """Simulated time (s): the scene's ticks (physics steps, and resets, placements and
        toggles, one each) times the physics time step."""
        return float(self._tick * self.config.time_step)

    @property
    def client(self) -> int:
        """The PyBullet physics client id of this scene."""
        return self._client


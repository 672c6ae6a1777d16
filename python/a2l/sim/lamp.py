"""The lamp: a sphere on the table showing the high-level state ``light`` ("off"/"on").

Shared by the PyBullet scenes that have a light (``press``: a button toggles it;
``grasp_light``: a "hot stove" next to the block). The camera reads the state from the
lamp's colour (:class:`a2l.sim.perception.Perception`, ``lamp_rgba``).
"""

from __future__ import annotations

from typing import Any

from a2l.sim._pybullet import p

__all__ = ["LAMP_OFF", "LAMP_ON", "LampMixin"]

#: Lamp colour when lit (saturated yellow: what perception looks for) and when not.
LAMP_ON = (1.0, 0.85, 0.05, 1.0)
LAMP_OFF = (0.22, 0.22, 0.22, 1.0)


class LampMixin:
    """Adds a lamp to a :class:`a2l.sim.bullet.BulletScene` (put it first in the bases).

    The scene's config has ``lamp_position`` (x, y) and ``lamp_radius``; its high-level
    states include ``light``. Call :meth:`_build_lamp` from ``_build_objects`` and
    :meth:`_show_light` from ``_reset_extra``.
    """

    _client: int
    _bodies: Any
    _states: dict[str, str]
    _tick: int
    config: Any

    def _lamp_rgba(self) -> tuple[float, float, float, float] | None:
        return LAMP_ON

    def _build_lamp(self) -> None:
        c, cfg = self._client, self.config
        lr = cfg.lamp_radius
        col = p.createCollisionShape(p.GEOM_SPHERE, radius=lr, physicsClientId=c)
        vis = p.createVisualShape(p.GEOM_SPHERE, radius=lr, rgbaColor=LAMP_OFF,
                                  physicsClientId=c)
        lx, ly = cfg.lamp_position
        self._bodies.add("lamp", baseMass=0, baseCollisionShapeIndex=col,
                         baseVisualShapeIndex=vis, basePosition=(lx, ly, cfg.table_z + lr))

    @property
    def _lamp(self) -> int:
        return int(self._bodies.ids["lamp"])

    def _show_light(self) -> None:
        p.changeVisualShape(self._lamp, -1,
                            rgbaColor=LAMP_ON if self._states["light"] == "on" else LAMP_OFF,
                            physicsClientId=self._client)

    def _flip_light(self) -> None:
        """Switch the light and show it."""
        self._states["light"] = "off" if self._states["light"] == "on" else "on"
        self._show_light()

    def _toggle(self, state: str) -> None:
        if state == "light":
            self._flip_light()
            self._tick += 1
            return
        super()._toggle(state)  # type: ignore[misc]

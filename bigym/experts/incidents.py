"""Mishaps that disqualify a demo even when the task ends in success.

A demo in which an object was dropped, or pushed into a surface, teaches the wrong thing
however the episode ends: the generator watches every step and rejects such demos.

* dropped: a free object falls faster than ``DROP_SPEED`` (a fall of about 3 cm from
  rest; an object let go just above where it rests never gets there), or than its own
  limit where the demonstrator lets it fall into place on purpose (a spoon let go into a
  mug: the fingers cannot follow it in);
* pushed through a surface: a contact of a free object penetrates deeper than
  ``MAX_PENETRATION`` (grasped objects stay under 1 mm).
"""

from __future__ import annotations

import numpy as np

DROP_SPEED = 0.75  # m/s downwards
MAX_PENETRATION = 0.006  # m


class IncidentWatch:
    """Watches the free objects of a task env step by step; :meth:`check` names the first mishap."""

    def __init__(self, env, drop_speeds: dict[str, float] | None = None) -> None:
        base = env.unwrapped
        self.env = base
        props = getattr(base, "_free_props", {})
        self.names = list(props)
        drop_speeds = drop_speeds or {}
        unknown = sorted(set(drop_speeds) - set(self.names))
        if unknown:
            raise ValueError(f"drop_speeds names {unknown}, not free objects of the task ({self.names})")
        self.drop_speeds = np.array([drop_speeds.get(name, DROP_SPEED) for name in self.names])
        self.bodies = np.array([props[name].root_body_id for name in self.names], dtype=np.int64)
        owner = np.full(base.model.ngeom, -1, dtype=np.int64)
        for index, name in enumerate(self.names):
            owner[np.isin(base.model.geom_bodyid, props[name].body_ids)] = index
        self.owner = owner
        self.reset()

    def reset(self) -> None:
        self._last_z: np.ndarray | None = None
        self._last_time = 0.0

    def check(self) -> str | None:
        """A description of the first mishap of this step, or None."""
        if not self.names:
            return None
        data = self.env.data
        z = data.xpos[self.bodies, 2]
        incident = None
        if self._last_z is not None and data.time > self._last_time:
            speed = (z - self._last_z) / (data.time - self._last_time)
            fastest = int(np.argmin(speed + self.drop_speeds))
            if speed[fastest] < -self.drop_speeds[fastest]:
                incident = f"{self.names[fastest]} dropped at t={data.time:.2f} s ({-speed[fastest]:.2f} m/s down)"
        self._last_z, self._last_time = z.copy(), float(data.time)
        if incident is None and data.ncon:
            contact = data.contact
            deep = np.flatnonzero(contact.dist[: data.ncon] < -MAX_PENETRATION)
            for index in deep:
                geoms = contact.geom[index]
                owners = [int(self.owner[g]) for g in geoms if self.owner[g] >= 0]
                if owners:
                    depth = -float(contact.dist[index]) * 1000
                    incident = f"{self.names[owners[0]]} pushed into a surface at t={data.time:.2f} s ({depth:.1f} mm)"
                    break
        return incident


__all__ = ["DROP_SPEED", "MAX_PENETRATION", "IncidentWatch"]

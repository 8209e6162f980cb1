"""Mishaps that disqualify a demo even when the task ends in success.

A demo in which an object was dropped, knocked over or pushed into a surface teaches the
wrong thing however the episode ends: the generator watches every step and rejects such
demos.

* dropped: a free object falls faster than ``DROP_SPEED`` (a fall of about 3 cm from
  rest; an object let go just above where it rests never gets there), or than its own
  limit where the demonstrator lets it fall into place on purpose (a spoon let go into a
  mug: the fingers cannot follow it in);
* knocked over: a free object that no hand holds tilts more than ``TIP_ANGLE`` away from
  how it stood when last held (or at the start): a cup an elbow pushes over, a box a
  finger tips onto its side. Held means gripped from two sides: both fingers of one
  gripper, or both grippers (a two-handed squeeze); a single finger only pushes. Objects
  the demonstrator tips on purpose without holding them (a sandwich turned over by the
  spatula, cutlery stood up and tipped over to lie flat in a tray, a spoon let fall into
  a mug, where it comes to lean against the rim) are exempt by name;
* pushed through a surface: a contact of a free object penetrates deeper than
  ``MAX_PENETRATION`` (grasped objects stay under 1 mm).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

DROP_SPEED = 0.75  # m/s downwards
#: a free object's tilt (rad) away from how it stood when last held: an upright object
#: knocked over lies at about 90 deg and a plate that falls over in a drainer leans on the
#: next holder at 43-48 deg, while one set down well settles within 30 deg of how it was
#: let go (the 50 shipped move_plate demos of dataset v2: 5-29 deg, or 43 deg and more)
TIP_ANGLE = np.radians(40.0)
MAX_PENETRATION = 0.006  # m

#: bits of the four fingers (left gripper: its two fingers, then the right gripper's)
_LEFT_GRIPPER, _RIGHT_GRIPPER = 0b0011, 0b1100


class IncidentWatch:
    """Watches the free objects of a task env step by step; :meth:`check` names the first mishap."""

    def __init__(
        self, env, drop_speeds: dict[str, float] | None = None, may_tip: Iterable[str] = ()
    ) -> None:
        base = env.unwrapped
        self.env = base
        props = getattr(base, "_free_props", {})
        self.names = list(props)
        drop_speeds = drop_speeds or {}
        may_tip = set(may_tip)
        for what, named in (("drop_speeds", drop_speeds), ("may_tip", may_tip)):
            unknown = sorted(set(named) - set(self.names))
            if unknown:
                raise ValueError(f"{what} names {unknown}, not free objects of the task ({self.names})")
        self.drop_speeds = np.array([drop_speeds.get(name, DROP_SPEED) for name in self.names])
        self.watch_tilt = np.array([name not in may_tip for name in self.names], dtype=bool)
        self.bodies = np.array([props[name].root_body_id for name in self.names], dtype=np.int64)
        owner = np.full(base.model.ngeom, -1, dtype=np.int64)
        for index, name in enumerate(self.names):
            owner[np.isin(base.model.geom_bodyid, props[name].body_ids)] = index
        self.owner = owner
        self.finger_bit = _finger_bits(base)
        self.reset()

    def reset(self) -> None:
        self._last_z: np.ndarray | None = None
        self._last_time = 0.0
        self._held_up: np.ndarray | None = None  # each object's world up, in its own frame, when last held
        #: the largest tilt (rad) of each object away from how it stood when last held
        self.peak_tilt = np.zeros(len(self.names))

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
        tipped = self._tilt()
        if incident is None and tipped is not None:
            degrees = np.degrees(self.peak_tilt[tipped])
            incident = f"{self.names[tipped]} knocked over at t={data.time:.2f} s (tilted {degrees:.0f} deg unheld)"
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

    def held(self) -> np.ndarray:
        """Which objects are gripped from two sides this step (see the module docstring)."""
        data = self.env.data
        fingers = np.zeros(len(self.names), dtype=np.int64)
        if data.ncon:
            contact = data.contact
            geoms = contact.geom[: data.ncon][contact.dist[: data.ncon] <= 0.0]
            owners, bits = self.owner[geoms], self.finger_bit[geoms]
            for mine, other in ((0, 1), (1, 0)):
                pinch = (owners[:, mine] >= 0) & (bits[:, other] > 0)
                np.bitwise_or.at(fingers, owners[pinch, mine], bits[pinch, other])
        one_gripper = ((fingers & _LEFT_GRIPPER) == _LEFT_GRIPPER) | ((fingers & _RIGHT_GRIPPER) == _RIGHT_GRIPPER)
        both_grippers = ((fingers & _LEFT_GRIPPER) > 0) & ((fingers & _RIGHT_GRIPPER) > 0)
        return one_gripper | both_grippers

    def _tilt(self) -> int | None:
        """Track each object's tilt since it was last held; the index of one knocked over, or None."""
        up = self.env.data.xmat[self.bodies, 6:9]  # world z in each object's frame
        if self._held_up is None:
            self._held_up = up.copy()
        held = self.held()
        self._held_up[held] = up[held]
        tilt = np.arccos(np.clip(np.einsum("ij,ij->i", up, self._held_up), -1.0, 1.0))
        np.maximum(self.peak_tilt, tilt, out=self.peak_tilt)
        over = np.flatnonzero(self.watch_tilt & (tilt > TIP_ANGLE))
        return int(over[0]) if over.size else None


def _finger_bits(env) -> np.ndarray:
    """Each geom's finger bit (0 for geoms of no finger): the grippers' finger links and pads."""
    model = env.model
    bits = np.zeros(model.ngeom, dtype=np.int64)
    for side_index, geom_ids in enumerate(env.robot.gripper_geom_ids_by_side):
        for geom in geom_ids:
            link = model.body(model.geom_bodyid[geom]).name.split("/", 1)[1]
            for finger_index, finger in enumerate(("left_", "right_")):
                if link.startswith(finger):
                    bits[geom] = 1 << (2 * side_index + finger_index)
    return bits


__all__ = ["DROP_SPEED", "MAX_PENETRATION", "TIP_ANGLE", "IncidentWatch"]

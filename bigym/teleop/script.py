"""Recorded input: a session's raw device events, saved and played back exactly.

A script is a JSON-lines file: a header line, then one line per raw event with the
session step it arrived at::

    {"bigym_teleop_script": 1, "task": "ReachTargetSingle", "seed": 3, "devices": ["keyboard"], "task_kwargs": {}}
    {"step": 0, "event": {"type": "keydown", "code": "KeyW"}}
    {"step": 400, "event": {"type": "keyup", "code": "KeyW"}}

Played back into a new session with the same task, first seed and devices, it gives
the same robot motion, the same demos and the same outcomes: teleoperation can be
tested headless, and a person's session reproduced.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

from bigym.demonstrations.atomic import atomic_write

FORMAT = 1


@dataclass
class InputScript:
    """Raw device events with the session step each arrived at."""

    task: str
    seed: int
    devices: list[str]
    events: list[tuple[int, dict]] = field(default_factory=list)
    task_kwargs: dict = field(default_factory=dict)

    @classmethod
    def from_session(cls, session) -> InputScript:
        """What a :class:`~bigym.teleop.session.TeleopSession` has received so far."""
        return cls(session.task, session.first_seed, [d.name for d in session.devices],
                   list(session.input_log), dict(session.task_kwargs))  # fmt: skip

    @property
    def steps(self) -> int:
        """The step of the last event."""
        return self.events[-1][0] if self.events else 0

    def save(self, path: Path | str) -> Path:
        header = {"bigym_teleop_script": FORMAT, "task": self.task, "seed": self.seed,
                  "devices": self.devices, "task_kwargs": self.task_kwargs}  # fmt: skip
        lines = [json.dumps(header)] + [json.dumps({"step": step, "event": event}) for step, event in self.events]
        return atomic_write(Path(path), ("\n".join(lines) + "\n").encode())

    @classmethod
    def load(cls, path: Path | str) -> InputScript:
        path = Path(path)
        lines = [line for line in path.read_text().splitlines() if line.strip()]
        try:
            header = json.loads(lines[0]) if lines else {}
        except json.JSONDecodeError as error:
            raise ValueError(f"{path} is not a bigym teleop script: {error}") from None
        if header.get("bigym_teleop_script") != FORMAT:
            raise ValueError(f"{path} is not a bigym teleop script (format {FORMAT}): its first line is {lines[:1]}")
        events = []
        last = 0
        for number, line in enumerate(lines[1:], start=2):
            try:
                record = json.loads(line)
                step, event = int(record["step"]), record["event"]
            except (json.JSONDecodeError, KeyError, TypeError, ValueError):
                raise ValueError(f"{path}:{number}: expected {{'step': int, 'event': {{...}}}}, got {line!r}") from None
            if step < last:
                raise ValueError(f"{path}:{number}: step {step} comes after step {last}")
            last = step
            events.append((step, event))
        return cls(str(header["task"]), int(header["seed"]), list(header["devices"]), events,
                   dict(header.get("task_kwargs") or {}))  # fmt: skip


def play(script: InputScript, session, extra_steps: int = 0) -> list:
    """Feed ``script``'s events into ``session`` at their steps, then run ``extra_steps``
    more; returns the outcomes of the episodes that ended."""
    outcomes = []
    for step, event in script.events:
        outcomes += session.advance(step - session.total_steps)
        session.handle(event)
    outcomes += session.advance(extra_steps)
    return outcomes


__all__ = ["InputScript", "play"]

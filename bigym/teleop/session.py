"""A recording session: a person drives the robot through devices, demos land in the store.

:class:`TeleopSession` owns the env (the benchmark's action mode at 500 Hz, the rate of
every shipped demo), a :class:`DemoRecorder` marking demos ``source="human"``, the
:class:`TeleopController` and the devices. Front ends (a window, a browser page, a
script) feed it raw device events (:meth:`handle`) and advance it (:meth:`step`); it
does the rest:

* success is shown live (:attr:`status`); 1 s after the first success (the margin every
  shipped demo has, for replays at lower rates) the demo is kept automatically, or
  whenever the person asks (keep), and a new scene starts;
* *keep* verifies the demo exactly as generated demos are verified: replayed from its
  file's bytes at 500 Hz (bit for bit) and at 50, 25 and 20 Hz (within tolerance), it
  must succeed every time. A verified demo goes into the store; one that fails is put
  aside (a folder beside the store, with the reason), never mixed into the verified set;
* *discard* drops the recording and starts a new scene; *retry* starts the same scene again;
* an episode that runs into the time limit without success is dropped and said so.

Every raw event is logged with the step it arrived at, so a session's input can be saved
and played back exactly (:mod:`bigym.teleop.script`).
"""

from __future__ import annotations

import json
import secrets
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from bigym.action_modes import JointPositionActionMode
from bigym.demonstrations.atomic import atomic_write
from bigym.demonstrations.player import VERIFY_RATES, resolve_task, verification_failure
from bigym.demonstrations.recorder import DemoRecorder
from bigym.demonstrations.store import DemoStore, demonstrations_home
from bigym.teleop.command import SESSION_EVENTS, TeleopCommand
from bigym.teleop.controller import TeleopController
from bigym.teleop.devices import Device, DeviceEventError

#: the recording rate of human demos: that of every shipped demo
CONTROL_FREQUENCY = 500.0
#: seconds recorded after the first success before a demo is kept automatically
AFTER_SUCCESS = 1.0


@dataclass
class Outcome:
    """What became of one episode."""

    kind: str  # "kept", "rejected" (failed verification, put aside) or "dropped"
    seed: int
    steps: int
    reason: str | None = None
    path: str | None = None  # the demo file (kept: in the store; rejected: aside)
    uuid: str | None = None

    def describe(self) -> str:
        seconds = self.steps / CONTROL_FREQUENCY
        text = {"kept": "kept", "rejected": "put aside", "dropped": "dropped"}[self.kind]
        line = f"seed {self.seed}: {text} after {seconds:.1f} s"
        return line + (f" ({self.reason})" if self.reason else "")


@dataclass
class SessionStatus:
    """What a front end shows."""

    task: str
    seed: int
    time: float
    success: bool
    kept: int
    rejected: int
    dropped: int
    message: str
    active_hands: list[str] = field(default_factory=list)
    grippers: list[float] = field(default_factory=list)

    def to_dict(self) -> dict:
        return dict(self.__dict__)


class TeleopSession:
    """Record human demos of ``task`` from ``devices`` into ``store``."""

    def __init__(
        self,
        task: str,
        devices: Sequence[Device],
        store: DemoStore | None = None,
        *,
        seed: int | None = None,
        task_kwargs: dict | None = None,
        aside: Path | str | None = None,
        auto_keep: bool = True,
        verify_rates: Sequence[float] = VERIFY_RATES,
        render_mode: str | None = None,
    ) -> None:
        if not devices:
            raise ValueError("a session needs at least one input device")
        self.task_kwargs = dict(task_kwargs or {})
        cls = resolve_task(task)
        self.env = cls(
            action_mode=JointPositionActionMode(floating_base=True, absolute=True),
            control_frequency=CONTROL_FREQUENCY,
            render_mode=render_mode,
            **self.task_kwargs,
        )
        self.task = self.env.task_name
        self.recorder = DemoRecorder(self.env, source="human", task_kwargs=self.task_kwargs)
        self.controller = TeleopController(self.env)
        self.devices = list(devices)
        self._by_type: dict[str, Device] = {}
        for device in self.devices:
            for kind in device.event_types:
                if kind in self._by_type:
                    raise ValueError(f"devices {self._by_type[kind].name} and {device.name} both read {kind!r} events")
                self._by_type[kind] = device
        self.store = store if store is not None else DemoStore()
        self.aside = Path(aside) if aside is not None else demonstrations_home() / "rejected"
        self.auto_keep = auto_keep
        self.verify_rates = tuple(verify_rates)
        self.outcomes: list[Outcome] = []
        #: every raw event so far: (session step, event)
        self.input_log: list[tuple[int, dict]] = []
        self.total_steps = 0
        self.message = "move the robot; the demo is kept 1 s after success"
        self.first_seed = int(seed) if seed is not None else secrets.randbits(31)
        self._pending: list[str] = []
        self._start(self.first_seed)

    # ------------------------------------------------------------------ episodes
    def _start(self, seed: int) -> None:
        self.seed = int(seed)
        self.obs, _ = self.recorder.reset(seed=self.seed)
        self.controller.reset()
        for device in self.devices:
            device.reset()
        self._after: int | None = None
        self.success = False

    def _next_episode(self, outcome: Outcome, same_scene: bool = False) -> Outcome:
        self.outcomes.append(outcome)
        self.message = outcome.describe()
        self._start(self.seed if same_scene else self.seed + 1)
        return outcome

    def keep(self) -> Outcome:
        """Verify the recording; into the store if it passes, aside with the reason if not."""
        steps = self.recorder.num_steps
        if steps == 0:
            return self._next_episode(Outcome("dropped", self.seed, 0, "nothing recorded"), same_scene=True)
        demo = self.recorder.to_demo(teleop_devices=[d.name for d in self.devices])
        reason = verification_failure(demo, self.verify_rates)
        if reason is None:
            entry = self.store.add(demo)
            return self._next_episode(Outcome("kept", self.seed, steps, None, entry.path, demo.metadata.uuid))
        folder = self.aside / self.task
        path = demo.save(folder)
        record = {"uuid": demo.metadata.uuid, "task": self.task, "seed": self.seed, "reason": reason}
        atomic_write(folder / f"{demo.metadata.uuid}.json", json.dumps(record, indent=1).encode())
        return self._next_episode(Outcome("rejected", self.seed, steps, reason, str(path), demo.metadata.uuid))

    def discard(self, reason: str = "discarded") -> Outcome:
        """Drop the recording; a new scene starts."""
        steps = self.recorder.num_steps
        self.recorder.discard()
        return self._next_episode(Outcome("dropped", self.seed, steps, reason))

    def retry(self) -> Outcome:
        """Drop the recording and start the same scene again."""
        steps = self.recorder.num_steps
        self.recorder.discard()
        return self._next_episode(Outcome("dropped", self.seed, steps, "retry"), same_scene=True)

    # ------------------------------------------------------------------ input
    def handle(self, event: dict) -> None:
        """A raw event from a device, or ``{"type": "session", "action": "keep"}`` (or
        discard, retry) from a front end's buttons. Applied from the next step on."""
        kind = event.get("type") if isinstance(event, dict) else None
        if kind == "session":
            action = event.get("action")
            if action not in SESSION_EVENTS:
                raise DeviceEventError(f"session event: 'action' must be one of {SESSION_EVENTS}, got {action!r}")
            self._pending.append(action)
        elif kind in self._by_type:
            self._by_type[kind].handle(event)
        else:
            known = ", ".join(["session", *self._by_type])
            raise DeviceEventError(f"no device of this session reads {kind!r} events (it reads {known})")
        self.input_log.append((self.total_steps, event))

    # ------------------------------------------------------------------ time
    def step(self) -> Outcome | None:
        """One control step (1/500 s). Returns the episode's outcome when one ended."""
        command = TeleopCommand.combine([d.command(1.0 / CONTROL_FREQUENCY) for d in self.devices])
        events = [*self._pending, *command.events]
        self._pending.clear()
        self.total_steps += 1
        for name in events:  # the first one decides; the rest belonged to the old scene
            return {"keep": self.keep, "discard": self.discard, "retry": self.retry}[name]()
        self.obs, _, _, truncated, info = self.recorder.step(self.controller(command))
        if "unstable" in info:
            return self.discard(f"unstable physics: {info['unstable']}")
        if info.get("is_success") and not self.success:
            self.success = True
            self.message = "success! keeping the demo in 1 s" if self.auto_keep else "success! press keep"
        if self.recorder.first_success_step is not None:
            self._after = round(AFTER_SUCCESS * CONTROL_FREQUENCY) if self._after is None else self._after - 1
            if self.auto_keep and (self._after <= 0 or truncated):
                return self.keep()
        if truncated:
            if self.recorder.first_success_step is not None:
                return self.keep()
            return self.discard("time limit: no success")
        return None

    def advance(self, steps: int) -> list[Outcome]:
        """Several control steps; the outcomes of the episodes that ended."""
        outcomes = []
        for _ in range(steps):
            outcome = self.step()
            if outcome is not None:
                outcomes.append(outcome)
        return outcomes

    # ------------------------------------------------------------------ display
    @property
    def time(self) -> float:
        return self.recorder.num_steps / CONTROL_FREQUENCY

    @property
    def status(self) -> SessionStatus:
        counts = {kind: sum(o.kind == kind for o in self.outcomes) for kind in ("kept", "rejected", "dropped")}
        active = sorted({side for d in self.devices for side in d.active})
        return SessionStatus(
            self.task, self.seed, round(self.time, 3), self.success, counts["kept"], counts["rejected"],
            counts["dropped"], self.message, [("left", "right")[s] for s in active],
            [round(float(g), 3) for g in self.controller.grip],
        )  # fmt: skip

    def close(self) -> None:
        self.env.close()


__all__ = ["AFTER_SUCCESS", "CONTROL_FREQUENCY", "Outcome", "SessionStatus", "TeleopSession"]

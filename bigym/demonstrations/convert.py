"""Action conversion: between control rates and between absolute and delta joint targets.

Everything goes through the control each entry puts on its actuator at every 500 Hz
physics step:

* absolute targets, grippers and torques are what they say;
* delta entries (the floating base always, the limbs in delta mode) are tracked as the
  servo target they produce: ``target = clip(target + delta, joint range)``, starting from
  the ``ctrl`` of the demo's initial state, with the same float operations as the env.

A new action stream is then read off that per-physics-step control, one window of
``substeps`` physics steps per new action:

* absolute targets and grippers: the value at the window's end;
* torques: the window's mean (keeps the impulse);
* deltas (base and joints): the target at the window's end minus the target the new
  stream has reached so far, clipped to the new rate's bounds. With no clamping this is
  the sum of the window's deltas; a clipped remainder carries into the next window, so
  the motion is kept.

Below 500 Hz the env ramps each servo target over its action's physics steps (torques are
held), and the per-physics-step control above includes that ramp. A trailing part-window
is padded with "hold" (absolute repeated, zero deltas). Some conversions are exact (the
same physics, bit for bit): delta to absolute at the same rate, and any rate to 500 Hz
when the 500 Hz actions reproduce every physics step's control exactly (checked, not
assumed). The others follow the recording within a tolerance.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from bigym.demonstrations.errors import DemoActionModeError
from bigym.demonstrations.metadata import (
    PHYSICS_FREQUENCY,
    describe_action_mode,
    normalise_action_mode,
    state_segments,
)

ABSOLUTE, DELTA, TORQUE = 0, 1, 2
_KIND_NAMES = {ABSOLUTE: "absolute", DELTA: "delta", TORQUE: "torque"}


@dataclass
class ActionSpec:
    """Per-entry semantics of an action vector at one control rate."""

    kinds: np.ndarray  # ABSOLUTE / DELTA / TORQUE per entry
    ctrl_low: np.ndarray  # where the env clamps the actuator control
    ctrl_high: np.ndarray
    substeps: int
    low: np.ndarray | None = None  # action bounds at this rate (only needed for a target)
    high: np.ndarray | None = None

    @classmethod
    def for_env(cls, env, action_mode: dict | None = None, substeps: int | None = None) -> ActionSpec:
        """The spec of ``env``'s robot under ``action_mode`` (default: the env's) at ``substeps``."""
        base = getattr(env, "unwrapped", env)
        mode = normalise_action_mode(action_mode if action_mode is not None else base.action_mode)
        torque = mode["name"] == "TorqueActionMode"
        absolute = bool(mode["absolute"])
        kinds, ctrl_low, ctrl_high = [], [], []
        for act in base.robot.description.actuators:
            if act.kind == "base":
                kinds.append(DELTA)
                low, high = act.joint_range
            elif torque:
                kinds.append(TORQUE)
                low, high = -act.torque_limit, act.torque_limit
            else:
                kinds.append(ABSOLUTE if absolute else DELTA)
                low, high = act.joint_range
            ctrl_low.append(low)
            ctrl_high.append(high)
        for _ in range(2):  # grippers
            kinds.append(ABSOLUTE)
            ctrl_low.append(0.0)
            ctrl_high.append(1.0)
        spec = cls(np.array(kinds), np.array(ctrl_low, float), np.array(ctrl_high, float),
                   int(substeps or base.substeps))  # fmt: skip
        if action_mode is None and substeps in (None, base.substeps):
            spec.low = base.action_space.low.astype(np.float64)
            spec.high = base.action_space.high.astype(np.float64)
        return spec

    def describe(self) -> str:
        return ", ".join(sorted({_KIND_NAMES[int(k)] for k in self.kinds}))


def initial_ctrl(model: mujoco.MjModel, initial_state: np.ndarray, spec: int, size: int) -> np.ndarray:
    """The actuator controls stored in a demo's initial state."""
    part = state_segments(model, spec)["ctrl"]
    return np.asarray(initial_state[part][:size], dtype=np.float64)


def check_convertible(source_mode: dict, target_mode: dict) -> None:
    """Raise :class:`DemoActionModeError` when no conversion links the two action modes."""
    source, target = normalise_action_mode(source_mode), normalise_action_mode(target_mode)
    if source == target:
        return
    if source["floating_base"] != target["floating_base"] or source["floating_dofs"] != target["floating_dofs"]:
        raise DemoActionModeError(
            f"the demo drives the robot as {describe_action_mode(source)}, not {describe_action_mode(target)}: "
            "a different floating base (or whole body) changes the robot model, and no conversion exists. "
            f"Use an env with {describe_action_mode(source)}.",
            recorded=source,
            requested=target,
        )
    if source["name"] != target["name"]:
        raise DemoActionModeError(
            f"the demo was recorded with {describe_action_mode(source)}; it cannot be converted to "
            f"{describe_action_mode(target)} (torque and joint-position actions do not convert)",
            recorded=source,
            requested=target,
        )


def held_controls(actions: np.ndarray, source: ActionSpec, ctrl0: np.ndarray) -> np.ndarray:
    """The control each entry holds after each action: shape (steps, A).

    Same arithmetic as the env's controller: ``ctrl = clip(keep * ctrl + action, low, high)``.
    """
    actions = np.asarray(actions, np.float64)
    held = np.empty_like(actions)
    delta = source.kinds == DELTA
    target = np.array(ctrl0, np.float64)
    for k, action in enumerate(actions):
        target = np.minimum(np.maximum(np.where(delta, target + action, action), source.ctrl_low), source.ctrl_high)
        held[k] = target
    return held


def _delta_steps(wanted: np.ndarray, start: np.ndarray, low, high, c_low, c_high) -> np.ndarray:
    """Deltas that move a clamped servo target from ``start`` through ``wanted`` (rows), clipped."""
    current = np.array(start, np.float64)
    steps = np.empty_like(wanted)
    for j in range(len(wanted)):
        step = np.minimum(np.maximum(wanted[j] - current, low), high)
        steps[j] = step
        current = np.minimum(np.maximum(current + step, c_low), c_high)
    return steps


def physics_controls(actions: np.ndarray, spec: ActionSpec, ctrl0: np.ndarray) -> np.ndarray:
    """The control on each actuator at every physics step: shape (steps * substeps, A).

    The env's arithmetic: over an action's ``n`` physics steps a servo target moves from its
    last value to the new one in equal parts (``start + k/n * (end - start)``, the last step
    exactly ``end``); torques are held.
    """
    held = held_controls(actions, spec, ctrl0)
    n = spec.substeps
    if n == 1:
        return held
    starts = np.concatenate([np.asarray(ctrl0, np.float64)[None], held[:-1]])
    torque = spec.kinds == TORQUE
    starts[:, torque] = held[:, torque]
    fractions = (np.arange(1, n) / n)[:, None]
    controls = np.empty((len(held), n, held.shape[1]))
    for k, (start, end) in enumerate(zip(starts, held)):
        controls[k, :-1] = start + fractions * (end - start)
        controls[k, -1] = end
    return controls.reshape(-1, held.shape[1])


def convert_actions(
    actions: np.ndarray, source: ActionSpec, target: ActionSpec, ctrl0: np.ndarray
) -> tuple[np.ndarray, bool]:
    """Actions for ``target`` that reproduce ``source``'s motion, and whether exactly.

    ``ctrl0`` is ``data.ctrl`` of the robot after reset (where delta targets start).
    """
    actions = np.asarray(actions, np.float64)
    if not np.array_equal(source.kinds == TORQUE, target.kinds == TORQUE):
        raise DemoActionModeError("torque and joint-position actions do not convert")
    ctrl0 = np.asarray(ctrl0, np.float64)
    delta_target = target.kinds == DELTA
    low = target.low[delta_target] if target.low is not None else -np.inf
    high = target.high[delta_target] if target.high is not None else np.inf
    c_low, c_high = target.ctrl_low[delta_target], target.ctrl_high[delta_target]

    if source.substeps == target.substeps:
        # Same rate: entries of the same kind are copied; only changed kinds are converted.
        out = actions.copy()
        to_absolute = (source.kinds == DELTA) & (target.kinds == ABSOLUTE)
        to_delta = (source.kinds == ABSOLUTE) & delta_target
        if to_absolute.any() or to_delta.any():
            held = held_controls(actions, source, ctrl0)
            out[:, to_absolute] = held[:, to_absolute]
            if to_delta.any():
                sub = to_delta[delta_target]
                out[:, to_delta] = _delta_steps(
                    held[:, to_delta], ctrl0[to_delta], _pick(low, sub), _pick(high, sub), c_low[sub], c_high[sub]
                )
        # A delta recomputed from absolute targets may differ in the last bit.
        return out, not to_delta.any()

    controls = physics_controls(actions, source, ctrl0)
    physics_steps = len(controls)
    s = target.substeps
    count = -(-physics_steps // s)  # ceil: a part-window at the end is padded with "hold"
    padded = np.concatenate([controls, np.repeat(controls[-1:], count * s - physics_steps, axis=0)])
    windows = padded.reshape(count, s, -1)
    out = windows[:, -1, :].copy()  # absolute targets and grippers: the window's end
    torque = target.kinds == TORQUE
    if torque.any():
        out[:, torque] = windows[:, :, torque].mean(axis=1)
    if delta_target.any():
        out[:, delta_target] = _delta_steps(out[:, delta_target], ctrl0[delta_target], low, high, c_low, c_high)
    # Exact when the new actions set the very same control at every physics step (checked,
    # not assumed): only possible at 500 Hz, where each action is one physics step.
    exact = s == 1 and np.array_equal(held_controls(out, target, ctrl0), controls)
    return out, exact


def _pick(bound, mask):
    return bound[mask] if isinstance(bound, np.ndarray) else bound


def resampled_length(steps: int, source_substeps: int, target_substeps: int) -> int:
    return -(-steps * source_substeps // target_substeps)


def rate_of(substeps: int) -> float:
    return PHYSICS_FREQUENCY / substeps


def convert_demo(
    demo,
    to: str | None = None,
    frequency: float | None = None,
    *,
    verify: bool = True,
    tolerance: float | None = None,
    checkpoint_interval: int | None = None,
):
    """A new :class:`~bigym.demonstrations.demo.Demo` with ``to`` = "absolute" / "delta" actions
    and/or recorded at ``frequency`` Hz.

    The converted actions are replayed once in the target env: the replay is checked
    against the source's checkpoints (bit for bit where the conversion is exact, within a
    tolerance otherwise) and must reach success when the source did; its states become the
    new demo's checkpoints, so the new demo replays bit for bit at its own rate.
    """
    import uuid as _uuid

    from bigym.demonstrations.demo import Demo
    from bigym.demonstrations.metadata import _now
    from bigym.demonstrations.player import make_env, replay
    from bigym.demonstrations.recorder import default_checkpoint_interval
    from bigym.observations import ObservationConfig

    meta = demo.metadata
    mode = dict(normalise_action_mode(meta.action_mode))
    if to is not None:
        if to not in ("absolute", "delta"):
            raise ValueError(f"to must be 'absolute' or 'delta', got {to!r}")
        if mode["absolute"] is None:
            raise DemoActionModeError(
                f"demo {demo.uuid} uses {describe_action_mode(mode)}: only joint-position demos convert "
                "between absolute and delta"
            )
        mode["absolute"] = to == "absolute"
    env = make_env(meta, ObservationConfig(proprioception=False), frequency, mode)
    try:
        # the whole recording: the converted lightweight demo keeps what follows the episode too
        replayed = replay(demo, env=env, verify=verify, tolerance=tolerance, convert=True, episode_only=False)
        rate = float(env.control_frequency)
        action_mode = env.action_mode.to_dict()
        names = list(env.action_layout.names)
    finally:
        env.close()
    if replayed.report.converted is None:
        return demo
    interval = int(checkpoint_interval or default_checkpoint_interval(rate))
    steps = len(replayed.actions)
    picks = list(range(interval, steps + 1, interval))
    if not picks or picks[-1] != steps:
        picks.append(steps)
    new_uuid = _uuid.uuid5(_uuid.NAMESPACE_URL, f"bigym-demo:{demo.uuid}:{replayed.report.converted}").hex
    metadata = meta.replace(
        action_mode=action_mode,
        frequency=rate,
        uuid=new_uuid,
        date=_now(),
        num_steps=steps,
        checkpoint_interval=interval,
        action_names=names,
        extra={
            **meta.extra,
            "converted_from": demo.uuid,
            "conversion": replayed.report.converted,
            "conversion_exact": replayed.report.exact,
            "conversion_max_divergence": replayed.report.max_divergence,
        },
    )
    return Demo(metadata, replayed.actions, demo.initial_state, np.array(picks), replayed.states[picks])

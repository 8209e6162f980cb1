"""Replaying demos into observations at any control rate, checked against the recording.

:func:`replay` rebuilds the demo's env (or uses yours), resets it with the demo's seed,
proves the reset state equals the recorded one, converts the actions to the requested
rate (see :mod:`bigym.demonstrations.convert`), steps them while comparing against every
stored checkpoint that falls on a step of the new rate, and checks success at the end.
At the recording rate (or any exact conversion) the comparison is bit for bit; otherwise
the joint positions must stay within a tolerance. Any failure raises: a drifted replay is
never returned as if it were fine.

:func:`replay_many` does the same for many demos on a process pool (spawn context, one
env per worker and configuration, reused across demos) or on Ray when asked.
"""

from __future__ import annotations

import importlib
import json
import multiprocessing
import os
import warnings
from collections import OrderedDict
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from pathlib import Path

import mujoco
import numpy as np

import bigym
from bigym.action_modes import ActionMode
from bigym.demonstrations.convert import ActionSpec, check_convertible, convert_actions, initial_ctrl
from bigym.demonstrations.demo import Demo, ReplayedDemo, ReplayReport
from bigym.demonstrations.errors import (
    DemoActionModeError,
    DemoDivergenceError,
    DemoError,
    DemoReplayError,
    DemoVersionWarning,
)
from bigym.demonstrations.metadata import (
    PHYSICS_FREQUENCY,
    Metadata,
    describe_action_mode,
    describe_state_index,
    frequency_slug,
    model_fingerprint,
    normalise_action_mode,
    state_segments,
)
from bigym.observations import ObservationConfig
from bigym.worker_lifetime import exit_with_parent

# A replay at another rate than the recording follows it only approximately: the servo
# targets change once per new control step instead of every recorded step, so the robot may
# lead or lag by what it moves in one new control step, and where it pushes doors and
# drawers it meets them on that shifted schedule. A checkpoint passes when every compared
# joint position (rad or m) is within TOLERANCE_BASE + TOLERANCE_SPEED / rate: 0.17 at
# 50 Hz, 0.29 at 25 Hz, 0.35 at 20 Hz. The constants come from the spread measured over
# down-sampled replays of the expert demos that still succeed (in free motion the arms stay
# within about 0.04 rad at 50 Hz and 0.08 at 20 Hz; pushing doors, 0.1-0.4 more).
# Exact replays (the recording rate, or an exact conversion) must match bit for bit.
TOLERANCE_BASE = 0.05
TOLERANCE_SPEED = 6.0  # rad/s (or m/s)

# Only the robot's own joints are compared (base or free root, legs, torso, arms); not the
# grippers' linkage joints, nor the props and objects. At another rate a close or open
# command shifts by up to one new control step, in which the fingers sweep much of their
# range (measured on the expert demos: up to 0.3 rad at 50 Hz, 0.7 rad at 20 Hz), and what
# contacts move (a door pushed open, a drawer, an object) moves on that shifted schedule:
# doors were measured 0.08-0.15 rad apart at 50 Hz in replays that still succeed. Exact
# replays compare everything bit for bit, and every replay must reach success.


def default_tolerance(frequency: float) -> float:
    """The joint-position tolerance of an inexact replay at ``frequency`` Hz."""
    return TOLERANCE_BASE + TOLERANCE_SPEED / float(frequency)


VIDEO_FPS = 30.0


# ---------------------------------------------------------------------- envs
def resolve_task(name: str) -> type:
    """The task class registered under ``name``: class name, snake_case name (as in the
    paper), alias or gymnasium id, in any letter case."""
    from bigym.task_docs import snake_case

    wanted = name.removeprefix("bigym/").removesuffix("-v0")
    key = wanted if wanted in bigym.TASKS else bigym.ALIASES.get(wanted)
    if key is None:
        lookup = {k.lower(): k for k in bigym.TASKS}
        lookup.update({snake_case(k): k for k in bigym.TASKS})
        lookup.update({alias.lower(): k for alias, k in bigym.ALIASES.items()})
        key = lookup.get(wanted.lower())
    if key is None:
        raise DemoError(f"unknown task {name!r}; this bigym knows {', '.join(bigym.TASKS)}", task=name)
    module, cls = bigym.TASKS[key].split(":")
    return getattr(importlib.import_module(module), cls)


def _observation_config(config) -> ObservationConfig:
    if config is None:
        return ObservationConfig()
    if isinstance(config, ObservationConfig):
        return config
    return ObservationConfig.from_dict(config)


def make_env(
    metadata: Metadata,
    observation_config: ObservationConfig | dict | None = None,
    frequency: float | None = None,
    action_mode: ActionMode | dict | None = None,
    render_mode: str | None = None,
):
    """Build the env a demo needs: its task, robot and action mode, your observations and rate."""
    from bigym.action_modes import action_mode_from_dict

    cls = resolve_task(metadata.task)
    if action_mode is None:
        action_mode = metadata.make_action_mode()
    elif isinstance(action_mode, dict):
        action_mode = action_mode_from_dict(action_mode)
    return cls(
        action_mode=action_mode,
        observation_config=_observation_config(observation_config),
        control_frequency=float(frequency if frequency is not None else metadata.frequency),
        render_mode=render_mode,
        **metadata.task_kwargs,
    )


def check_env_for_demo(demo: Demo, env, convert: bool = False) -> None:
    """Raise a clear error when ``env`` cannot replay ``demo``."""
    base = getattr(env, "unwrapped", env)
    if resolve_task(demo.metadata.task) is not type(base):
        raise DemoError(
            f"demo {demo.uuid} is for task {demo.metadata.task}, this env runs {base.task_name}",
            task=demo.metadata.task,
        )
    recorded, wanted = normalise_action_mode(demo.metadata.action_mode), normalise_action_mode(base.action_mode)
    if recorded == wanted:
        return
    check_convertible(recorded, wanted)  # raises when no conversion exists
    if not convert:
        hint = ""
        if recorded["absolute"] is not None and wanted["absolute"] is not None:
            to = "absolute" if wanted["absolute"] else "delta"
            hint = (
                f"; convert with `bigym demos convert --to {to}`, or pass convert=True to replay it through "
                f"the conversion (convert_demo(demo, to='{to}') in Python)"
            )
        kind = {True: "absolute actions", False: "delta actions", None: "torques"}
        raise DemoActionModeError(
            f"demo {demo.uuid} was recorded with {kind[recorded['absolute']]} ({describe_action_mode(recorded)}), "
            f"but the env uses {kind[wanted['absolute']]} ({describe_action_mode(wanted)}){hint}",
            recorded=recorded,
            requested=wanted,
        )


# ---------------------------------------------------------------------- replay

def _mismatch_hint(demo: Demo, env) -> str:
    notes = []
    meta = demo.metadata
    if meta.model_fingerprint and meta.model_fingerprint != model_fingerprint(env.model):
        notes.append("the compiled model differs from the one the demo was recorded with (physics fingerprint)")
    if meta.mujoco_version != mujoco.__version__:
        notes.append(f"recorded with MuJoCo {meta.mujoco_version}, running {mujoco.__version__}")
    if meta.bigym_version != bigym.__version__:
        notes.append(f"recorded with bigym {meta.bigym_version}, running {bigym.__version__}")
    return ("; likely cause: " + "; ".join(notes)) if notes else ""


def _warn_versions(demo: Demo, env) -> None:
    hint = _mismatch_hint(demo, env)
    if hint:
        warnings.warn(f"demo {demo.uuid}{hint}", DemoVersionWarning, stacklevel=3)


def replay(
    demo: Demo,
    observation_config: ObservationConfig | dict | None = None,
    frequency: float | None = None,
    *,
    env=None,
    action_mode: ActionMode | dict | None = None,
    verify: bool = True,
    tolerance: float | None = None,
    video: Path | str | None = None,
    video_fps: float = VIDEO_FPS,
    convert: bool = False,
    episode_only: bool = True,
) -> ReplayedDemo:
    """Replay ``demo`` into ``observation_config`` at ``frequency`` Hz; return its episode.

    ``env``: replay in this env (its observations, rate and action mode) instead of a new
    one. ``action_mode``: convert to another joint-position mode (absolute / delta) on the
    fly. ``verify``: raise :class:`DemoDivergenceError` on the first checkpoint that differs
    (bit for bit when the replay is exact, else by more than ``tolerance`` on any joint
    position, default :func:`default_tolerance`) and :class:`DemoReplayError` when a demo
    marked successful never reaches success or the physics turns unstable. ``video``: also
    write an mp4 of the external camera (of the whole recording). ``convert``: allow ``env`` to use another
    joint-position mode than the demo (absolute / delta); without it such an env is an error.

    The whole recording is replayed and checked; what is returned is the episode, which
    ends at the first step with ``terminated`` or ``truncated`` (``report.replayed_steps``
    vs ``report.episode_steps``). ``episode_only=False`` returns every replayed step
    instead, steps after the episode's end included (what a conversion of the lightweight
    demo to another rate or mode keeps).
    """
    own_env = env is None
    if own_env:
        env = make_env(demo.metadata, observation_config, frequency, action_mode,
                       render_mode="rgb_array" if video is not None else None)  # fmt: skip
    elif observation_config is not None or frequency is not None:
        raise ValueError("pass either env or observation_config/frequency, not both: the env fixes both")
    elif action_mode is not None and not _modes_equal(action_mode, env.unwrapped.action_mode):
        raise ValueError("action_mode differs from the env's action mode")
    try:
        check_env_for_demo(demo, env, convert=convert or action_mode is not None)
        return _replay_in_env(demo, env.unwrapped, verify, tolerance, video, video_fps, episode_only)
    finally:
        if own_env:
            env.close()


#: down-sampled rates every verified demo also replays at (checkpoints within tolerance,
#: success at the end), besides its own rate (bit for bit): the rates the paper's baselines
#: trained at (robobase: 50, 25 and 20 Hz)
VERIFY_RATES = (50.0, 25.0, 20.0)


def verification_failure(
    demo: Demo, rates: Sequence[float] = VERIFY_RATES, env_for: Callable[[float], object] | None = None
) -> str | None:
    """Why ``demo`` is not a verified demo, or None when it is: replayed from its file's
    bytes at its own rate (bit for bit) and at each of ``rates`` (within tolerance), it
    must reach success every time. ``env_for(rate)``: an env to reuse at that rate (a new
    one is built when it gives None)."""
    loaded = Demo.from_bytes(demo.to_bytes(), demo.metadata.uuid)
    for rate in (float(demo.metadata.frequency), *(float(r) for r in rates)):
        env = env_for(rate) if env_for is not None else None
        try:
            if env is None:
                replayed = replay(loaded, frequency=rate, verify=True)
            else:
                replayed = replay(loaded, env=env, verify=True)
        except DemoError as error:
            return f"replay at {rate:g} Hz failed: {error}"
        if replayed.report.first_success_step is None:
            return f"replay at {rate:g} Hz failed: never succeeded"
    return None


def _modes_equal(a, b) -> bool:
    return normalise_action_mode(a) == normalise_action_mode(b)


def _same_mode(demo: Demo, env) -> bool:
    return normalise_action_mode(demo.metadata.action_mode) == normalise_action_mode(env.unwrapped.action_mode)


def _replay_in_env(
    demo: Demo, env, verify: bool, tolerance: float | None, video, video_fps, episode_only: bool = True
) -> ReplayedDemo:
    meta = demo.metadata
    model, data = env.model, env.data
    if meta.seed is None:
        raise DemoError(f"demo {demo.uuid} has no reset seed: it cannot be replayed")

    # Actions at the env's rate and in its action mode.
    source = ActionSpec.for_env(env, meta.action_mode, meta.substeps)
    target = ActionSpec.for_env(env)
    ctrl0 = initial_ctrl(model, demo.initial_state, meta.initial_state_spec, len(target.kinds))
    actions, exact = convert_actions(demo.actions, source, target, ctrl0)
    converted = []
    if meta.substeps != env.substeps:
        converted.append(f"{frequency_slug(meta.frequency)}->{frequency_slug(env.control_frequency)}")
    if not _same_mode(demo, env):
        converted.append(f"{describe_action_mode(meta.action_mode)}->{describe_action_mode(env.action_mode)}")
    tol = 0.0 if exact else float(default_tolerance(env.control_frequency) if tolerance is None else tolerance)

    # Reset and prove the initial state; the model is compared after the reset, which may
    # move static props (a task's racks and pads are placed by moving their bodies).
    obs, info = env.reset(seed=int(meta.seed))
    _warn_versions(demo, env)
    state0 = np.empty(mujoco.mj_stateSize(model, meta.initial_state_spec))
    mujoco.mj_getState(model, data, state0, meta.initial_state_spec)
    if state0.shape != demo.initial_state.shape or not np.array_equal(state0, demo.initial_state):
        if verify:
            raise _divergence(demo, env, 0, 0, state0, demo.initial_state, meta.initial_state_spec, 0.0,
                              "the state after reset(seed) differs from the recorded initial state")  # fmt: skip
        if state0.shape == demo.initial_state.shape:  # best effort: start from the recorded state
            mujoco.mj_setState(model, data, demo.initial_state, meta.initial_state_spec)
            mujoco.mj_forward(model, data)
            obs = env._observe()

    # Which replay step each checkpoint lands on.
    spec = meta.checkpoint_spec
    qpos = state_segments(model, spec).get("qpos", slice(0, 0))
    ignored = np.ones(model.nq, bool)  # not compared in inexact replays (see TOLERANCE_SPEED)
    ignored[env.robot.replay_checked_qpos] = False

    def joint_positions(state: np.ndarray) -> np.ndarray:
        positions = state[qpos].copy()
        positions[ignored] = 0.0
        return positions

    checks: dict[int, int] = {}
    for index, step in enumerate(demo.checkpoint_steps):
        physics = int(step) * meta.substeps
        if physics % env.substeps == 0 and 0 < physics // env.substeps <= len(actions):
            checks[physics // env.substeps] = index

    steps = len(actions)
    state_size = mujoco.mj_stateSize(model, spec)
    states = np.empty((steps + 1, state_size))
    mujoco.mj_getState(model, data, states[0], spec)
    observations = {key: [value] for key, value in obs.items()}
    rewards = np.zeros(steps)
    terminated = np.zeros(steps, bool)
    truncated = np.zeros(steps, bool)
    success = np.zeros(steps, bool)
    report = ReplayReport(demo.uuid, float(meta.frequency), float(env.control_frequency), exact, tol,
                          converted=", ".join(converted) or None)  # fmt: skip
    writer, frame_every = None, 1
    if video is not None:
        writer, frame_every = _open_video(video, env, video_fps)
        writer.append_data(env.render())
    try:
        for j in range(steps):
            try:
                obs, reward, term, trunc, info = env.step(actions[j])
            except ValueError as error:  # the env rejects the action: a damaged or foreign demo
                raise DemoReplayError(
                    f"demo {demo.uuid}: action {j} is not valid for {env.task_name} with "
                    f"{describe_action_mode(env.action_mode)} at {env.control_frequency:g} Hz: {error}",
                    step=j,
                ) from error
            for key, value in obs.items():
                observations[key].append(value)
            rewards[j], terminated[j], truncated[j] = reward, term, trunc
            success[j] = bool(info.get("is_success", False))
            if success[j] and report.first_success_step is None:
                report.first_success_step = j + 1
            mujoco.mj_getState(model, data, states[j + 1], spec)
            if writer is not None and (j + 1) % frame_every == 0:
                writer.append_data(env.render())
            if "unstable" in info and verify:
                raise DemoReplayError(
                    f"replay of demo {demo.uuid} became unstable at step {j + 1}: {info['unstable']}"
                    + _mismatch_hint(demo, env),
                    step=j + 1,
                )
            index = checks.get(j + 1)
            if index is None:
                continue
            recorded = demo.checkpoint_states[index]
            report.checkpoints_checked += 1
            if exact:
                if states[j + 1].shape != recorded.shape or not np.array_equal(states[j + 1], recorded):
                    if verify:
                        raise _divergence(demo, env, j + 1, int(demo.checkpoint_steps[index]), states[j + 1],
                                          recorded, spec, 0.0)  # fmt: skip
                    size = _max_diff(states[j + 1], recorded)
                else:
                    size = 0.0
            else:
                replayed, expected = joint_positions(states[j + 1]), joint_positions(recorded)
                size = float(np.max(np.abs(replayed - expected), initial=0.0))
                if not size <= tol and verify:
                    raise _divergence(demo, env, j + 1, int(demo.checkpoint_steps[index]), replayed, expected,
                                      None, tol)  # fmt: skip
            if size > report.max_divergence:
                report.max_divergence, report.max_divergence_step = size, j + 1
    finally:
        if writer is not None:
            writer.close()

    # The recording's last state rarely falls on a step of another rate: the replay pads the
    # last window with "hold", so its end state is also checked, with the slack of that padding.
    last = len(demo.checkpoint_steps) - 1
    if not exact and steps and last >= 0 and last not in checks.values():
        pad = steps * env.substeps - int(demo.checkpoint_steps[last]) * meta.substeps
        if pad >= 0:
            end_tol = tol + TOLERANCE_SPEED * pad / PHYSICS_FREQUENCY
            replayed, expected = joint_positions(states[-1]), joint_positions(demo.checkpoint_states[last])
            size = float(np.max(np.abs(replayed - expected), initial=0.0))
            report.checkpoints_checked += 1
            if not size <= end_tol and verify:
                raise _divergence(demo, env, steps, int(demo.checkpoint_steps[last]), replayed, expected,
                                  None, end_tol)  # fmt: skip
            if size > report.max_divergence:
                report.max_divergence, report.max_divergence_step = size, steps
    if verify and meta.success and report.first_success_step is None:
        raise DemoReplayError(
            f"demo {demo.uuid} is marked successful, but its replay at {env.control_frequency:g} Hz never reaches "
            f"success (max divergence {report.max_divergence:.3g} over {report.checkpoints_checked} checkpoints)"
            + _mismatch_hint(demo, env),
        )
    # One episode semantics everywhere: the episode ends at its first terminal step (success,
    # failure or time limit). The recording may go on past it (expert demos keep ~1 s, so
    # that replays at lower rates still reach success); those steps were replayed and
    # checked above, but they are not part of the MDP, so they are not returned.
    ends = np.flatnonzero(terminated | truncated)
    episode = int(ends[0]) + 1 if ends.size else steps
    report.replayed_steps, report.episode_steps = steps, episode
    if not episode_only:
        episode = steps
    report.final_success = bool(success[episode - 1]) if episode else False
    actions, rewards, terminated, truncated, success = (
        a[:episode] for a in (actions, rewards, terminated, truncated, success)
    )
    states = states[: episode + 1]
    stacked = {key: np.stack(values[: episode + 1]) for key, values in observations.items()}
    metadata = meta.replace(
        frequency=float(env.control_frequency),
        observation_config=env.observation_config.to_dict(),
        action_mode=env.action_mode.to_dict(),
        action_names=list(env.action_layout.names),
        num_steps=episode,
        model_fingerprint=model_fingerprint(model),
        bigym_version=bigym.__version__,
        mujoco_version=mujoco.__version__,
        extra={**meta.extra, "source_frequency": float(meta.frequency)},
    )
    return ReplayedDemo(metadata, stacked, actions, rewards, terminated, truncated, success, states, report)


def _max_diff(a: np.ndarray, b: np.ndarray) -> float:
    if a.shape != b.shape:
        return float("inf")
    return float(np.max(np.abs(a - b), initial=0.0))


def _divergence(demo, env, step, source_step, replayed, recorded, spec, tolerance, reason=None):
    """The error for a replay that left the recording (``spec`` None: ``replayed`` is qpos)."""
    model = env.model
    if replayed.shape != recorded.shape:
        size, where = float("inf"), f"state size {replayed.shape} vs recorded {recorded.shape}"
    else:
        diff = np.abs(replayed - recorded)
        diff[np.isnan(diff)] = np.inf
        index = int(np.argmax(diff))
        size = float(diff[index])
        if spec is None:  # a qpos slice
            joint = int(np.searchsorted(model.jnt_qposadr, index, side="right") - 1)
            where = f"qpos[{index}] (joint {model.joint(joint).name or joint})"
        else:
            where = describe_state_index(model, spec, index)
    rate = f"{env.control_frequency:g} Hz"
    what = reason or (
        "bit-identical replay expected"
        if tolerance == 0
        else f"tolerance {tolerance:g} on joint positions; the demo was recorded at "
        f"{demo.metadata.frequency:g} Hz and its actions were converted, which this demo does not survive: "
        "replay it at a rate closer to the recording, or pass a larger tolerance"
    )
    seconds = step / env.control_frequency
    return DemoDivergenceError(
        f"replay of demo {demo.uuid} diverged at step {step} ({seconds:.3f} s, {rate}; recorded step "
        f"{source_step}): max |difference| {size:.3g} at {where} ({what})" + _mismatch_hint(demo, env),
        step=step,
        source_step=source_step,
        size=size,
        where=where,
        tolerance=tolerance,
    )


def _open_video(path, env, fps: float):
    import imageio.v2 as imageio

    if env.render_mode != "rgb_array":
        raise DemoError("writing a video needs an env built with render_mode='rgb_array'")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    frame_every = max(1, round(env.control_frequency / fps))
    writer = imageio.get_writer(path, fps=env.control_frequency / frame_every, macro_block_size=1)
    return writer, frame_every


# ---------------------------------------------------------------------- many demos
_ENV_CACHE: OrderedDict[str, object] = OrderedDict()
_ENV_CACHE_SIZE = 2


def _cached_env(demo: Demo, observation_config, frequency, action_mode):
    mode = action_mode if action_mode is not None else demo.metadata.action_mode
    if isinstance(mode, ActionMode):
        mode = mode.to_dict()
    config = _observation_config(observation_config).to_dict()
    rate = frequency if frequency is not None else demo.metadata.frequency
    key = json.dumps([demo.metadata.task, demo.metadata.task_kwargs, mode, config, float(rate)], sort_keys=True)
    env = _ENV_CACHE.get(key)
    if env is None:
        env = make_env(demo.metadata, config, rate, mode)
        _ENV_CACHE[key] = env
        while len(_ENV_CACHE) > _ENV_CACHE_SIZE:
            _, old = _ENV_CACHE.popitem(last=False)
            old.close()
    _ENV_CACHE.move_to_end(key)
    return env


def close_cached_envs() -> None:
    """Close the envs :func:`replay_many` keeps for reuse in this process."""
    while _ENV_CACHE:
        _, env = _ENV_CACHE.popitem()
        env.close()


def _replay_job(job: tuple) -> ReplayedDemo:
    demo, observation_config, frequency, action_mode, verify, tolerance, episode_only = job
    if isinstance(demo, (str, Path)):
        demo = Demo.load(demo)
    env = _cached_env(demo, observation_config, frequency, action_mode)
    return replay(
        demo, env=env, verify=verify, tolerance=tolerance, convert=action_mode is not None, episode_only=episode_only
    )


def replay_many(
    demos: Sequence[Demo | Path | str],
    observation_config: ObservationConfig | dict | None = None,
    frequency: float | None = None,
    *,
    action_mode: ActionMode | dict | None = None,
    workers: int | None = None,
    backend: str = "process",
    verify: bool = True,
    tolerance: float | None = None,
    progress: bool = True,
    errors: str = "raise",
    on_result: Callable[[int, ReplayedDemo | Exception], None] | None = None,
    description: str = "replaying demos",
    pool: ReplayPool | None = None,
    episode_only: bool = True,
) -> list[ReplayedDemo | Exception]:
    """Replay many demos, in input order; in parallel with ``workers`` > 1.

    ``backend``: ``"process"`` (a spawn-context process pool; safe with MuJoCo and EGL),
    ``"ray"`` (needs the optional ``ray`` package; imported only here) or ``"serial"``.
    ``errors``: ``"raise"`` stops at the first failure; ``"return"`` puts the exception in
    that demo's place. ``on_result(index, result)`` is called as each demo finishes.
    ``pool``: a :class:`ReplayPool` to reuse (its size replaces ``workers``).
    ``episode_only``: as for :func:`replay` (False: the recording's steps after the episode's
    end too).
    """
    if errors not in ("raise", "return"):
        raise ValueError("errors must be 'raise' or 'return'")
    if backend not in ("process", "ray", "serial"):
        raise ValueError(f"backend must be 'process', 'ray' or 'serial', got {backend!r}")
    if isinstance(observation_config, ObservationConfig):
        observation_config = observation_config.to_dict()
    if isinstance(action_mode, ActionMode):
        action_mode = action_mode.to_dict()
    jobs = [(demo, observation_config, frequency, action_mode, verify, tolerance, episode_only) for demo in demos]
    workers = pool.workers if pool is not None else max(1, min(workers or 1, len(jobs) or 1))
    results: list = [None] * len(jobs)

    with progress_bar(progress, description, len(jobs)) as advance:

        def finish(index: int, result) -> None:
            if isinstance(result, BaseException) and errors == "raise":
                raise result
            results[index] = result
            if on_result is not None:
                on_result(index, result)
            advance()

        if backend == "ray":
            _run_ray(jobs, workers, finish)
        elif backend == "serial" or (workers == 1 and pool is None):
            # The envs stay cached for the next call (close_cached_envs() frees them).
            for index, job in enumerate(jobs):
                try:
                    result = _replay_job(job)
                except DemoError as error:
                    result = error
                finish(index, result)
        else:
            _run_pool(jobs, workers, finish, pool)
    return results


def _warm_worker(_: int) -> int:
    import time

    import bigym.envs  # noqa: F401  (the imports a replay needs)

    time.sleep(0.05)  # hold this worker so that the next call starts another one
    return os.getpid()


class ReplayPool:
    """A reusable spawn-context process pool for :func:`replay_many`.

    Starting workers (a fresh interpreter, importing bigym, building an env) takes seconds;
    a pool kept across calls pays that once, and its workers keep their envs (one per task,
    observation config and rate) between calls. Use as a context manager, or ``close()``.
    """

    def __init__(self, workers: int = 2) -> None:
        self.workers = max(1, int(workers))
        context = multiprocessing.get_context("spawn")  # fork is unsafe with GL contexts and threads
        self.executor = ProcessPoolExecutor(
            max_workers=self.workers, mp_context=context, initializer=exit_with_parent
        )

    def warm_up(self) -> ReplayPool:
        """Start every worker and import bigym in it now."""
        list(self.executor.map(_warm_worker, range(self.workers)))
        return self

    def close(self) -> None:
        self.executor.shutdown(wait=True, cancel_futures=True)

    def __enter__(self) -> ReplayPool:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _run_pool(jobs, workers, finish, pool: ReplayPool | None = None) -> None:
    own = pool is None
    if own:
        pool = ReplayPool(workers)
    futures = {pool.executor.submit(_replay_job, job): index for index, job in enumerate(jobs)}
    try:
        pending = set(futures)
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                error = future.exception()
                if error is not None and not isinstance(error, DemoError):
                    raise error
                finish(futures[future], error if error is not None else future.result())
    except BaseException:
        for future in futures:
            future.cancel()
        raise
    finally:
        if own:
            pool.close()


def _run_ray(jobs, workers, finish) -> None:
    """The jobs as Ray tasks (:mod:`bigym.scale_out`): a local instance, or the cluster Ray is connected to."""
    from bigym.scale_out import RayUnavailableError, run_tasks

    try:
        for finished in run_tasks(_replay_job, jobs, workers, catch=(DemoError,)):
            for index, result in finished:
                finish(index, result)
    except RayUnavailableError as error:
        raise DemoError(str(error)) from error


class progress_bar:
    """A rich progress bar (or nothing) that yields an ``advance()`` callable."""

    def __init__(self, enabled: bool, description: str, total: int) -> None:
        self.enabled, self.description, self.total = enabled, description, total
        self._progress = None

    def __enter__(self):
        if not self.enabled:
            return lambda: None
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            SpinnerColumn,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self._progress = Progress(
            SpinnerColumn(), TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
            TimeElapsedColumn(), TimeRemainingColumn(),
        )  # fmt: skip
        self._progress.__enter__()
        task = self._progress.add_task(self.description, total=self.total)
        return lambda: self._progress.advance(task)

    def __exit__(self, *exc) -> None:
        if self._progress is not None:
            self._progress.__exit__(*exc)

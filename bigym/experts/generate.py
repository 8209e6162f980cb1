"""Generate verified expert demos: record, replay from the lightweight file, keep successes.

:func:`generate_demos` runs the task's human-like expert on seeds ``seed, seed + 1, ...``
(the same integer seeds the env's reset and the expert's own draws), records each
episode at 500 Hz through :class:`bigym.demonstrations.DemoRecorder` in the benchmark's
action mode (floating base, absolute joint positions), serialises it to its lightweight
file format, replays it from those bytes with :func:`bigym.demonstrations.replay`
(bit-exact checkpoints, success at the end) and keeps it only if all of that holds,
until ``n`` demos are kept or ``max_attempts`` are spent. Attempts run in parallel on a
spawn-context process pool (one env per worker, reused), with a progress bar.

The report says how often the generator succeeded and why the others failed.
"""

from __future__ import annotations

import multiprocessing
import os
from collections import Counter
from collections.abc import Iterable, Iterator
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from bigym.experts.incidents import IncidentWatch
from bigym.experts.motion import HumanStyle
from bigym.experts.numerics import numerics_pinned, pinned_environment, pinned_settings
from bigym.worker_lifetime import exit_with_parent

CONTROL_FREQUENCY = 500.0  # the recording rate of the benchmark's demos
#: seconds recorded after the first success: a margin for replays at lower rates, which
#: reach success a little later (0.2 s was too little for the dishwasher door)
AFTER_SUCCESS = 1.0


@dataclass
class Attempt:
    """One recorded episode and what became of it."""

    index: int
    seed: int
    success: bool
    reason: str | None = None  # why it was not kept
    data: bytes | None = None  # the lightweight demo file's bytes (kept demos only)
    duration: float = 0.0  # simulated seconds
    choices: dict = field(default_factory=dict)


@dataclass
class GenerationReport:
    """What :func:`generate_demos` produced."""

    task: str
    requested: int
    attempts: list[Attempt]
    demos: list  # bigym.demonstrations.Demo, in seed order
    paths: list[Path]

    @property
    def kept(self) -> int:
        return len(self.demos)

    @property
    def success_rate(self) -> float:
        """Fraction of attempts that became verified demos."""
        return self.kept / len(self.attempts) if self.attempts else 0.0

    @property
    def failures(self) -> list[tuple[int, str]]:
        return [(a.seed, a.reason or "unknown") for a in self.attempts if not a.success]

    def failure_summary(self) -> dict[str, int]:
        """Failure reasons (their first clause) and how often each happened."""
        return dict(Counter((reason.split(":")[0]) for _, reason in self.failures))

    def summary(self) -> str:
        lines = [
            (
                f"{self.task}: kept {self.kept}/{self.requested} demos from {len(self.attempts)} attempts "
                f"(generator success rate {100.0 * self.success_rate:.0f}%)"
            )
        ]
        for seed, reason in self.failures:
            lines.append(f"  seed {seed}: {reason}")
        return "\n".join(lines)


# ---------------------------------------------------------------------- one attempt
_ENVS: dict[str, object] = {}


def _env(task: str, frequency: float = CONTROL_FREQUENCY):
    key = f"{task}@{frequency:g}"
    env = _ENVS.get(key)
    if env is None:
        from bigym.action_modes import JointPositionActionMode
        from bigym.demonstrations.player import resolve_task

        env = resolve_task(task)(
            action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=frequency
        )
        _ENVS[key] = env
    return env


def close_envs() -> None:
    """Close the envs :func:`record_attempt` keeps for reuse in this process."""
    while _ENVS:
        _, env = _ENVS.popitem()
        env.close()


def failure_reason(env, info: dict) -> str:
    """Why an episode did not succeed, in words (unmet joints, unstable physics, ...)."""
    if "unstable" in info:
        return f"unstable physics: {info['unstable']}"
    base = env.unwrapped
    prefix = "time limit" if info.get("time_limit") else "stopped"
    targets = getattr(base, "targets", None)
    goal = getattr(base, "goal", None)
    if targets and goal is not None:
        missed = []
        pairs = (
            [("dishwasher", k) for k in targets]
            if isinstance(targets[0], str)
            else [(p, k) for p, ks in targets for k in ks]
        )
        for prop, key in pairs:
            p = base.props[prop]
            value = float(p.get_state(base.data)[p.joint_index(key)])
            if abs(value - goal) > 0.1:
                missed.append(f"{prop}/{key}={value:.2f}")
        return f"{prefix}: not at {goal:g}: " + ", ".join(missed)
    if hasattr(base, "target_positions"):
        return f"{prefix}: target not reached"
    dropped = [name for name, mask in zip(base.fail_on_floor, getattr(base, "_floor_fail_masks", ())) if base.touching(mask, base.floor_mask)]
    if dropped:
        return f"{prefix}: {', '.join(dropped)} on the floor"
    return prefix


def demo_uuid(task: str, seed: int, style: dict | None) -> str:
    """A uuid that names the expert demo of ``task`` on ``seed`` with ``style`` (and this
    bigym version): the same on every run, so a regenerated dataset has the same files."""
    import json
    import uuid

    import bigym

    key = json.dumps(["expert", task, int(seed), style or HumanStyle().to_dict(), bigym.__version__], sort_keys=True)
    return uuid.uuid5(uuid.NAMESPACE_URL, "bigym:" + key).hex


def record_attempt(
    task: str,
    index: int,
    seed: int,
    style: dict | None = None,
    verify: bool = True,
    date: str | None = None,
    reject_incidents: bool = True,
    *,
    expert_class: type | None = None,
    rates: tuple[float, ...] | None = None,
) -> Attempt:
    """Record the expert on ``seed``, and (``verify``) replay it from its file bytes: at
    the recording rate (bit-exact) and at each of ``rates`` (within tolerance; default
    ``VERIFY_RATES``, what a dataset demo must pass). ``expert_class``: an expert not (yet)
    in the registry, e.g. one under development (default: the task's registered expert).

    The recording ends ``AFTER_SUCCESS`` s after the first success; for an expert whose
    ``success_must_last``, once the task has been successful for the step that succeeds and
    ``AFTER_SUCCESS`` s after it without a break (the same end when the first success holds;
    "success did not last" when no such stretch begins within the time limit); for an
    expert whose ``success_after_plan``, such a stretch after its plan has returned.

    ``reject_incidents``: reject the attempt at the first mishap the incident watch names
    (an object dropped, knocked over or pushed into a surface; see
    :mod:`bigym.experts.incidents`). Off only to regenerate a file whose bytes are known
    (:func:`regenerate`): the sha256 decides there, and a demo shipped before a check was
    added stays reproducible.

    ``date``: the date written into the demo (default now); with a fixed date the demo's
    bytes depend only on the task, seed, style and versions, and on this process's numpy
    kernels: :func:`generate_demos` runs it in workers with pinned kernels, so that its
    files are the same on every machine.
    """
    from bigym.demonstrations import DemoRecorder
    from bigym.demonstrations.player import VERIFY_RATES, verification_failure
    from bigym.experts import make_expert

    env = _env(task)
    recorder = DemoRecorder(env, source="expert")
    obs, _ = recorder.reset(seed=seed)
    human_style = HumanStyle(**style) if style else None
    if expert_class is None:
        expert = make_expert(env, seed=seed, style=human_style)
    else:
        expert = expert_class(env, seed=seed, style=human_style)
    watch = IncidentWatch(env, expert.drop_speeds, expert.may_tip)
    margin = round(AFTER_SUCCESS * CONTROL_FREQUENCY)
    after = None
    lasted = 0  # steps the success has held without a break (experts whose success must last)
    info: dict = {}
    for _ in range(env.unwrapped.max_episode_steps + margin):
        obs, _, terminated, truncated, info = recorder.step(expert(obs))
        if "unstable" in info:
            break
        incident = watch.check() if reject_incidents else None
        if incident is not None:
            duration = recorder.num_steps / CONTROL_FREQUENCY
            recorder.discard()
            return Attempt(index, seed, False, f"rejected: {incident}", None, duration, dict(expert.choices))
        if recorder.first_success_step is not None:
            if expert.success_must_last or expert.success_after_plan:
                # the step that succeeds and a whole margin after it: a success that holds
                # from the first gives the same recording as the plain rule
                counts = info.get("is_success", False) and (expert.finished or not expert.success_after_plan)
                lasted = lasted + 1 if counts else 0
                if lasted > margin:
                    break
                continue
            after = margin if after is None else after - 1
            if after <= 0:
                break
            continue
        if terminated or truncated:
            break
    duration = recorder.num_steps / CONTROL_FREQUENCY
    choices = dict(expert.choices)
    if recorder.first_success_step is None or "unstable" in info:
        reason = failure_reason(env, info)
        recorder.discard()
        return Attempt(index, seed, False, reason, None, duration, choices)
    if (expert.success_must_last or expert.success_after_plan) and lasted <= margin:
        recorder.discard()
        return Attempt(index, seed, False, "success did not last", None, duration, choices)
    demo = recorder.to_demo(
        uuid=demo_uuid(task, seed, style),
        date=date,
        expert_choices=choices,
        expert_style=(style or HumanStyle().to_dict()),
    )
    if verify:
        # from the file's bytes, in a reused env per rate: no model build per demo
        checked = VERIFY_RATES if rates is None else rates
        reason = verification_failure(demo, checked, env_for=lambda rate: _env(task, rate))
        if reason is not None:
            return Attempt(index, seed, False, reason, None, duration, choices)
    return Attempt(index, seed, True, None, demo.to_bytes(), duration, choices)


def _job(args: tuple) -> Attempt:
    return record_attempt(*args)


def _pinned_job(args: tuple) -> Attempt:
    """A job in a worker that should have been started with pinned numerics (Ray): refuse to
    record with other kernels, which would give other bytes."""
    if not numerics_pinned():
        raise RuntimeError("this worker's numpy runs on dispatched SIMD kernels: its demos would differ in bytes")
    return record_attempt(*args)


# ---------------------------------------------------------------------- many attempts
def generate_demos(
    task: str,
    n: int = 50,
    seed: int = 0,
    out_dir: Path | str | None = None,
    workers: int | None = None,
    style: HumanStyle | None = None,
    max_attempts: int | None = None,
    progress: bool = True,
    verify: bool = True,
    store=None,
    date: str | None = None,
    backend: str = "process",
) -> GenerationReport:
    """Generate ``n`` verified demos of ``task`` (class name or alias).

    ``out_dir``: write each kept demo as ``<uuid>.safetensors``; ``store``: also add them
    to this :class:`bigym.demonstrations.DemoStore`. ``workers``: processes (default: the
    CPU count, at most 8); attempts run in spawned worker processes whose numpy and OpenBLAS
    kernels are pinned (:mod:`bigym.experts.numerics`), so the files are the same on every
    machine; 1 worker runs in this process if it is already pinned. ``max_attempts``: give up after this
    many episodes (default ``3 n + 5``). ``date``: written into every demo (default: now;
    fix it to make the files reproducible). ``backend``: ``"process"`` or ``"ray"`` (Ray
    tasks with the same pinned kernels; see :mod:`bigym.scale_out`).

    The demos kept are those of the ``n`` lowest seeds that succeed, whatever the order in
    which attempts finish: attempts stop only once every lower seed has finished.
    """
    from bigym.demonstrations import Demo
    from bigym.demonstrations.player import resolve_task

    task = resolve_task(task).__name__
    max_attempts = max_attempts if max_attempts is not None else 3 * n + 5
    workers = max(1, min(workers or min(8, os.cpu_count() or 1), max_attempts))
    style_dict = style.to_dict() if style is not None else None
    attempts: list[Attempt] = []
    kept: list[Attempt] = []

    jobs = ((task, index, seed + index, style_dict, verify, date) for index in range(max_attempts))
    finished_indices: set[int] = set()
    with _Progress(progress, f"{task}: generating", n) as advance:
        for finished in run_attempts(jobs, workers, backend):
            for attempt in finished:
                attempts.append(attempt)
                finished_indices.add(attempt.index)
                if attempt.success:
                    kept.append(attempt)
                    advance()
            if _first_successes_known(kept, finished_indices, n):
                break
    attempts.sort(key=lambda a: a.index)
    # keep the n lowest seeds among the successes, so that the result does not depend on
    # which worker finished first
    kept = sorted(kept, key=lambda a: a.index)[:n]
    last = kept[-1].index if len(kept) >= n else max((a.index for a in attempts), default=-1)
    attempts = [a for a in attempts if a.index <= last]
    demos = [Demo.from_bytes(a.data, f"{task} seed {a.seed}") for a in kept]
    paths: list[Path] = []
    if out_dir is not None:
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        paths = [demo.save(out) for demo in demos]
    if store is not None:
        store.add_many(demos)
    return GenerationReport(task, n, attempts, demos, paths)


def _first_successes_known(kept: list[Attempt], finished: set[int], n: int) -> bool:
    """Are the ``n`` lowest-index successes known: ``n`` successes, and every attempt below
    the ``n``-th of them finished?"""
    if len(kept) < n:
        return False
    last = sorted(a.index for a in kept)[n - 1]
    return all(index in finished for index in range(last))


def run_attempts(jobs: Iterable[tuple], workers: int, backend: str = "process") -> Iterator[list[Attempt]]:
    """Run :func:`record_attempt` on each job's arguments, yielding the attempts that
    finished together, as they finish.

    In this process only if numpy here already runs on pinned kernels and one worker is
    asked for; otherwise in spawned workers started with them (or Ray tasks, whose workers
    get the same settings), so that the files have the same bytes on every machine.
    Closing the iterator early cancels the jobs not started.
    """
    from bigym.scale_out import check_backend, run_tasks

    check_backend(backend)
    if backend == "ray":
        for finished in run_tasks(_pinned_job, jobs, workers, env_vars=pinned_settings()):
            yield [attempt for _, attempt in finished]
        return
    if workers == 1 and numerics_pinned():
        for job in jobs:
            yield [_job(job)]
        return
    context = multiprocessing.get_context("spawn")  # spawn: numpy loads again, with the pinned kernels
    with pinned_environment(), ProcessPoolExecutor(
        max_workers=workers, mp_context=context, initializer=exit_with_parent
    ) as pool:
        queue = iter(jobs)
        running: dict = {}

        def top_up() -> None:
            while len(running) < 2 * workers:
                job = next(queue, None)
                if job is None:
                    return
                running[pool.submit(_job, job)] = job

        try:
            top_up()
            while running:
                done, _ = wait(running, return_when=FIRST_COMPLETED)
                for future in done:
                    running.pop(future)
                yield [future.result() for future in done]
                top_up()
        finally:
            for future in running:
                future.cancel()


def regenerate(
    task: str, seeds: Iterable[int], first_seed: int, date: str, workers: int, backend: str = "process"
) -> Iterator[list[Attempt]]:
    """Record the expert again on ``seeds`` of a dataset built from ``first_seed`` on, with
    its ``date``: the same bytes the dataset build kept for those seeds, without the replay
    checks and the incident watch (the shipped manifest's sha256 proves the bytes). Yields
    attempts as they finish, in lists like :func:`run_attempts`."""
    jobs = [(task, seed - first_seed, seed, None, False, date, False) for seed in seeds]
    return run_attempts(jobs, max(1, min(workers, len(jobs))), backend)


class _Progress:
    """A rich progress bar (or nothing)."""

    def __init__(self, enabled: bool, description: str, total: int) -> None:
        self.enabled, self.description, self.total = enabled, description, total

    def __enter__(self):
        if not self.enabled:
            return lambda: None
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

        self._progress = Progress(
            TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(), transient=False
        )
        self._progress.__enter__()
        bar = self._progress.add_task(self.description, total=self.total)
        return lambda: self._progress.advance(bar)

    def __exit__(self, *exc) -> None:
        if self.enabled:
            self._progress.__exit__(*exc)


def seeds_of(report: GenerationReport) -> np.ndarray:
    """The env seeds of the kept demos."""
    return np.array([d.metadata.seed for d in report.demos])


__all__ = [
    "Attempt",
    "GenerationReport",
    "close_envs",
    "failure_reason",
    "generate_demos",
    "record_attempt",
    "regenerate",
    "run_attempts",
]

"""Run a policy over a task's seed block in worker processes, and collect the records.

Every episode runs in a spawned worker process (also with one worker), each with one env
(or one vector env) and one policy built once and reset per episode. An episode depends
only on its seed and the policy, so the records are the same for any number of workers
and either vector-env mode; workers start single-threaded (BLAS, OpenMP) so that they
neither fight over the cores nor differ in how they add up.
"""

from __future__ import annotations

import math
import multiprocessing
import os
import queue as queue_module
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from pathlib import Path
from typing import Any, Callable

import gymnasium as gym
import numpy as np

from bigym.child_environment import child_environment
from bigym.worker_lifetime import exit_with_parent
from bigym.evaluation.policy import (
    PolicyFactory,
    check_portable,
    describe,
    load_factory,
    make_policy,
    reset_policy,
)
from bigym.evaluation.protocol import (
    CONTROL_FREQUENCY,
    EPISODES,
    Settings,
    fingerprint,
    official_action_mode,
    official_seeds,
    unofficial_reasons,
)
from bigym.evaluation.results import EpisodeRecord, EvaluationResult
from bigym.observations import ObservationConfig

VECTOR_MODES = ("sync", "async")
_THREAD_SETTINGS = {name: "1" for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")}
VIDEO_FPS = 30


class EvaluationError(RuntimeError):
    """An episode could not be run (the policy raised, or gave an invalid action)."""


def evaluate(
    policy: str | PolicyFactory,
    task: str,
    *,
    episodes: int | None = None,
    seeds: list[int] | None = None,
    workers: int | None = None,
    vector: str | None = None,
    envs_per_worker: int = 2,
    control_frequency: float = CONTROL_FREQUENCY,
    action_mode=None,
    observation_config: ObservationConfig | None = None,
    time_limit: float | None = None,
    task_kwargs: dict[str, Any] | None = None,
    video_dir: str | Path | None = None,
    videos: int = 3,
    progress: Callable[[EpisodeRecord], None] | None = None,
    backend: str = "process",
) -> EvaluationResult:
    """Evaluate a policy on ``task`` and return every episode's record and the summary.

    ``policy``: a factory ``factory(env) -> policy`` or its name (see
    :mod:`bigym.evaluation.policy`). ``episodes``: the first ``episodes`` seeds of the
    official block (default all :data:`~bigym.evaluation.protocol.EPISODES`); ``seeds``:
    other seeds instead (unofficial). ``workers``: processes (default: the CPU count, at
    most 8). ``vector``: ``"sync"`` or ``"async"`` to run ``envs_per_worker`` envs per
    worker in a gymnasium vector env (policies then act per sub-env; useful when one
    process should hold the policy). The remaining settings default to the protocol;
    changing them marks the result unofficial. ``video_dir``: write an mp4 of the
    external camera for the first ``videos`` episodes. ``progress``: called with each
    finished episode's record, in completion order. ``backend``: ``"process"`` (a local
    spawn-context pool) or ``"ray"`` (one Ray actor per worker, on a local instance or the
    cluster Ray is connected to: :mod:`bigym.scale_out`); the records are the same.
    """
    from bigym.scale_out import check_backend

    from bigym.demonstrations.player import resolve_task

    cls = resolve_task(task)
    if seeds is not None and episodes is not None:
        raise ValueError("give episodes (the official block) or seeds, not both")
    seed_list = list(seeds) if seeds is not None else official_seeds(EPISODES if episodes is None else episodes)
    settings = Settings(
        task=cls.__name__,
        seeds=tuple(seed_list),
        control_frequency=float(control_frequency),
        action_mode=action_mode if action_mode is not None else official_action_mode(),
        observation_config=observation_config if observation_config is not None else ObservationConfig(),
        time_limit=time_limit,
        task_kwargs=dict(task_kwargs or {}),
    )
    if vector is not None and vector not in VECTOR_MODES:
        raise ValueError(f"vector must be one of {VECTOR_MODES} or None, got {vector!r}")
    if vector is not None and not hasattr(gym.vector, "AutoresetMode"):
        raise ValueError(
            f"evaluating in a vector env needs gymnasium >= 1.1 (sub-envs reset with their own seeds), "
            f"this is {gym.__version__}: use workers instead"
        )
    if envs_per_worker < 1:
        raise ValueError(f"envs_per_worker must be at least 1, got {envs_per_worker}")
    if video_dir is not None and vector is not None:
        raise ValueError("videos are recorded without a vector env: drop vector or video_dir")
    check_portable(policy)
    check_backend(backend)
    n = len(settings.seeds)
    workers = max(1, min(workers or min(8, os.cpu_count() or 1), n))
    if vector is None:
        jobs = [(seed,) for seed in settings.seeds]  # one episode per job: idle workers take the next
    else:
        jobs = [settings.seeds[w::workers] for w in range(workers)]  # each worker's vector env takes a share
    video_seeds = tuple(settings.seeds[:videos]) if video_dir is not None else ()
    if video_dir is not None:
        Path(video_dir).mkdir(parents=True, exist_ok=True)

    started = time.perf_counter()
    records: dict[int, EpisodeRecord] = {}
    fingerprints: list[dict] = []

    def collect(worker_fingerprint: dict, job_records: list[EpisodeRecord]) -> None:
        fingerprints.append(worker_fingerprint)
        for record in job_records:
            if record.seed not in records and progress is not None:
                progress(record)
            records[record.seed] = record

    init_args = (settings, policy, vector, envs_per_worker, str(video_dir) if video_dir else None, video_seeds)
    if backend == "ray":
        _run_on_ray(jobs, workers, init_args, collect)
    else:
        _run_on_pool(jobs, workers, init_args, collect, records, progress)
    if any(f != fingerprints[0] for f in fingerprints):
        raise EvaluationError("workers evaluated different models: the fingerprints of their envs differ")
    evaluated = fingerprints[0]
    task_time_limit = cls.time_limit
    return EvaluationResult(
        task=settings.task,
        policy=describe(policy),
        episodes=[records[seed] for seed in settings.seeds],
        fingerprint=evaluated,
        unofficial_reasons=unofficial_reasons(settings, task_time_limit),
        workers=workers,
        vector=vector,
        wall_time=time.perf_counter() - started,
        backend=backend,
    )


def _run_on_pool(jobs, workers, init_args, collect, records, progress) -> None:
    """The jobs on a spawn-context process pool; episodes are reported as they finish."""
    context = multiprocessing.get_context("spawn")
    finished = context.Queue()
    initialiser = (_init_worker, (*init_args, finished))
    with child_environment(_THREAD_SETTINGS), ProcessPoolExecutor(workers, context, *initialiser) as pool:
        order = {pool.submit(_run_job, job): index for index, job in enumerate(jobs)}
        running = set(order)
        try:
            while running:
                done, running = wait(running, timeout=0.2, return_when=FIRST_COMPLETED)
                _drain(finished, records, progress)
                for future in sorted(done, key=order.get):  # the earliest job's error first, every time
                    collect(*future.result())  # re-raises a worker's EvaluationError
        except BaseException:
            for future in running:  # do not wait for episodes nobody will read
                future.cancel()
            raise


class _RayWorker:
    """One evaluation worker as a Ray actor: the pool worker's set-up, then its jobs."""

    def __init__(self, *init_args) -> None:
        _init_worker(*init_args, _NoQueue())

    def run(self, job):
        return _run_job(job)


class _NoQueue:
    """Ray actors report episodes with their job's result, not through a queue."""

    def put(self, record) -> None:
        pass


def _run_on_ray(jobs, workers, init_args, collect) -> None:
    """The jobs on ``workers`` Ray actors, each given the next job when it is free."""
    from bigym.scale_out import ensure_ray, unwrap, worker_environment

    ray = ensure_ray(num_cpus=workers)
    # an actor holds its CPU for the whole evaluation: no more actors than the cluster has CPUs
    workers = max(1, min(workers, int(ray.cluster_resources().get("CPU", workers))))
    options = {"num_cpus": 1, "runtime_env": {"env_vars": worker_environment(_THREAD_SETTINGS)}}
    actors = [ray.remote(_RayWorker).options(**options).remote(*init_args) for _ in range(workers)]
    queue = list(enumerate(jobs))
    running: dict = {}

    def give(actor) -> None:
        if queue:
            index, job = queue.pop(0)
            running[actor.run.remote(job)] = (index, actor)

    try:
        for actor in actors:
            give(actor)
        while running:
            done, _ = ray.wait(list(running), num_returns=1)
            for ref in sorted(done, key=lambda r: running[r][0]):  # the earliest job's error first
                _, actor = running.pop(ref)
                collect(*unwrap(ray, ref))  # raises a worker's EvaluationError as itself
                give(actor)
    finally:
        for actor in actors:
            ray.kill(actor)


def _drain(finished, records: dict[int, EpisodeRecord], progress) -> None:
    """Report episodes that workers finished (before their job as a whole is done)."""
    while True:
        try:
            record = finished.get_nowait()
        except queue_module.Empty:
            return
        if record.seed not in records:
            records[record.seed] = record
            if progress is not None:
                progress(record)


# ---------------------------------------------------------------------- in the worker
_worker: dict[str, Any] = {}


def make_env(settings: Settings, render_mode: str | None = None):
    """The env an evaluation with ``settings`` runs in."""
    from bigym.demonstrations.player import resolve_task

    env = resolve_task(settings.task)(
        action_mode=settings.action_mode,
        observation_config=settings.observation_config,
        control_frequency=settings.control_frequency,
        render_mode=render_mode,
        **settings.task_kwargs,
    )
    if settings.time_limit is not None:
        env.max_episode_steps = math.ceil(settings.time_limit * env.control_frequency)
    return env


def _init_worker(*args) -> None:
    exit_with_parent()
    # An initializer that raises breaks the pool with an unhelpful message: keep the error
    # and raise it from the first job instead.
    try:
        _set_up_worker(*args)
    except Exception as error:
        _worker["error"] = EvaluationError(f"setting up the policy failed: {type(error).__name__}: {error}")


def _set_up_worker(settings, policy_spec, vector, envs_per_worker, video_dir, video_seeds, finished) -> None:
    _worker.clear()
    factory = load_factory(policy_spec)
    _worker.update(settings=settings, finished=finished, video_dir=video_dir, video_seeds=video_seeds)
    if vector is None:
        env = make_env(settings, render_mode="rgb_array" if video_seeds else None)
        _worker.update(env=env, policy=make_policy(factory, env), vector=None)
        _worker["fingerprint"] = fingerprint(settings, env)
        return
    thunks = [lambda: make_env(settings)] * envs_per_worker
    if vector == "sync":
        vec = gym.vector.SyncVectorEnv(thunks, autoreset_mode=gym.vector.AutoresetMode.DISABLED)
        templates = list(vec.envs)
    else:
        vec = gym.vector.AsyncVectorEnv(thunks, autoreset_mode=gym.vector.AutoresetMode.DISABLED, context="spawn")
        # The sub-envs live in other processes: policies get a local env of the same
        # settings for its spaces and layouts; one that reads the simulator would be blind.
        templates = [make_env(settings)] * envs_per_worker
    policies = [make_policy(factory, env) for env in templates]
    if vector == "async" and any(getattr(p, "reads_simulator", False) for p in policies):
        raise ValueError(
            f"the policy {describe(policy_spec)} reads the simulator (env.data), which an async vector env keeps "
            "in its sub-processes: use vector='sync' or no vector env"
        )
    _worker.update(env=vec, policies=policies, vector=vector, fingerprint=fingerprint(settings, templates[0]))


def _run_job(seeds: tuple[int, ...]) -> tuple[dict, list[EpisodeRecord]]:
    if "error" in _worker:
        raise _worker["error"]
    if _worker["vector"] is None:
        records = [_run_episode(seed) for seed in seeds]
    else:
        records = _run_vector(list(seeds))
    return _worker["fingerprint"], records


def _outcome(terminated: bool, success: bool, info: dict) -> tuple[str, str]:
    if success:
        return "success", ""
    if "unstable" in info:
        return "unstable", str(info["unstable"])
    if terminated:
        return "failure", ""
    return "time_limit", ""


def _run_episode(seed: int) -> EpisodeRecord:
    env, policy = _worker["env"], _worker["policy"]
    writer, frame_every = _video_writer(env, seed)
    started = time.perf_counter()
    steps, success, terminated, info = 0, False, False, {}
    try:
        obs, info = env.reset(seed=seed)
        start = env.state_digest()
        reset_policy(policy, seed)
        if writer is not None:
            writer.append_data(env.render())
        while True:
            action = policy(obs)
            obs, _, terminated, truncated, info = env.step(action)
            steps += 1
            success = bool(info["is_success"])
            if writer is not None and steps % frame_every == 0:
                writer.append_data(env.render())
            if terminated or truncated:
                break
    except Exception as error:
        raise EvaluationError(f"{env.task_name} seed {seed}, step {steps}: {type(error).__name__}: {error}") from None
    finally:
        if writer is not None:
            writer.close()
    outcome, detail = _outcome(terminated, success, info)
    record = EpisodeRecord(
        seed=seed,
        success=success,
        outcome=outcome,
        steps=steps,
        sim_time=steps / env.control_frequency,
        wall_time=time.perf_counter() - started,
        detail=detail,
        start=start,
        video=str(_video_path(env, seed)) if writer is not None else None,
    )
    _worker["finished"].put(record)
    return record


def _video_path(env, seed: int) -> Path:
    return Path(_worker["video_dir"]) / f"{env.task_name}-seed{seed}.mp4"


def _video_writer(env, seed: int):
    if seed not in _worker["video_seeds"]:
        return None, 1
    import imageio.v2 as imageio

    frame_every = max(1, round(env.control_frequency / VIDEO_FPS))
    writer = imageio.get_writer(_video_path(env, seed), fps=env.control_frequency / frame_every)
    return writer, frame_every


def _run_vector(seeds: list[int]) -> list[EpisodeRecord]:
    """Episodes on a vector env: each sub-env takes the next seed when its episode ends."""
    vec, policies = _worker["env"], _worker["policies"]
    n = vec.num_envs
    queue = list(seeds)
    current: list[int | None] = [None] * n
    steps = [0] * n
    started = [0.0] * n
    space = vec.single_action_space
    idle_action = np.clip(np.zeros(space.shape, np.float32), space.low, space.high)  # for sub-envs without a seed
    records: list[EpisodeRecord] = []

    # the first episodes: one seed per sub-env (sub-envs without one replay a seed, idle)
    first = [queue.pop(0) if queue else None for _ in range(n)]
    fill = first[0]
    obs, _ = vec.reset(seed=[s if s is not None else fill for s in first])
    digests = list(vec.call("state_digest"))
    for i, seed in enumerate(first):
        current[i] = seed
        if seed is not None:
            reset_policy(policies[i], seed)
            started[i] = time.perf_counter()
    control_frequency = _worker["fingerprint"]["control_frequency"]
    while any(s is not None for s in current):
        actions = []
        for i in range(n):
            if current[i] is None:
                actions.append(idle_action)
                continue
            try:
                actions.append(np.asarray(policies[i]({k: v[i] for k, v in obs.items()}), np.float32))
            except Exception as error:
                raise EvaluationError(
                    f"{_worker['settings'].task} seed {current[i]}, step {steps[i]}: {type(error).__name__}: {error}"
                ) from None
        try:
            obs, _, terminated, truncated, info = vec.step(np.stack(actions))
        except Exception as error:
            live = [s for s in current if s is not None]
            raise EvaluationError(f"{_worker['settings'].task} seeds {live}: {type(error).__name__}: {error}") from None
        ended = np.zeros(n, bool)
        reset_seeds = list(current)
        for i in range(n):
            if not (terminated[i] or truncated[i]):
                if current[i] is not None:
                    steps[i] += 1
                continue
            ended[i] = True
            if current[i] is None:
                reset_seeds[i] = fill  # an idle sub-env that ended again: restart it, still idle
                continue
            steps[i] += 1
            sub_info = {
                k: v[i] for k, v in info.items() if not k.startswith("_") and info.get(f"_{k}", np.ones(n, bool))[i]
            }
            success = bool(sub_info.get("is_success", False))
            outcome, detail = _outcome(bool(terminated[i]), success, sub_info)
            record = EpisodeRecord(
                seed=current[i],
                success=success,
                outcome=outcome,
                steps=steps[i],
                sim_time=steps[i] / control_frequency,
                wall_time=time.perf_counter() - started[i],
                detail=detail,
                start=digests[i],
            )
            records.append(record)
            _worker["finished"].put(record)
            current[i] = queue.pop(0) if queue else None
            reset_seeds[i] = current[i] if current[i] is not None else fill
            steps[i] = 0
        if ended.any():
            obs, _ = vec.reset(seed=[s if s is not None else fill for s in reset_seeds], options={"reset_mask": ended})
            now = vec.call("state_digest")
            for i in np.flatnonzero(ended):
                if current[i] is not None:
                    digests[i] = now[i]
                    reset_policy(policies[i], current[i])
                    started[i] = time.perf_counter()
    return records

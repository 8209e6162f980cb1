"""Ray: the same parallel work as the local process pools, on a cluster.

bigym's long jobs (building the dataset, replaying demos into pixels, exporting,
evaluating over many seeds) run on a spawn-context process pool by default. With
``backend="ray"`` they run as Ray tasks or actors instead: on a local Ray instance
(``ray.init()`` with as many CPUs as workers asked for) or on a cluster, when Ray is
already initialised or ``address`` / ``$RAY_ADDRESS`` names one. Jobs and results are
the same objects either way, so the results are too.

Ray is an optional extra (``pip install "bigym[ray]"``) and is imported only here, only
when asked for. Workers get the environment variables bigym reads (MuJoCo's GL backend,
the menagerie and cache folders) plus what the caller adds (pinned numerics for the
dataset build) through Ray's ``runtime_env``, set per task so that it holds on a
cluster that someone else started too.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Iterator
from typing import Any

BACKENDS = ("process", "ray")
#: environment variables every bigym worker needs as the driver has them
FORWARDED_VARIABLES = (
    "MUJOCO_GL", "PYOPENGL_PLATFORM", "MENAGERIE_ROOT", "BIGYM_HOME", "BIGYM_DEMO_STORE", "PYTHONPATH",
)


class RayUnavailableError(RuntimeError):
    """``backend="ray"`` was asked for and Ray is not installed."""


def check_backend(backend: str) -> None:
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {', '.join(BACKENDS)}, got {backend!r}")


def import_ray():
    try:
        import ray
    except ImportError as error:
        raise RayUnavailableError(
            "the Ray backend needs Ray, an optional dependency: pip install 'bigym[ray]' (or pip install ray)"
        ) from error
    return ray


def ensure_ray(address: str | None = None, num_cpus: int | None = None):
    """Ray, initialised: connected to ``address`` (or ``$RAY_ADDRESS``) when given, else a
    local instance with ``num_cpus`` CPUs; an instance already initialised is kept."""
    ray = import_ray()
    if not ray.is_initialized():
        address = address or os.environ.get("RAY_ADDRESS") or None
        if address:
            ray.init(address=address, log_to_driver=False)
        else:
            ray.init(num_cpus=num_cpus, include_dashboard=False, log_to_driver=False)
    return ray


def worker_environment(extra: dict[str, str] | None = None) -> dict[str, str]:
    """The variables a bigym worker gets: :data:`FORWARDED_VARIABLES` as set here, and ``extra``."""
    variables = {name: os.environ[name] for name in FORWARDED_VARIABLES if name in os.environ}
    return {**variables, **(extra or {})}


def run_tasks(
    function: Callable[[Any], Any],
    jobs: Iterable[Any],
    workers: int,
    *,
    env_vars: dict[str, str] | None = None,
    catch: tuple[type[BaseException], ...] = (),
) -> Iterator[list[tuple[int, Any]]]:
    """Run ``function(job)`` for every job as Ray tasks, at most ``workers`` at a time.

    Yields ``(index, result)`` pairs of the tasks that finished together, as they finish.
    An exception of a ``catch`` type raised by a task is yielded in its result's place;
    any other is raised here, unwrapped from Ray's error. Closing the iterator early
    cancels the tasks still pending.
    """
    ray = ensure_ray(num_cpus=workers)
    remote = ray.remote(num_cpus=1)(function).options(runtime_env={"env_vars": worker_environment(env_vars)})
    queue = enumerate(jobs)
    running: dict = {}

    def top_up() -> None:
        while len(running) < workers:
            item = next(queue, None)
            if item is None:
                return
            index, job = item
            running[remote.remote(job)] = index

    try:
        top_up()
        while running:
            done, _ = ray.wait(list(running), num_returns=1)
            finished = []
            for ref in done:
                finished.append((running.pop(ref), unwrap(ray, ref, catch)))
            yield finished
            top_up()
    finally:
        for ref in running:
            ray.cancel(ref)


def unwrap(ray, ref, catch: tuple[type[BaseException], ...] = ()) -> Any:
    """``ray.get(ref)``; a task's own exception raised as itself (or returned, if of a ``catch`` type)."""
    try:
        return ray.get(ref)
    except ray.exceptions.RayTaskError as error:
        cause = error.cause if isinstance(getattr(error, "cause", None), BaseException) else None
        if cause is None:
            raise
        if catch and isinstance(cause, catch):
            return cause
        raise cause from None


__all__ = [
    "BACKENDS",
    "FORWARDED_VARIABLES",
    "RayUnavailableError",
    "check_backend",
    "ensure_ray",
    "import_ray",
    "run_tasks",
    "unwrap",
    "worker_environment",
]

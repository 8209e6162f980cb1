"""Completing a local store with a task's slice of a shipped dataset, on demand.

When a store is asked for demos of a task it lacks and the dataset version it serves is
shipped with a recipe (:mod:`bigym.demonstrations.datasets`), :func:`provide_task` puts
exactly that task's files into the store, the same bytes the shipped manifest lists:
downloaded from a hosted copy when one is configured (``BIGYM_DATASET_MIRROR`` or
``DemoStore(mirror=...)``), else rebuilt on this machine. Every file is checked against
the shipped manifest (size and sha256) before it is kept.

Many processes, one store: the work on a task happens under a lock file per task in the
store's version folder. A process that finds the lock held waits, then finds the slice
complete and builds nothing. Each file is written atomically as soon as it is made, and
the manifest is updated once at the end: an interrupted build leaves complete files and
no half-written one, and the next call builds only what is missing.
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

from bigym.demonstrations.atomic import atomic_write, sweep_partial_files
from bigym.demonstrations.datasets import DatasetRecipe, find_recipe
from bigym.demonstrations.demo import sha256_file
from bigym.demonstrations.errors import DemoBuildError, DemoChecksumError, DemoError
from bigym.demonstrations.locks import file_lock
from bigym.demonstrations.store import DemoStore, ManifestEntry, task_variant, verify_bytes

MIRROR_VARIABLE = "BIGYM_DATASET_MIRROR"


@dataclass
class ProvisionReport:
    """What :func:`provide_task` did for one task."""

    task: str
    version: str
    expected: int  # files of the task in the shipped manifest
    reused: int  # already complete in the store
    made: int  # built or downloaded now
    source: str  # "rebuilt on this machine", "downloaded from <url>" or "none needed"
    seconds: float

    def summary(self) -> str:
        if not self.made:
            return f"{self.task}: all {self.expected} demos of dataset {self.version} already in the store"
        return (
            f"{self.task}: {self.made} of {self.expected} demos of dataset {self.version} {self.source} "
            f"in {self.seconds:.0f} s ({self.reused} already there)"
        )


def shipped_entries(version: str, task: str, task_kwargs: dict | None = None) -> list[ManifestEntry]:
    """The shipped manifest's entries of ``task`` (empty when no recipe covers it, or
    none of its demos is of the variant ``task_kwargs``)."""
    recipe = find_recipe(version)
    if recipe is None:
        return []
    entries = [e for e in recipe.manifest().entries if e.task == task]
    if task_kwargs is not None:
        wanted = task_variant(task, task_kwargs)
        if not any(task_variant(task, e.task_kwargs) == wanted for e in entries):
            return []
    return entries


def shipped_tasks(version: str) -> list[str]:
    """The tasks the shipped dataset ``version`` has demos of (none without a recipe)."""
    recipe = find_recipe(version)
    return sorted({e.task for e in recipe.manifest().entries}) if recipe is not None else []


def provide_task(
    store: DemoStore,
    task: str,
    *,
    mirror: str | None = None,
    workers: int | None = None,
    progress: bool = True,
    rebuild: Iterable[str] = (),
) -> ProvisionReport | None:
    """Make ``store`` (a local one) hold ``task``'s slice of its shipped dataset version.

    Returns None when no shipped dataset covers the task (nothing to do), else what was
    done. ``rebuild``: paths (relative to the version folder) to make again even if
    present, e.g. files found damaged. Raises :class:`DemoChecksumError` when a hosted
    copy serves other bytes and :class:`DemoBuildError` when this machine rebuilds other
    bytes (another MuJoCo version, say); nothing of such a file is kept.
    """
    if not store.is_local:
        return None
    recipe = find_recipe(store.version)
    expected = shipped_entries(store.version, task)
    if recipe is None or not expected:
        return None
    start = time.perf_counter()
    folder = store.version_folder
    waiting = f"waiting for another process that is providing {task} in {store.url}"
    with file_lock(folder / f".provide-{task}.lock", on_wait=lambda: notify(waiting)):
        for path in rebuild:
            (folder / path).unlink(missing_ok=True)
        sweep_partial_files(folder / task)
        missing = [e for e in expected if not file_matches(folder / e.path, e)]
        source = "none needed"
        if missing:
            workers = workers or min(8, os.cpu_count() or 1)
            mirror = mirror if mirror is not None else os.environ.get(MIRROR_VARIABLE) or None
            if mirror:
                source = f"downloaded from {mirror}"
                notify(f"{store.url} has no {task} demos: downloading its {len(missing)} files of dataset "
                     f"{store.version} from {mirror}")  # fmt: skip
                files = _download(mirror, store.version, missing)
            else:
                source = "rebuilt on this machine"
                notify(_build_announcement(recipe, store, task, missing, workers))
                files = recipe.build(task, missing, workers)
            _keep(files, missing, folder, mirror, progress, f"{task}: {'downloading' if mirror else 'building'}")
        _add_to_manifest(store, expected)
    return ProvisionReport(
        task, store.version, len(expected), len(expected) - len(missing), len(missing), source,
        time.perf_counter() - start,
    )  # fmt: skip


def file_matches(path: Path, entry: ManifestEntry) -> bool:
    """``path`` holds ``entry``'s file: its size and sha256."""
    return path.is_file() and path.stat().st_size == entry.size and sha256_file(path) == entry.sha256


def _keep(files: Iterator[tuple[ManifestEntry, bytes]], missing: list[ManifestEntry], folder: Path,
          mirror: str | None, progress: bool, description: str) -> None:  # fmt: skip
    """Check each made file against its shipped entry and write it atomically."""
    from bigym.demonstrations.player import progress_bar

    wanted = {e.path: e for e in missing}
    with progress_bar(progress, description, len(missing)) as advance:
        for entry, data in files:
            shipped = wanted.pop(entry.path, None)
            if shipped is None:
                raise DemoBuildError(f"the dataset recipe made {entry.path}, which was not asked for")
            try:
                verify_bytes(data, shipped, entry.path)
            except DemoChecksumError as error:
                if mirror:
                    raise DemoChecksumError(f"the hosted copy {mirror} serves other bytes: {error}") from error
                raise DemoBuildError(_rebuilt_differently(shipped, error)) from error
            atomic_write(folder / shipped.path, data)
            advance()
    if wanted:
        raise DemoBuildError(f"the dataset recipe did not make {len(wanted)} files, e.g. {next(iter(wanted))}")


def _rebuilt_differently(entry: ManifestEntry, error: DemoError) -> str:
    import mujoco

    import bigym

    return (
        f"{entry.path} was rebuilt with other bytes than the shipped manifest says ({error}). The dataset was "
        f"made with bigym {entry.bigym_version} and MuJoCo {entry.mujoco_version}; this machine runs bigym "
        f"{bigym.__version__} and MuJoCo {mujoco.__version__}. Install those versions, or set {MIRROR_VARIABLE} "
        "to a hosted copy of the dataset"
    )


def _download(mirror: str, version: str, entries: list[ManifestEntry]) -> Iterator[tuple[ManifestEntry, bytes]]:
    import fsspec

    try:
        fs, root = fsspec.core.url_to_fs(mirror.rstrip("/"))
    except (ImportError, ValueError) as error:
        raise DemoError(f"cannot open the hosted dataset copy {mirror}: {error}") from error
    for entry in entries:
        remote = "/".join([root.rstrip("/"), version, entry.path])
        try:
            yield entry, fs.cat_file(remote)
        except FileNotFoundError as error:
            raise DemoError(f"the hosted copy {mirror} lacks {version}/{entry.path}") from error
        except Exception as error:  # network errors of every fsspec backend
            raise DemoError(f"cannot download {remote}: {error}") from error


def _build_announcement(recipe: DatasetRecipe, store: DemoStore, task: str, missing: list, workers: int) -> str:
    seconds = recipe.estimate_seconds(task, missing, workers)
    about = f"about {_duration(seconds)} with {workers} processes" if seconds else f"{workers} processes"
    return (
        f"{store.url} has no {task} demos: building its {len(missing)} files of dataset {store.version} on this "
        f"machine ({about}); set {MIRROR_VARIABLE} to download a hosted copy instead"
    )


def _duration(seconds: float) -> str:
    if seconds < 90:
        return f"{max(5, round(seconds / 5) * 5):.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def _add_to_manifest(store: DemoStore, expected: list[ManifestEntry]) -> None:
    """Put the shipped entries into the store's manifest (replacing any of the same uuid or path)."""
    held = {(e.path, e.sha256, e.size, e.uuid) for e in store.manifest(refresh=True).entries}
    if all((e.path, e.sha256, e.size, e.uuid) in held for e in expected):
        return
    uuids, paths = {e.uuid for e in expected}, {e.path for e in expected}
    with store._writing() as manifest:
        kept = [e for e in manifest.entries if e.uuid not in uuids and e.path not in paths]
        manifest.entries = kept + list(expected)


def notify(message: str) -> None:
    print(f"bigym: {message}", file=sys.stderr, flush=True)


__all__ = [
    "MIRROR_VARIABLE",
    "ProvisionReport",
    "file_matches",
    "notify",
    "provide_task",
    "shipped_entries",
    "shipped_tasks",
]

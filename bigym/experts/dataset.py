"""The shipped expert dataset: its recipe, how to rebuild it, and how to check a copy.

The demo files are not kept in git. What is kept is the recipe below (tasks, demos per
task, first seed, date) and the version's manifest (``manifests/<version>.json``: every
file's path, size and sha256). ``bigym demos dataset build OUT`` regenerates the whole
version into ``OUT`` (a folder a :class:`~bigym.demonstrations.DemoStore` serves) and
compares it with that manifest; ``bigym demos dataset check URL`` compares any copy,
local or downloaded, without regenerating.

Rebuilding gives the same bytes because everything that enters a demo file is fixed:
the seeds, the demonstrator's draws (seeded), the uuid (derived from task, seed, style
and bigym version), the date (the recipe's), the safetensors header (sorted keys) and
the actions (rounded to a grid, so last-bit differences in linear algebra between CPUs
do not show). The MuJoCo version and the bigym version are part of the files: another
version of either gives other files, and the check says so.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path

from bigym.demonstrations.store import DATASET_VERSION  # the version this bigym ships a manifest for

#: the date written into every demo of the version
DATASET_DATE = "2026-11-23T00:00:00Z"
DEMOS_PER_TASK = 50
#: attempts per demo (and spare ones) a task's build may spend before it gives up: the
#: hardest experts keep about one attempt in two, and a build that stops a few demos short
#: wastes the hour
ATTEMPTS_PER_DEMO = 5
SPARE_ATTEMPTS = 5
FIRST_SEED = 0
DATASET_TASKS = (
    "ReachTargetSingle",
    "ReachTargetMultiModal",
    "ReachTargetDual",
    "DishwasherOpen",
    "DishwasherClose",
    "DishwasherOpenTrays",
    "DishwasherCloseTrays",
    "DrawerTopOpen",
    "DrawerTopClose",
    "DrawersOpenAll",
    "DrawersCloseAll",
    "WallCupboardOpen",
    "WallCupboardClose",
    "CupboardsOpenAll",
    "CupboardsCloseAll",
    "StackBlocks",
    "MovePlate",
    "MoveTwoPlates",
    "SaucepanToHob",
    "StoreKitchenware",
    "PickBox",
    "StoreBox",
    "FlipCup",
    "FlipCutlery",
    "StoreGroceriesLower",
    "DishwasherUnloadCutlery",
    "DishwasherLoadCutlery",
    "DishwasherUnloadCutleryLong",
    "DishwasherUnloadPlates",
    "DishwasherLoadPlates",
    "DishwasherLoadCups",
    "DishwasherUnloadCups",
    "PutCups",
    "TakeCups",
    "StoreGroceriesUpper",
    "SandwichRemove",
    "SandwichToast",
    "DishwasherUnloadPlatesLong",
    "DishwasherUnloadCupsLong",
    "SandwichFlip",
)
MANIFEST_DIR = Path(__file__).parent / "manifests"
BUILD_RECORD_NAME = "build.json"  # beside a built store's manifest: how each task's build went


def shipped_manifest_path(version: str = DATASET_VERSION) -> Path:
    return MANIFEST_DIR / f"{version}.json"


@dataclass
class DatasetCheck:
    """How a copy of the dataset compares with the shipped manifest (by path, size, sha256)."""

    version: str
    expected: int
    matching: list[str] = field(default_factory=list)
    missing: list[str] = field(default_factory=list)
    different: list[str] = field(default_factory=list)
    extra: list[str] = field(default_factory=list)

    @property
    def identical(self) -> bool:
        return not (self.missing or self.different or self.extra) and len(self.matching) == self.expected

    def summary(self) -> str:
        if self.identical:
            return f"dataset {self.version}: all {self.expected} demo files identical to the shipped manifest"
        parts = [f"dataset {self.version}: {len(self.matching)} of {self.expected} demo files identical"]
        for label, items in (("missing", self.missing), ("different", self.different), ("not in the manifest", self.extra)):
            if items:
                shown = ", ".join(items[:5]) + (f" and {len(items) - 5} more" if len(items) > 5 else "")
                parts.append(f"{len(items)} {label}: {shown}")
        return "; ".join(parts)


def _file_table(manifest_json: str) -> dict[str, tuple[int, str]]:
    payload = json.loads(manifest_json)
    return {item["path"]: (int(item["size"]), item["sha256"]) for item in payload.get("demos", [])}


def compare_manifests(expected_json: str, actual_json: str, tasks: tuple[str, ...] | None = None) -> DatasetCheck:
    """Compare two store manifests file by file; ``tasks`` limits both to those tasks."""
    expected, actual = _file_table(expected_json), _file_table(actual_json)
    if tasks is not None:
        wanted = tuple(f"{task}/" for task in tasks)
        expected = {p: v for p, v in expected.items() if p.startswith(wanted)}
        actual = {p: v for p, v in actual.items() if p.startswith(wanted)}
    check = DatasetCheck(json.loads(expected_json).get("version", "?"), len(expected))
    for path, value in sorted(expected.items()):
        if path not in actual:
            check.missing.append(path)
        elif actual[path] != value:
            check.different.append(path)
        else:
            check.matching.append(path)
    check.extra = sorted(set(actual) - set(expected))
    return check


def check_dataset(store, tasks: tuple[str, ...] | None = None, version: str = DATASET_VERSION) -> DatasetCheck:
    """Compare ``store`` (a DemoStore, URL or folder) with the shipped manifest of ``version``."""
    from bigym.demonstrations.store import DemoStore

    path = shipped_manifest_path(version)
    if not path.is_file():
        raise FileNotFoundError(f"this bigym ships no manifest for dataset version {version!r} ({path})")
    if not isinstance(store, DemoStore):
        store = DemoStore(store, version=version)
    return compare_manifests(path.read_text(), store.manifest(refresh=True).to_json(), tasks)


def build_record_path(version: str = DATASET_VERSION) -> Path:
    """The shipped build record: per task, attempts, generator success, failure reasons, time."""
    return MANIFEST_DIR / f"{version}-build.json"


def _local_record_path(out: Path) -> Path:
    return Path(out) / DATASET_VERSION / BUILD_RECORD_NAME


def _read_record(path: Path) -> dict:
    return json.loads(path.read_text()) if path.is_file() else {"version": DATASET_VERSION, "tasks": {}}


def _write_record(path: Path, record: dict) -> None:
    from bigym.demonstrations.atomic import atomic_write

    record["tasks"] = dict(sorted(record["tasks"].items()))
    atomic_write(path, (json.dumps(record, indent=1, sort_keys=True) + "\n").encode())


def _bigym_version() -> str:
    from bigym import __version__

    return __version__


def task_complete(out: Path | str, task: str, per_task: int = DEMOS_PER_TASK, against_shipped: bool = True) -> bool:
    """The store folder ``out`` already holds ``task``'s slice of the version: exactly the
    files the shipped manifest lists for it (or, for a task the manifest does not list yet,
    the files a build recorded for it in ``out``), each present with its size and sha256.

    ``against_shipped=False`` (maintainers rebuilding the version, whose shipped manifest is
    about to be replaced): the files a build of this bigym version recorded in ``out``."""
    from bigym.demonstrations.provision import file_matches
    from bigym.demonstrations.store import DemoStore

    store = DemoStore(out, version=DATASET_VERSION)
    entries = store.entries(task=task)
    held = {(e.path, e.size, e.sha256) for e in entries}
    if len(held) != per_task:
        return False
    shipped = shipped_manifest_path()
    expected = set()
    if not against_shipped:
        recorded = _read_record(_local_record_path(Path(out))).get("tasks", {}).get(task, {})
        if recorded.get("bigym_version") != _bigym_version():
            return False
    elif shipped.is_file():
        table = _file_table(shipped.read_text())
        expected = {(p, size, sha) for p, (size, sha) in table.items() if p.startswith(f"{task}/")}
    if expected:
        if held != expected:
            return False
    else:
        recorded = _read_record(_local_record_path(Path(out))).get("tasks", {}).get(task, {})
        if sorted(recorded.get("files", [])) != sorted(p for p, _, _ in held):
            return False
    folder = Path(out) / DATASET_VERSION
    return all(file_matches(folder / e.path, e) for e in entries)


def build_dataset(
    out: Path | str,
    tasks: tuple[str, ...] | None = None,
    workers: int | None = None,
    progress: bool = True,
    per_task: int = DEMOS_PER_TASK,
    on_task=None,
    resume: bool = True,
    backend: str = "process",
    against_shipped: bool = True,
) -> list:
    """Regenerate the dataset version into the store folder ``out``, one task at a time.

    Each task is generated, checked and added before the next starts, so an interrupted
    build loses at most the task in progress; with ``resume`` a task whose files are
    already complete in ``out`` (see :func:`task_complete`, which ``against_shipped`` is
    passed to) is skipped. Every built task's
    figures (attempts, generator success, failure reasons, seconds) go into
    ``out/<version>/build.json`` as it finishes. Returns the
    :class:`~bigym.experts.generate.GenerationReport` of every task built;
    ``on_task(task, report_or_None)`` is called as each task finishes or is skipped.
    ``backend``: ``"process"`` (a local pool) or ``"ray"`` (:mod:`bigym.scale_out`); the
    files are the same either way.
    """
    import platform
    import time

    from bigym.demonstrations.store import DemoStore
    from bigym.experts.generate import generate_demos

    store = DemoStore(out, version=DATASET_VERSION)
    record_path = _local_record_path(Path(out))
    reports = []
    for task in tasks or DATASET_TASKS:
        if resume and task_complete(out, task, per_task, against_shipped):
            if on_task is not None:
                on_task(task, None)
            continue
        start = time.perf_counter()
        report = generate_demos(
            task,
            n=per_task,
            seed=FIRST_SEED,
            workers=workers,
            progress=progress,
            date=DATASET_DATE,
            backend=backend,
            max_attempts=ATTEMPTS_PER_DEMO * per_task + SPARE_ATTEMPTS,
        )
        seconds = time.perf_counter() - start
        if report.kept < per_task:
            raise RuntimeError(f"{report.summary()}\nthe dataset needs {per_task} demos of {task}")
        old = [e.uuid for e in store.entries(task=task)]
        if old:
            store.remove(old)
        entries = store.add_many(report.demos)
        record = _read_record(record_path)
        record["tasks"][task] = {
            "demos": report.kept,
            "attempts": len(report.attempts),
            "generator_success_rate": round(report.success_rate, 4),
            "failures": report.failure_summary(),
            "failed_seeds": [seed for seed, _ in report.failures],
            "build_seconds": round(seconds, 1),
            "workers": workers or min(8, os.cpu_count() or 1),
            "machine": f"{platform.machine()}, {os.cpu_count()} CPUs",
            "bigym_version": _bigym_version(),
            "demo_seconds": round(sum(d.duration for d in report.demos), 1),
            "files": sorted(e.path for e in entries),
        }
        _write_record(record_path, record)
        reports.append(report)
        if on_task is not None:
            on_task(task, report)
    return reports


def write_shipped_manifest(out: Path | str, tasks: tuple[str, ...] | None = None, version: str = DATASET_VERSION) -> Path:
    """Maintainers cutting a version: merge ``tasks``' entries (default: every task it holds)
    from the manifest of the store folder ``out`` into the shipped manifest, and their build
    figures into the shipped build record; other tasks' entries are kept as they were."""
    from bigym.demonstrations.store import DemoStore, Manifest

    store = DemoStore(out, version=version)
    built = store.manifest(refresh=True)
    tasks = tuple(tasks) if tasks else tuple(sorted({e.task for e in built.entries}))
    path = shipped_manifest_path(version)
    kept = Manifest.from_json(path.read_text(), str(path)).entries if path.is_file() else []
    entries = [e for e in kept if e.task not in tasks] + [e for e in built.entries if e.task in tasks]
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(Manifest(version, entries).to_json() + "\n")
    local = _read_record(_local_record_path(Path(out)))
    shipped = _read_record(build_record_path(version))
    for task in tasks:
        if task in local["tasks"]:
            figures = dict(local["tasks"][task])
            figures.pop("files", None)  # the manifest lists them
            shipped["tasks"][task] = figures
    _write_record(build_record_path(version), shipped)
    return path


TABLE_HEADER = (
    "| task | generator success | build min | distinct plans (most common) | hand split L / R / both "
    "| duration s, cv | straightness | bell corr. | LDLJ |\n|---|---|---|---|---|---|---|---|---|"
)


def dataset_table(store, tasks: tuple[str, ...] | None = None, progress: bool = True) -> str:
    """The README's dataset table: per task, the shipped build record's generator success
    and build time, and the figures of :func:`~bigym.experts.stats.demo_stats` on the
    store's demos next to the plain controller's on the same seeds (in brackets)."""
    from bigym.demonstrations.store import DemoStore
    from bigym.experts.stats import demo_stats
    from bigym.task_docs import snake_case

    if not isinstance(store, DemoStore):
        store = DemoStore(store, version=DATASET_VERSION)
    record = _read_record(build_record_path()).get("tasks", {})
    lines = [TABLE_HEADER]
    for task in tasks or DATASET_TASKS:
        entries = sorted(store.entries(task=task), key=lambda e: e.seed or 0)
        if not entries:
            continue
        demos = [store.load(e) for e in entries]
        report = demo_stats(task, demos=demos, progress=progress)
        d, p = report.demos, report.plain
        built = record.get(task, {})
        success = f"{100 * built['generator_success_rate']:.0f}%" if built else "-"
        minutes = f"{built['build_seconds'] / 60:.1f}" if built else "-"
        split = " / ".join(f"{100 * d.hand_split.get(k, 0.0):.0f}" for k in ("left", "right", "both"))
        lines.append(
            f"| {snake_case(task)} | {success} | {minutes} | {d.plans} ({100 * d.top_plan_share:.0f}%) | {split} % "
            f"| {d.duration_mean:.1f}, {d.duration_cv:.2f} ({p.duration_mean:.1f}, {p.duration_cv:.2f}) "
            f"| {d.straightness:.2f} ({p.straightness:.2f}) | {d.bell_correlation:.2f} ({p.bell_correlation:.2f}) "
            f"| {d.ldlj:.1f} ({p.ldlj:.1f}) |"
        )
    return "\n".join(lines)


#: share of a dataset build's time spent recording (the rest replays every demo at four
#: rates): recording alone took 17-27% of record-and-verify on reach, drawer and plate seeds
RECORD_SHARE = 0.25


class ShippedDataset:
    """The recipe of the dataset version this bigym ships, for demos on demand.

    Found by the demonstration system through the ``bigym.datasets`` entry point (see
    :mod:`bigym.demonstrations.datasets`). It rebuilds a task's files by recording the
    expert again on exactly the seeds the manifest lists, with the version's date: the
    build's failed seeds and its replay checks are skipped, the sha256 of every file is
    checked against the manifest by the caller.
    """

    version = DATASET_VERSION

    def __init__(self) -> None:
        self._manifest = None

    def manifest(self):
        from bigym.demonstrations.store import Manifest

        if self._manifest is None:
            path = shipped_manifest_path(self.version)
            self._manifest = Manifest.from_json(path.read_text(), str(path))
        return self._manifest

    def estimate_seconds(self, task: str, entries: list, workers: int) -> float | None:
        """From the shipped build record: its seconds per attempt, times the recording share."""
        built = _read_record(build_record_path(self.version)).get("tasks", {}).get(task)
        if not built or not built.get("attempts"):
            return None
        per_attempt = built["build_seconds"] * built.get("workers", 1) / built["attempts"]
        return per_attempt * RECORD_SHARE * len(entries) / max(1, min(workers, len(entries)))

    def build(self, task: str, entries: list, workers: int):
        from bigym.demonstrations.errors import DemoBuildError
        from bigym.experts.generate import regenerate

        by_seed = {entry.seed: entry for entry in entries}
        if None in by_seed or len(by_seed) != len(entries):
            raise DemoBuildError(f"the shipped manifest does not give one seed per {task} demo")
        for finished in regenerate(task, sorted(by_seed), FIRST_SEED, DATASET_DATE, workers):
            for attempt in finished:
                entry = by_seed[attempt.seed]
                if not attempt.success:
                    raise DemoBuildError(
                        f"{entry.path} (seed {attempt.seed}) did not succeed when rebuilt: {attempt.reason}"
                    )
                yield entry, attempt.data


def dataset_size(version: str = DATASET_VERSION) -> str:
    """One line on the shipped manifest's size: demos, bytes, hours, bytes per demo-second."""
    demos = json.loads(shipped_manifest_path(version).read_text())["demos"]
    size = sum(entry["size"] for entry in demos)
    seconds = sum(entry["num_steps"] / entry["frequency"] for entry in demos)
    return (
        f"dataset {version}: {len(demos)} demos, {size / 1e6:.0f} MB, {seconds / 3600:.1f} h of demonstration, "
        f"{size / seconds / 1000:.1f} KB per demo-second"
    )


__all__ = [
    "DATASET_DATE",
    "DATASET_TASKS",
    "DATASET_VERSION",
    "DEMOS_PER_TASK",
    "DatasetCheck",
    "ShippedDataset",
    "build_dataset",
    "build_record_path",
    "check_dataset",
    "compare_manifests",
    "dataset_size",
    "dataset_table",
    "shipped_manifest_path",
    "task_complete",
    "write_shipped_manifest",
]

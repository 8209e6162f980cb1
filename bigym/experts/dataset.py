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
from dataclasses import dataclass, field
from pathlib import Path

#: the dataset version this bigym ships a manifest for
DATASET_VERSION = "v1"
#: the date written into every demo of the version
DATASET_DATE = "2026-11-23T00:00:00Z"
DEMOS_PER_TASK = 50
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
)
MANIFEST_DIR = Path(__file__).parent / "manifests"


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


def build_dataset(
    out: Path | str,
    tasks: tuple[str, ...] | None = None,
    workers: int | None = None,
    progress: bool = True,
    per_task: int = DEMOS_PER_TASK,
    on_task=None,
) -> list:
    """Regenerate the dataset version into the store folder ``out`` (task by task).

    Returns the :class:`~bigym.experts.generate.GenerationReport` of every task;
    ``on_task(report)`` is called as each task finishes. A task already complete in
    ``out`` (``per_task`` demos with the expected uuids) is generated again all the same:
    the files are replaced by identical ones.
    """
    from bigym.demonstrations.store import DemoStore
    from bigym.experts.generate import generate_demos

    store = DemoStore(out, version=DATASET_VERSION)
    reports = []
    for task in tasks or DATASET_TASKS:
        report = generate_demos(
            task, n=per_task, seed=FIRST_SEED, workers=workers, progress=progress, date=DATASET_DATE
        )
        if report.kept < per_task:
            raise RuntimeError(f"{report.summary()}\nthe dataset needs {per_task} demos of {task}")
        old = [e.uuid for e in store.entries(task=task)]
        if old:
            store.remove(old)
        store.add_many(report.demos)
        reports.append(report)
        if on_task is not None:
            on_task(report)
    return reports


def write_shipped_manifest(store, version: str = DATASET_VERSION) -> Path:
    """Copy ``store``'s manifest into the package (for maintainers cutting a version)."""
    from bigym.demonstrations.store import DemoStore

    if not isinstance(store, DemoStore):
        store = DemoStore(store, version=version)
    path = shipped_manifest_path(version)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(store.manifest(refresh=True).to_json() + "\n")
    return path


__all__ = [
    "DATASET_DATE",
    "DATASET_TASKS",
    "DATASET_VERSION",
    "DEMOS_PER_TASK",
    "DatasetCheck",
    "build_dataset",
    "check_dataset",
    "compare_manifests",
    "shipped_manifest_path",
    "write_shipped_manifest",
]

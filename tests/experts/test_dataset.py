"""The expert dataset: byte-reproducible demos, the generate/stats/dataset commands, the
shipped manifest and the check of a copy against it."""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys

import pytest
from typer.testing import CliRunner

import bigym.cli.demos as demos_cli
from bigym.cli import app
from bigym.demonstrations import Demo, DemoStore
from bigym.experts.dataset import (
    ATTEMPTS_PER_DEMO,
    DATASET_DATE,
    DATASET_TASKS,
    DATASET_VERSION,
    DEMOS_PER_TASK,
    SPARE_ATTEMPTS,
    build_dataset,
    build_record_path,
    check_dataset,
    compare_manifests,
    shipped_manifest_path,
)
from bigym.experts.generate import generate_demos

runner = CliRunner()

_RECORD = """
import hashlib
from bigym.experts.generate import record_attempt
attempt = record_attempt("ReachTargetDual", 0, 4, date="2026-01-01T00:00:00Z")
print(attempt.success, hashlib.sha256(attempt.data).hexdigest())
"""


def run(*args):
    return runner.invoke(app, ["demos", *map(str, args)])


@pytest.fixture(autouse=True)
def wide_console(monkeypatch):
    monkeypatch.setattr(demos_cli.console, "width", 250)
    monkeypatch.setattr(demos_cli.err_console, "width", 250)


def test_an_expert_demo_has_the_same_bytes_in_every_process():
    """safetensors writes its metadata in hash order, which changes per process; the demo
    files must not (the dataset's checksums are checked on regeneration)."""
    outputs = set()
    for hash_seed in ("1", "2"):
        env = {**os.environ, "PYTHONHASHSEED": hash_seed}
        done = subprocess.run([sys.executable, "-c", _RECORD], env=env, capture_output=True, text=True, check=True)
        outputs.add(done.stdout.strip().splitlines()[-1])
    assert len(outputs) == 1, outputs
    success, _ = outputs.pop().split()
    assert success == "True"


def test_demo_header_keys_are_sorted_and_the_file_still_loads(tmp_path):
    import safetensors.numpy

    from bigym.experts.generate import record_attempt

    attempt = record_attempt("ReachTargetDual", 0, 5, date="2026-01-01T00:00:00Z", verify=False)
    data = attempt.data
    size = int.from_bytes(data[:8], "little")
    assert size % 8 == 0
    header = json.loads(data[8 : 8 + size])
    assert list(header) == sorted(header)
    assert list(header["__metadata__"]) == sorted(header["__metadata__"])
    assert set(safetensors.numpy.load(data)) == {
        "actions_packed", "initial_state", "checkpoint_steps", "checkpoint_states_packed"
    }  # fmt: skip
    # The expert's actions lie on its 2**-17 grid: packed as integers.
    packing = json.loads(header["__metadata__"]["packing"])
    assert packing["actions"]["codec"] == "grid-delta2-bz2" and packing["actions"]["grid_bits"] == 17
    demo = Demo.from_bytes(data)
    assert demo.to_bytes() == data  # a load/save round trip changes nothing
    assert demo.metadata.date == "2026-01-01T00:00:00Z"


def test_generate_command_fills_a_store_and_stats_measures_it(tmp_path):
    store = tmp_path / "store"
    result = run("generate", "reach_target_dual", "-n", 2, "--workers", 1, "--store", store)
    assert result.exit_code == 0, result.output
    assert "kept 2/2" in result.output and "generator success rate" in result.output
    entries = DemoStore(store).entries(task="ReachTargetDual")
    assert len(entries) == 2 and all(e.success and e.source == "expert" for e in entries)
    plot, figures = tmp_path / "paths.png", tmp_path / "figures.json"
    result = run("stats", "ReachTargetDual", "-n", 2, "--store", store, "--plot", plot, "--json", figures)
    assert result.exit_code == 0, result.output
    assert "plain controller" in result.output and "path length / straight distance" in result.output
    assert plot.stat().st_size > 1000
    payload = json.loads(figures.read_text())
    assert payload["demos"]["count"] == 2 and payload["plain"]["count"] == 2
    assert payload["demos"]["hand_split"]["both"] == 1.0  # the dual task uses both hands


def test_generate_and_stats_fail_clearly(tmp_path, monkeypatch):
    import bigym.experts

    # every task has one now: as if this had none (a copy, so that the registry's order,
    # which tables follow, stays as it is for the tests after this one)
    without = {task: path for task, path in bigym.experts.EXPERTS.items() if task != "SandwichFlip"}
    monkeypatch.setattr(bigym.experts, "EXPERTS", without)
    result = run("generate", "SandwichFlip", "-n", 1, "--store", tmp_path / "s")
    assert result.exit_code == 1 and "no expert for SandwichFlip" in result.output
    result = run("generate", "NoSuchTask", "--store", tmp_path / "s")
    assert result.exit_code == 1 and "unknown task" in result.output
    # an expert, but no shipped demos to build (StoreBox has none in v1)
    result = run("stats", "StoreBox", "--store", tmp_path / "empty", "--version", "v1")
    assert result.exit_code == 1 and "--source fresh" in result.output
    result = run("stats", "ReachTargetSingle", "-n", 2, "--store", tmp_path / "empty")  # built on demand
    assert result.exit_code == 0 and "building its 50 files" in result.output, result.output
    assert "log dimensionless jerk" in result.output


def test_shipped_manifest_lists_fifty_demos_of_each_task():
    payload = json.loads(shipped_manifest_path().read_text())
    assert payload["version"] == DATASET_VERSION
    per_task: dict[str, int] = {}
    for entry in payload["demos"]:
        assert entry["success"] is True and entry["source"] == "expert" and entry["frequency"] == 500
        assert entry["action_mode"]["absolute"] is True and entry["action_mode"]["floating_base"] is True
        assert len(entry["sha256"]) == 64 and entry["size"] > 0
        per_task[entry["task"]] = per_task.get(entry["task"], 0) + 1
    assert per_task == {task: DEMOS_PER_TASK for task in DATASET_TASKS}


def test_shipped_demos_are_light_and_every_task_has_its_build_figures():
    """Issue 10's target: at most 18 KB per demo-second over the whole shipped manifest;
    and the build record says, per task, how the generator did and how long it took."""
    payload = json.loads(shipped_manifest_path().read_text())
    size = sum(entry["size"] for entry in payload["demos"])
    seconds = sum(entry["num_steps"] / entry["frequency"] for entry in payload["demos"])
    assert size / seconds <= 18_000, f"{size / seconds:.0f} bytes per demo-second"
    record = json.loads(build_record_path().read_text())
    assert record["version"] == DATASET_VERSION and set(record["tasks"]) == set(DATASET_TASKS)
    for task, figures in record["tasks"].items():
        assert figures["demos"] == DEMOS_PER_TASK <= figures["attempts"], task
        assert figures["generator_success_rate"] == pytest.approx(DEMOS_PER_TASK / figures["attempts"], abs=1e-4)
        assert sum(figures["failures"].values()) == figures["attempts"] - DEMOS_PER_TASK == len(figures["failed_seeds"])
        assert figures["build_seconds"] > 0 and figures["demo_seconds"] > 0


def test_an_interrupted_build_resumes_and_a_cut_merges_into_the_shipped_manifest(tmp_path, monkeypatch):
    """A task whose files are complete is skipped; one with a file missing is built again;
    merging one task into the shipped manifest keeps every other task's entries."""
    import bigym.experts.dataset as dataset

    monkeypatch.setattr(dataset, "MANIFEST_DIR", tmp_path / "manifests")  # a version being cut
    out = tmp_path / "store"
    seen: list = []
    build_dataset(out, ("ReachTargetDual",), workers=1, progress=False, per_task=2, on_task=lambda t, r: seen.append(r))
    assert seen[-1] is not None and dataset.task_complete(out, "ReachTargetDual", per_task=2)
    files = sorted((out / DATASET_VERSION).rglob("*.safetensors"))
    stamps = [f.stat().st_mtime_ns for f in files]
    build_dataset(out, ("ReachTargetDual",), workers=1, progress=False, per_task=2, on_task=lambda t, r: seen.append(r))
    assert seen[-1] is None and [f.stat().st_mtime_ns for f in files] == stamps  # skipped, untouched
    files[0].unlink()  # as if the build had stopped before this file
    assert not dataset.task_complete(out, "ReachTargetDual", per_task=2)
    build_dataset(out, ("ReachTargetDual",), workers=1, progress=False, per_task=2, on_task=lambda t, r: seen.append(r))
    assert seen[-1] is not None and sorted((out / DATASET_VERSION).rglob("*.safetensors")) == files

    other = {"path": "Other/x/500hz/1.safetensors", "sha256": "0" * 64, "size": 1, "uuid": "1", "task": "Other",
             "action_mode": {}, "frequency": 500.0, "num_steps": 1}  # fmt: skip
    (tmp_path / "manifests").mkdir()
    dataset.shipped_manifest_path().write_text(json.dumps({"format": "bigym-demo-store", "demos": [other]}))
    dataset.write_shipped_manifest(out, ("ReachTargetDual",))
    merged = json.loads(dataset.shipped_manifest_path().read_text())
    assert sorted(e["task"] for e in merged["demos"]) == ["Other", "ReachTargetDual", "ReachTargetDual"]
    record = json.loads(dataset.build_record_path().read_text())
    assert record["tasks"]["ReachTargetDual"]["demos"] == 2 and "files" not in record["tasks"]["ReachTargetDual"]
    assert dataset.task_complete(out, "ReachTargetDual", per_task=2)  # now against the merged manifest


def test_a_maintainer_rebuild_resumes_against_its_own_build_not_the_stale_manifest(tmp_path, monkeypatch):
    """After a physics change every shipped sha256 is stale: a user's build must not trust
    such files, but a maintainer's rebuild (``--update-manifest``) resumes on what this
    bigym version built, and only on that."""
    import bigym.experts.dataset as dataset

    monkeypatch.setattr(dataset, "MANIFEST_DIR", tmp_path / "manifests")
    out = tmp_path / "store"
    build_dataset(out, ("ReachTargetDual",), workers=1, progress=False, per_task=2)
    built = json.loads((out / DATASET_VERSION / "manifest.json").read_text())["demos"]
    stale = [{**e, "sha256": "f" * 64} for e in built]  # what the last version shipped
    (tmp_path / "manifests").mkdir()
    dataset.shipped_manifest_path().write_text(json.dumps({"format": "bigym-demo-store", "demos": stale}))
    assert not dataset.task_complete(out, "ReachTargetDual", per_task=2)
    assert dataset.task_complete(out, "ReachTargetDual", per_task=2, against_shipped=False)
    seen: list = []
    build_dataset(out, ("ReachTargetDual",), workers=1, progress=False, per_task=2, against_shipped=False,
                  on_task=lambda t, r: seen.append(r))  # fmt: skip
    assert seen == [None]
    record_path = out / DATASET_VERSION / "build.json"
    record = json.loads(record_path.read_text())
    record["tasks"]["ReachTargetDual"]["bigym_version"] = "0.0.1"  # built by another bigym
    record_path.write_text(json.dumps(record))
    assert not dataset.task_complete(out, "ReachTargetDual", per_task=2, against_shipped=False)


def test_a_task_build_may_spend_five_attempts_per_demo_and_then_says_what_it_kept(tmp_path, monkeypatch):
    """The hardest experts keep about one attempt in two: a build gives each task five
    attempts per demo (and a few spare) before it gives up, and then fails with the figures."""
    import bigym.experts.generate as generate

    calls = []

    class Report:
        kept = 7

        def summary(self):
            return "kept 7/55"

    def fake_generate_demos(task, **kwargs):
        calls.append((task, kwargs))
        return Report()

    monkeypatch.setattr(generate, "generate_demos", fake_generate_demos)
    with pytest.raises(RuntimeError, match=r"kept 7/55\nthe dataset needs 10 demos of SandwichFlip"):
        build_dataset(tmp_path / "store", ("SandwichFlip",), workers=1, progress=False, per_task=10)
    [(task, kwargs)] = calls
    assert task == "SandwichFlip" and kwargs["n"] == 10
    assert kwargs["max_attempts"] == ATTEMPTS_PER_DEMO * 10 + SPARE_ATTEMPTS == 55


def _shipped_demos(task: str) -> dict[int, dict]:
    demos = json.loads(shipped_manifest_path().read_text())["demos"]
    return {d["seed"]: d for d in demos if d["task"] == task}


@pytest.mark.usefixtures("closes_envs")
@pytest.mark.parametrize("task", DATASET_TASKS)
def test_the_first_demo_of_every_shipped_task_regenerates_byte_for_byte(task):
    """Every task of the shipped dataset, not one: its first demo (the lowest seed the build
    kept), regenerated here as the build does, has the shipped name, size and sha256 (the
    expert, the task, the physics and the file format are all unchanged). The seeds below
    it, which the build tried and did not keep, are not tried again: that the build path
    itself gives the shipped files is ``test_a_rebuilt_task_matches_the_shipped_manifest_file_for_file``."""
    shipped = _shipped_demos(task)
    assert len(shipped) == DEMOS_PER_TASK
    first = min(shipped)
    report = generate_demos(task, n=1, seed=first, workers=1, progress=False, date=DATASET_DATE, max_attempts=1)
    assert report.kept == 1, report.summary()
    [demo] = report.demos
    data = demo.to_bytes()
    expected = shipped[first]
    assert expected["path"].endswith(f"{demo.metadata.uuid}.safetensors"), expected["path"]
    assert (len(data), hashlib.sha256(data).hexdigest()) == (expected["size"], expected["sha256"])


def test_a_rebuilt_task_matches_the_shipped_manifest_file_for_file(tmp_path):
    """The first demos of a task, regenerated here, have the shipped names and checksums."""
    build_dataset(tmp_path / "store", ("ReachTargetDual",), workers=1, progress=False, per_task=3)
    check = check_dataset(tmp_path / "store", ("ReachTargetDual",))
    assert not check.different and not check.extra, check.summary()
    assert len(check.matching) == 3 and len(check.missing) == DEMOS_PER_TASK - 3


def test_check_reports_missing_changed_and_extra_files():
    def manifest(files: dict[str, str]) -> str:
        demos = [{"path": p, "size": 10, "sha256": hashlib.sha256(c.encode()).hexdigest()} for p, c in files.items()]
        return json.dumps({"version": "vX", "demos": demos})

    expected = manifest({"A/x/500hz/1.safetensors": "a", "A/x/500hz/2.safetensors": "b", "B/x/500hz/3.safetensors": "c"})
    same = compare_manifests(expected, expected)
    assert same.identical and "identical" in same.summary()
    other = manifest({"A/x/500hz/1.safetensors": "a", "A/x/500hz/2.safetensors": "changed", "C/4.safetensors": "d"})
    check = compare_manifests(expected, other)
    assert not check.identical
    assert check.matching == ["A/x/500hz/1.safetensors"]
    assert check.different == ["A/x/500hz/2.safetensors"]
    assert check.missing == ["B/x/500hz/3.safetensors"]
    assert check.extra == ["C/4.safetensors"]
    assert "1 missing" in check.summary() and "1 different" in check.summary()
    only_a = compare_manifests(expected, other, tasks=("A",))
    assert only_a.expected == 2 and not only_a.missing and not only_a.extra


def test_dataset_check_command_exits_1_on_a_copy_that_differs(tmp_path):
    store = DemoStore(tmp_path / "copy", version=DATASET_VERSION)
    build_dataset(store.url, ("ReachTargetDual",), workers=1, progress=False, per_task=1)
    result = run("dataset", "check", store.url, "--task", "ReachTargetDual")
    assert result.exit_code == 1 and f"1 of {DEMOS_PER_TASK} demo files identical" in result.output


def test_generation_workers_run_on_pinned_numpy_kernels():
    """Spawned under pinned_environment, a worker's numpy uses its baseline kernels only
    (what makes the dataset's bytes machine-independent); the parent's settings come back."""
    import multiprocessing

    from bigym.experts.numerics import numerics_pinned, pinned_environment, pinned_settings

    before = {name: os.environ.get(name) for name in pinned_settings()}
    with pinned_environment():
        with multiprocessing.get_context("spawn").Pool(1) as pool:
            assert pool.apply(numerics_pinned) is True
    assert {name: os.environ.get(name) for name in pinned_settings()} == before
    # Without the settings a worker gets the machine's dispatch (unless this CPU has none).
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        assert pool.apply(numerics_pinned) is numerics_pinned()

"""Demos on demand: a store completes a missing task from the shipped dataset, byte for
byte, once, whatever the number of processes asking; interrupted builds resume; damaged
files are made again; hosted copies are checked; remote stores refuse a second writer."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from bigym.action_modes import JointPositionActionMode
from bigym.cli import app
from bigym.demonstrations import (
    DemoBuildError,
    DemoChecksumError,
    DemoNotFoundError,
    DemoStore,
    DemoStoreBusyError,
    Metadata,
)
from bigym.demonstrations.atomic import is_partial
from bigym.demonstrations.datasets import find_recipe
from bigym.demonstrations.demo import Demo, sha256_file
from bigym.demonstrations.provision import shipped_entries
from bigym.envs.reach_target import ReachTargetSingle
from bigym.experts.dataset import DATASET_VERSION, check_dataset

#: the cheapest slice of the shipped dataset: 50 reach demos, a few seconds to build on two cores
TASK = "ReachTargetSingle"


def _query(frequency: float = 50) -> Metadata:
    env = ReachTargetSingle(action_mode=JointPositionActionMode(absolute=True), control_frequency=frequency)
    metadata = Metadata.from_env(env)
    env.close()
    return metadata


def _task_files(folder: Path) -> list[Path]:
    return sorted((folder / DATASET_VERSION / TASK).rglob("*"))


@pytest.fixture(scope="module")
def built_store(tmp_path_factory) -> Path:
    """A store folder holding the task's shipped slice, built on demand once for the module."""
    root = tmp_path_factory.mktemp("built")
    store = DemoStore(root / "store", cache_dir=root / "cache")
    report = store.provide(TASK, progress=False)
    assert report is not None and report.made == 50 and report.source == "rebuilt on this machine"
    return root / "store"


@pytest.fixture()
def no_building(monkeypatch):
    """Fail the test if the shipped recipe is asked to build anything."""

    def refuse(*args, **kwargs):
        raise AssertionError("built, though the files should have come from elsewhere")

    monkeypatch.setattr(find_recipe(DATASET_VERSION), "build", refuse)


def test_the_papers_example_on_an_empty_store_builds_verifies_and_serves(tmp_path, monkeypatch, capfd):
    from bigym.envs.reach_target import ReachTarget

    monkeypatch.setenv("BIGYM_HOME", str(tmp_path / "home"))
    monkeypatch.delenv("BIGYM_DEMO_STORE", raising=False)
    monkeypatch.delenv("BIGYM_DATASET_MIRROR", raising=False)
    env = ReachTarget(action_mode=JointPositionActionMode(floating_base=True, absolute=True))
    demos = DemoStore().get_demos(Metadata.from_env(env))
    env.close()
    assert len(demos) == 50
    assert all(demo.report.first_success_step is not None for demo in demos)
    announced = capfd.readouterr().err
    assert "has no ReachTargetMultiModal demos: building its 50 files of dataset v2" in announced
    assert "about " in announced  # the time estimate
    store = DemoStore()
    assert check_dataset(store, tasks=("ReachTargetMultiModal",)).identical
    shipped = {(e.path, e.sha256) for e in shipped_entries(DATASET_VERSION, "ReachTargetMultiModal")}
    assert {(e.path, e.sha256) for e in store.entries()} == shipped
    assert store.provide("ReachTargetMultiModal", progress=False).made == 0  # complete: nothing to do


_ASK = """
import sys
from bigym.action_modes import JointPositionActionMode
from bigym.demonstrations import DemoStore, Metadata
from bigym.envs.reach_target import ReachTargetSingle

env = ReachTargetSingle(action_mode=JointPositionActionMode(absolute=True), control_frequency=50)
demos = DemoStore(sys.argv[1], cache_dir=sys.argv[2], build_workers=1).get_demos(Metadata.from_env(env), amount=3)
print("demos", len(demos), all(d.report.first_success_step is not None for d in demos))
"""


def test_concurrent_processes_build_a_task_once_and_all_get_it(tmp_path):
    store = tmp_path / "store"
    processes = [
        subprocess.Popen([sys.executable, "-c", _ASK, str(store), str(tmp_path / f"cache{i}")],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
        for i in range(3)
    ]
    outputs = [process.communicate(timeout=600) for process in processes]
    for (out, err), process in zip(outputs, processes):
        assert process.returncode == 0, err
        assert "demos 3 True" in out
    builders = [err for _, err in outputs if "building its 50 files" in err]
    assert len(builders) == 1, [err for _, err in outputs]
    assert check_dataset(DemoStore(store), tasks=(TASK,)).identical


def test_an_interrupted_build_keeps_whole_files_only_and_resumes(tmp_path, monkeypatch):
    recipe = find_recipe(DATASET_VERSION)
    real_build = recipe.build

    def interrupted(task, entries, workers):
        for count, made in enumerate(real_build(task, entries, workers)):
            if count == 7:
                raise KeyboardInterrupt
            yield made

    store = DemoStore(tmp_path / "store", cache_dir=tmp_path / "cache")
    monkeypatch.setattr(recipe, "build", interrupted)
    with pytest.raises(KeyboardInterrupt):
        store.provide(TASK, progress=False)
    files = [p for p in _task_files(tmp_path / "store") if p.is_file()]
    assert len(files) == 7 and not any(is_partial(p) for p in files)
    shipped = {e.path: e.sha256 for e in shipped_entries(DATASET_VERSION, TASK)}
    folder = tmp_path / "store" / DATASET_VERSION
    assert all(sha256_file(p) == shipped[p.relative_to(folder).as_posix()] for p in files)
    assert store.entries(task=TASK) == []  # not served until complete

    monkeypatch.setattr(recipe, "build", real_build)
    report = store.provide(TASK, progress=False)
    assert (report.reused, report.made) == (7, 43)
    assert check_dataset(store, tasks=(TASK,)).identical


def test_damaged_files_of_the_slice_are_made_again(tmp_path, built_store, capfd):
    shutil.copytree(built_store, tmp_path / "store")
    store = DemoStore(tmp_path / "store", cache_dir=tmp_path / "cache", build_workers=1)
    entries = store.entries(task=TASK)
    flipped, truncated = store.local_path(entries[0]), store.local_path(entries[1])
    data = bytearray(flipped.read_bytes())
    data[-10] ^= 0xFF
    flipped.write_bytes(bytes(data))
    truncated.write_bytes(truncated.read_bytes()[:1000])
    store.local_path(entries[2]).unlink()

    demos = store.get_demos(_query(), amount=3)
    assert [d.uuid for d in demos] == [e.uuid for e in entries[:3]]
    assert check_dataset(store, tasks=(TASK,)).identical
    assert "making it again from the shipped dataset" in capfd.readouterr().err

    # without demos on demand a damaged file is reported, not replaced
    strict = DemoStore(tmp_path / "store", cache_dir=tmp_path / "cache2", on_demand=False)
    truncated.write_bytes(truncated.read_bytes()[:1000])
    with pytest.raises(DemoChecksumError, match="truncated"):
        strict.get_demos(_query(), amount=3)


def test_without_demos_on_demand_an_empty_store_says_what_it_lacks(tmp_path):
    store = DemoStore(tmp_path / "store", cache_dir=tmp_path / "cache", on_demand=False)
    with pytest.raises(DemoNotFoundError, match="no successful demos of ReachTargetSingle.*it is empty"):
        store.get_demos(_query(), amount=1)
    assert not (tmp_path / "store").exists() or not _task_files(tmp_path / "store")


def test_a_variant_the_dataset_does_not_ship_is_not_built(tmp_path, no_building):
    store = DemoStore(tmp_path / "store", cache_dir=tmp_path / "cache")
    env = ReachTargetSingle(action_mode=JointPositionActionMode(absolute=True), hand="right")
    with pytest.raises(DemoNotFoundError, match="it is empty"):
        store.get_demos(Metadata.from_env(env), amount=1)
    env.close()


def test_a_hosted_copy_is_downloaded_and_checked_against_the_shipped_manifest(tmp_path, built_store, no_building,
                                                                            monkeypatch):  # fmt: skip
    store = DemoStore(tmp_path / "store", cache_dir=tmp_path / "cache", mirror=str(built_store))
    report = store.provide(TASK, progress=False)
    assert report.made == 50 and report.source == f"downloaded from {built_store}"
    assert check_dataset(store, tasks=(TASK,)).identical

    tampered = tmp_path / "tampered"
    shutil.copytree(built_store, tampered)
    victim = sorted((tampered / DATASET_VERSION / TASK).rglob("*.safetensors"))[5]
    data = bytearray(victim.read_bytes())
    data[-10] ^= 0xFF
    victim.write_bytes(bytes(data))
    monkeypatch.setenv("BIGYM_DATASET_MIRROR", str(tampered))
    other = DemoStore(tmp_path / "other", cache_dir=tmp_path / "cache")
    with pytest.raises(DemoChecksumError, match="serves other bytes"):
        other.get_demos(_query(), amount=1)
    assert not (tmp_path / "other" / victim.relative_to(tampered)).exists()
    assert other.entries(task=TASK) == []


def test_a_rebuild_with_other_bytes_is_refused_and_not_kept(tmp_path, monkeypatch):
    recipe = find_recipe(DATASET_VERSION)

    def other_bytes(task, entries, workers):
        for entry in entries[:1]:
            yield entry, b"not the shipped bytes"

    monkeypatch.setattr(recipe, "build", other_bytes)
    store = DemoStore(tmp_path / "store", cache_dir=tmp_path / "cache")
    with pytest.raises(DemoBuildError, match="rebuilt with other bytes.*MuJoCo"):
        store.provide(TASK, progress=False)
    assert not [p for p in _task_files(tmp_path / "store") if p.is_file()]


def test_a_remote_copy_with_other_bytes_than_shipped_is_refused(tmp_path, built_store):
    import fsspec

    shipped = DemoStore(built_store).entries(task=TASK)[0]
    demo = Demo.load(built_store / DATASET_VERSION / shipped.path)
    demo.metadata.date = "2030-01-01T00:00:00Z"  # same demo and path, other bytes
    url = f"memory://bigym-hosted-{tmp_path.name}"
    DemoStore(url).add(demo)
    remote = DemoStore(url, cache_dir=tmp_path / "cache")
    with pytest.raises(DemoChecksumError, match="differs from the dataset v2 this bigym ships"):
        remote.load(shipped.uuid)
    fsspec.filesystem("memory").rm(url, recursive=True)


def test_a_remote_store_refuses_a_second_writer(tmp_path, expert_demos):
    import fsspec

    url = f"memory://bigym-writers-{tmp_path.name}"
    first, second = DemoStore(url), DemoStore(url)
    with first._writing() as manifest:
        with pytest.raises(DemoStoreBusyError, match="is being written by .*refuses concurrent writes"):
            second.add(expert_demos["single_absolute"])
        manifest.entries = []
    second.add(expert_demos["single_absolute"])
    first.add(expert_demos["dual_absolute"])
    assert len(DemoStore(url).manifest(refresh=True).entries) == 2  # nothing lost

    lease = f"{url}/{DATASET_VERSION}/.write-lease"
    fs = fsspec.filesystem("memory")
    fs.pipe_file(lease, json.dumps({"token": "gone", "writer": "a dead writer", "since": time.time() - 3600}).encode())
    second.add(expert_demos["single_delta"])  # an abandoned lease is taken over
    assert len(DemoStore(url).manifest(refresh=True).entries) == 3
    assert not fs.exists(lease)
    fs.rm(url, recursive=True)


def test_cli_download_completes_a_local_store_from_a_hosted_copy(tmp_path, built_store, no_building, monkeypatch):
    monkeypatch.setenv("BIGYM_DATASET_MIRROR", str(built_store))
    result = CliRunner().invoke(app, ["demos", "download", "--task", "reach_target_single",
                                      "--store", str(tmp_path / "store")])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "50 of 50 demos of dataset v2 downloaded from" in result.output
    assert check_dataset(DemoStore(tmp_path / "store"), tasks=(TASK,)).identical


def test_the_build_estimate_comes_from_the_build_record():
    recipe = find_recipe(DATASET_VERSION)
    entries = shipped_entries(DATASET_VERSION, "StackBlocks")
    one, two = recipe.estimate_seconds("StackBlocks", entries, 1), recipe.estimate_seconds("StackBlocks", entries, 2)
    assert one > 0 and two == pytest.approx(one / 2)
    assert recipe.estimate_seconds("StackBlocks", entries, 1) > recipe.estimate_seconds(TASK, entries, 1)

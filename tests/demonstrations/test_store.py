"""DemoStore: local and HTTP stores, manifest checksums, caches, atomic writes."""

from __future__ import annotations

import functools
import http.server
import json
import os
import signal
import subprocess
import sys
import threading
from collections import Counter

import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.demonstrations import (
    Demo,
    DemoActionModeError,
    DemoChecksumError,
    DemoCorruptError,
    DemoError,
    DemoNotFoundError,
    DemoStore,
    Metadata,
    TooManyDemosRequestedError,
    player,
)
from bigym.demonstrations.atomic import is_partial, sweep_partial_files
from bigym.demonstrations.store import DATASET_VERSION, ReplayCache
from bigym.envs.reach_target import ReachTargetDual, ReachTargetSingle
from bigym.observations import CameraConfig, ObservationConfig


def _query(absolute=True, frequency=50, cameras=()):
    env = ReachTargetSingle(
        action_mode=JointPositionActionMode(absolute=absolute),
        control_frequency=frequency,
        observation_config=ObservationConfig(cameras=cameras),
    )
    metadata = Metadata.from_env(env)
    env.close()
    return metadata


class _CountingHandler(http.server.SimpleHTTPRequestHandler):
    counts: Counter

    def do_GET(self):
        self.counts[self.path] += 1
        super().do_GET()

    def do_HEAD(self):
        self.counts["HEAD " + self.path] += 1
        super().do_HEAD()

    def log_message(self, *args):
        pass


@pytest.fixture()
def http_store(local_store, tmp_path):
    """The local store served over HTTP on 127.0.0.1; yields (DemoStore, request counts, served folder)."""
    counts: Counter = Counter()
    handler = functools.partial(
        type("Handler", (_CountingHandler,), {"counts": counts}), directory=str(tmp_path / "store")
    )
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    url = f"http://127.0.0.1:{server.server_address[1]}"
    try:
        yield DemoStore(url, cache_dir=tmp_path / "http-cache"), counts, tmp_path / "store" / DATASET_VERSION
    finally:
        server.shutdown()
        server.server_close()


def test_store_layout_manifest_and_index(local_store, tmp_path):
    root = tmp_path / "store"
    index = json.loads((root / "index.json").read_text())
    assert index == {"format": "bigym-demo-store", "versions": [DATASET_VERSION], "latest": DATASET_VERSION}
    manifest = json.loads((root / DATASET_VERSION / "manifest.json").read_text())
    assert manifest["format"] == "bigym-demo-store" and manifest["version"] == DATASET_VERSION
    assert len(manifest["demos"]) == 3
    for item in manifest["demos"]:
        path = root / DATASET_VERSION / item["path"]
        assert item["path"].startswith("ReachTargetSingle/joint_position-absolute-floating_x_y_z_rz/500hz/")
        assert path.stat().st_size == item["size"] and len(item["sha256"]) == 64
        assert item["success"] is True and item["source"] == "expert"
    assert DemoStore(root, version="latest").version == DATASET_VERSION
    with pytest.raises(DemoError, match="already in"):
        local_store.add(local_store.load(manifest["demos"][0]["uuid"]))


def test_get_demos_replays_selects_and_caches(local_store, monkeypatch):
    query = _query(frequency=50, cameras=(CameraConfig("head", resolution=(16, 16)),))
    demos = local_store.get_demos(query, amount=2)
    assert len(demos) == 2 and all(d.report.first_success_step is not None for d in demos)
    assert demos[0].observations["rgb_head"].shape[1:] == (3, 16, 16)
    assert all(d.metadata.frequency == 50 for d in demos)
    assert [d.uuid for d in demos] == [e.uuid for e in local_store.entries()[:2]]
    assert len(local_store.replays.entries()) == 2

    def no_replays(*args, **kwargs):
        raise AssertionError("a cached replay was replayed again")

    monkeypatch.setattr(player, "replay_many", no_replays)
    again = local_store.get_demos(query, amount=2)
    assert [d.uuid for d in again] == [d.uuid for d in demos]
    assert (again[0].observations["rgb_head"] == demos[0].observations["rgb_head"]).all()
    monkeypatch.undo()
    # Another rate or observation config is another cache entry.
    local_store.get_demos(query, amount=1, frequency=25)
    assert len(local_store.replays.entries()) == 3
    assert local_store.get_demos(query, amount=0) == []
    with pytest.raises(TooManyDemosRequestedError, match="4 demos of ReachTargetSingle requested, the store has 3"):
        local_store.get_demos(query, amount=4)


def test_damaged_cache_entry_is_rebuilt(local_store):
    query = _query(frequency=50)
    first = local_store.get_demos(query, amount=1)[0]
    (path,) = local_store.replays.entries()
    path.write_bytes(path.read_bytes()[:100])
    again = local_store.get_demos(query, amount=1)[0]
    assert (again.observations["proprioception"] == first.observations["proprioception"]).all()
    assert len(path.read_bytes()) > 100


def test_other_action_mode_fails_clearly_or_converts(local_store):
    with pytest.raises(DemoActionModeError) as caught:
        local_store.get_demos(_query(absolute=False), amount=1)
    message = str(caught.value)
    assert "recorded with absolute actions" in message
    assert "bigym demos convert --task ReachTargetSingle --to delta" in message
    converted = local_store.get_demos(_query(absolute=False), amount=1, convert=True)
    assert converted[0].metadata.action_mode["absolute"] is False
    assert converted[0].report.first_success_step is not None
    env = ReachTargetDual()
    with pytest.raises(DemoNotFoundError, match="no successful demos of ReachTargetDual.*ReachTargetSingle"):
        local_store.get_demos(Metadata.from_env(env))
    env.close()


def test_http_store_downloads_once_then_hits_the_cache(http_store):
    store, counts, _ = http_store
    query = _query(frequency=50)
    demos = store.get_demos(query, amount=2)
    assert len(demos) == 2
    demo_gets = {path: n for path, n in counts.items() if path.endswith(".safetensors")}
    assert len(demo_gets) == 2 and set(demo_gets.values()) == {1}
    assert counts[f"/{DATASET_VERSION}/manifest.json"] == 1
    before = sum(counts.values())
    # A new store object on the same URL and cache: no request at all.
    fresh = DemoStore(store.url, cache_dir=store._cache_root)
    again = fresh.get_demos(query, amount=2)
    assert [d.uuid for d in again] == [d.uuid for d in demos]
    assert sum(counts.values()) == before
    # The lightweight files are in the cache and load without the network too.
    assert all(fresh.local_path(e).is_file() for e in fresh.entries()[:2])
    fresh.download()  # the third demo: one more request
    assert sum(counts.values()) == before + 1


def test_http_checksum_mismatch_and_truncation_fail_and_leave_nothing(http_store):
    store, _, served = http_store
    entries = store.entries()
    tampered = served / entries[0].path
    data = bytearray(tampered.read_bytes())
    data[-3] ^= 0xFF  # same size, different content
    tampered.write_bytes(bytes(data))
    with pytest.raises(DemoChecksumError, match="checksum mismatch") as caught:
        store.load(entries[0])
    assert caught.value.expected == entries[0].sha256
    truncated = served / entries[1].path
    truncated.write_bytes(truncated.read_bytes()[: entries[1].size // 2])
    with pytest.raises(DemoChecksumError, match="truncated"):
        store.fetch(entries[1])
    leftovers = [p for p in store.download_dir.rglob("*.safetensors")]
    assert leftovers == [], "a bad download was kept in the cache"
    assert store.load(entries[2]).uuid == entries[2].uuid


def test_corrupted_cached_download_is_fetched_again(http_store):
    store, counts, _ = http_store
    entry = store.entries()[0]
    path = store.fetch(entry)
    path.write_bytes(b"garbage")
    assert store.load(entry).uuid == entry.uuid
    assert counts[f"/{DATASET_VERSION}/{entry.path}"] == 2


def test_local_store_detects_modified_and_damaged_files(local_store, tmp_path):
    entries = local_store.entries()
    path = tmp_path / "store" / DATASET_VERSION / entries[0].path
    path.write_bytes(path.read_bytes()[:-10])
    with pytest.raises(DemoChecksumError, match="truncated"):
        local_store.get_demos(_query(), amount=1)
    # A manifest rebuilt from the damaged file no longer flags the size, the file itself fails to parse.
    with pytest.raises(DemoCorruptError):
        local_store.rebuild_manifest()


def test_unknown_protocol_and_missing_version_fail_clearly(tmp_path):
    with pytest.raises(DemoError, match="cannot open the demo store"):
        DemoStore("nosuchprotocol://bucket/demos")
    with pytest.raises(DemoNotFoundError, match="no .*index.json"):
        DemoStore(tmp_path / "empty", version="latest").version  # noqa: B018


_KILLED_WRITER = """
import os, sys, time
from bigym.demonstrations import Demo
demo = Demo.load(sys.argv[1])
def stall(fd):
    print("writing", flush=True)
    time.sleep(60)
os.fsync = stall  # bytes written, rename not done yet: the moment a crash hurts most
demo.save(sys.argv[2])
"""


@pytest.mark.parametrize("overwrite", [False, True], ids=["new-file", "overwrite"])
def test_killed_writer_leaves_no_partial_file(tmp_path, expert_demos, overwrite):
    demo = expert_demos["single_delta"]
    source = demo.save(tmp_path / "source.safetensors")
    folder = tmp_path / "out"
    folder.mkdir()
    target = folder / demo.filename
    old = expert_demos["single_absolute"].to_bytes()
    if overwrite:
        target.write_bytes(old)
    writer = subprocess.Popen(
        [sys.executable, "-c", _KILLED_WRITER, str(source), str(target)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert writer.stdout.readline().strip() == "writing"
        partial = [p for p in folder.iterdir() if is_partial(p)]
        assert len(partial) == 1 and partial[0].stat().st_size == source.stat().st_size
    finally:
        os.kill(writer.pid, signal.SIGKILL)
        writer.wait()
    if overwrite:
        assert target.read_bytes() == old, "the old file was damaged"
    else:
        assert not target.exists(), "a killed writer left a file under the final name"
    store = DemoStore(tmp_path / "out-store")
    assert store.entries() == []
    removed = sweep_partial_files(folder)
    assert len(removed) == 1 and [p for p in folder.iterdir() if is_partial(p)] == []
    assert Demo.load(demo.save(target)).uuid == demo.uuid  # a later write succeeds


def test_replay_cache_key_covers_config_rate_mode_and_whole_recordings():
    base = ReplayCache.key("ab" * 32, ObservationConfig(), 50, JointPositionActionMode(absolute=True))
    assert base == ReplayCache.key("ab" * 32, None, 50.0, JointPositionActionMode(absolute=True))
    others = {
        ReplayCache.key("cd" * 32, ObservationConfig(), 50, JointPositionActionMode(absolute=True)),
        ReplayCache.key("ab" * 32, ObservationConfig.robot_cameras(), 50, JointPositionActionMode(absolute=True)),
        ReplayCache.key("ab" * 32, ObservationConfig(), 25, JointPositionActionMode(absolute=True)),
        ReplayCache.key("ab" * 32, ObservationConfig(), 50, JointPositionActionMode(absolute=False)),
        ReplayCache.key("ab" * 32, ObservationConfig(), 50, JointPositionActionMode(absolute=True), episode_only=False),
    }
    assert base not in others and len(others) == 5
    assert base == ReplayCache.key("ab" * 32, None, 50.0, JointPositionActionMode(absolute=True), episode_only=True)


def test_remove_deletes_files_manifest_entries_and_replays(local_store, tmp_path):
    query = _query()
    local_store.get_demos(query, amount=3)
    entry = local_store.entries()[0]
    local_store.remove([entry.uuid[:8]])
    assert entry.uuid not in {e.uuid for e in local_store.entries()}
    assert not (tmp_path / "store" / DATASET_VERSION / entry.path).exists()
    assert not any(entry.uuid in str(p) for p in local_store.replays.entries())
    assert len(local_store.get_demos(query)) == 2


def test_remote_filesystem_store_writes_and_downloads(tmp_path, expert_demos):
    """fsspec's in-memory file system stands in for s3/gcs: the remote code paths end to end."""
    import fsspec

    url = f"memory://bigym-test-{tmp_path.name}"
    writer = DemoStore(url, cache_dir=tmp_path / "cache-w")
    assert not writer.is_local
    writer.add(expert_demos["single_absolute"])
    fs = fsspec.filesystem("memory")
    assert fs.exists(f"{url}/{DATASET_VERSION}/manifest.json") and fs.exists(f"{url}/index.json")
    reader = DemoStore(url, cache_dir=tmp_path / "cache-r")
    (entry,) = reader.entries()
    demos = reader.get_demos(_query(frequency=100), amount=1)
    assert demos[0].uuid == entry.uuid and demos[0].report.first_success_step is not None
    assert reader.local_path(entry).is_file() and str(reader.local_path(entry)).startswith(str(tmp_path / "cache-r"))
    fs.rm(url, recursive=True)

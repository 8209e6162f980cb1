"""``bigym demos ...``: every command, and a readable message with exit status 1 on errors."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

import bigym.cli.demos as demos_cli
from bigym.cli import app
from bigym.demonstrations import Demo

runner = CliRunner()


def run(*args):
    return runner.invoke(app, ["demos", *map(str, args)])


@pytest.fixture(autouse=True)
def wide_console(monkeypatch):
    """Tables at full width, so that names are not cut."""
    monkeypatch.setattr(demos_cli.console, "width", 250)
    monkeypatch.setattr(demos_cli.err_console, "width", 250)


@pytest.fixture()
def store_url(local_store, tmp_path, monkeypatch):
    monkeypatch.setenv("BIGYM_HOME", str(tmp_path / "home"))  # replay cache of the CLI
    return str(tmp_path / "store")


def test_list_info_and_verify(store_url, local_store):
    result = run("list", "--store", store_url)
    assert result.exit_code == 0, result.output
    assert "ReachTargetSingle" in result.output and "3 demos" in result.output
    uuid = local_store.entries()[0].uuid
    result = run("info", uuid[:10], "--store", store_url)
    assert result.exit_code == 0 and "reset seed" in result.output and "absolute" in result.output
    result = run("verify", "--task", "ReachTargetSingle", "--store", store_url, "--frequency", 50)
    assert result.exit_code == 0, result.output
    assert "all 3 demos verified" in result.output


def test_verify_fails_with_exit_1_on_a_bad_demo(store_url, local_store, tmp_path):
    demo = local_store.load(local_store.entries()[0])
    bad = demo.replace(checkpoint_states=demo.checkpoint_states + 1e-6)
    path = bad.save(tmp_path / "bad.safetensors")
    result = run("verify", path)
    assert result.exit_code == 1
    assert "DemoDivergenceError" in result.output and "1 of 1 demos failed verification" in result.output


def test_replay_writes_video_and_output(store_url, local_store, tmp_path):
    uuid = local_store.entries()[1].uuid
    video, output = tmp_path / "replay.mp4", tmp_path / "replayed.safetensors"
    result = run("replay", uuid, "--store", store_url, "-f", 50, "--cameras", "head", "--resolution", 16,
                 "--video", video, "--output", output)  # fmt: skip
    assert result.exit_code == 0, result.output
    assert video.stat().st_size > 0 and output.stat().st_size > 0
    assert "success at step" in result.output


def test_convert_and_export(store_url, local_store, tmp_path):
    result = run("convert", "--task", "ReachTargetSingle", "--to", "delta", "-f", 100, "--output", tmp_path / "conv",
                 "--store", store_url)  # fmt: skip
    assert result.exit_code == 0, result.output
    converted = [Demo.load(p) for p in sorted((tmp_path / "conv").iterdir())]
    assert len(converted) == 3 and all(d.metadata.action_mode["absolute"] is False for d in converted)
    assert all(d.metadata.frequency == 100 for d in converted)
    result = run("export", "lerobot", tmp_path / "lerobot", "--task", "ReachTargetSingle", "--amount", 2,
                 "--store", store_url)  # fmt: skip
    assert result.exit_code == 0, result.output
    info = json.loads((tmp_path / "lerobot" / "meta" / "info.json").read_text())
    assert info["total_episodes"] == 2 and info["fps"] == 50
    result = run("export", "robomimic", tmp_path / "demos.hdf5", "--task", "ReachTargetSingle", "--mode", "delta",
                 "-f", 25, "--store", store_url)  # fmt: skip
    assert result.exit_code == 0, result.output
    assert (tmp_path / "demos.hdf5").stat().st_size > 0


def test_download_delete_and_record(store_url, local_store, tmp_path):
    result = run("download", "--store", store_url)
    assert result.exit_code == 0 and "3 demos verified" in result.output
    run("verify", "--task", "ReachTargetSingle", "--store", store_url)
    result = run("delete", "--all", "--store", store_url)
    assert result.exit_code == 0, result.output
    uuid = local_store.entries()[0].uuid
    result = run("delete", uuid, "--from-store", "--yes", "--store", store_url)
    assert result.exit_code == 0 and "deleted 1 demos" in result.output
    result = run("record", "ReachTargetDual", "--episodes", 1, "--seed", 2, "--store", store_url)
    assert result.exit_code == 0, result.output
    result = run("list", "--store", store_url, "--each")
    assert "ReachTargetDual" in result.output and "3 demos" in result.output


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["info", "nope"], "no demo with uuid 'nope'"),
        (["info", "missing/file.safetensors"], "no demo file"),
        (["verify"], "name demos"),
        (["replay", "nope", "--video", "x.txt"], "--video must end in"),
        (["export", "parquet", "out", "--task", "ReachTargetSingle"], "format must be"),
        (["export", "lerobot", "out", "--task", "ReachTargetSingle", "-f", 30], "whole frames per second"),
        (["export", "lerobot", "out", "--task", "NoSuchTask"], "unknown task"),
        (["convert", "--task", "ReachTargetSingle"], "nothing to convert"),
        (["list", "--store", "nosuchprotocol://x"], "cannot open the demo store"),
    ],
)
def test_errors_exit_1_with_a_message(store_url, args, message):
    if "--store" not in args:
        args = [*args, "--store", store_url]
    result = run(*args)
    assert result.exit_code == 1, result.output
    assert "error:" in result.output and message in " ".join(result.output.split())

"""``bigym eval``: a summary that matches the record it writes, videos, and readable errors."""

from __future__ import annotations

import importlib
import json

import pytest
from typer.testing import CliRunner

from bigym.cli import app

app_module = importlib.import_module("bigym.cli.app")  # the package re-exports the Typer app under this name

runner = CliRunner()


@pytest.fixture(autouse=True)
def wide_console(monkeypatch):
    monkeypatch.setattr(app_module.console, "width", 200)
    monkeypatch.setattr(app_module.err_console, "width", 200)


def run(*args):
    return runner.invoke(app, ["eval", *map(str, args)])


def test_eval_prints_the_summary_and_writes_the_record_and_a_video(tmp_path):
    out = tmp_path / "result.json"
    result = run(
        "reach_target_dual", "--episodes", 3, "--workers", 1, "--json", out, "--video", tmp_path / "videos",
        "--videos", 1,
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    record = json.loads(out.read_text())
    successes = record["summary"]["successes"]
    assert len(record["episodes"]) == 3 and successes == sum(e["success"] for e in record["episodes"])
    assert f"{successes}/3" in result.output and "(Wilson)" in result.output
    assert record["official"] is False and "3 episodes instead of 100" in result.output
    assert record["policy"] == "bigym.experts:make_expert"
    videos = [e["video"] for e in record["episodes"] if e["video"]]
    assert len(videos) == 1 and (tmp_path / "videos" / "ReachTargetDual-seed1000000.mp4").stat().st_size > 1000


def test_eval_with_observations_a_policy_file_and_delta_actions(tmp_path):
    source = tmp_path / "my_policy.py"
    source.write_text(
        "import numpy as np\n"
        "def factory(env):\n"
        "    seen = env.observation_space.spaces\n"
        "    assert 'rgb_head' in seen and 'target_position' in seen, list(seen)\n"
        "    return lambda obs: np.zeros(env.action_space.shape, np.float32)\n"
    )
    out = tmp_path / "result.json"
    result = run(
        "reach_target_multi_modal", "--policy", f"{source}:factory", "--episodes", 2, "--workers", 1,
        "--cameras", "head", "--privileged", "--delta", "--json", out,
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    record = json.loads(out.read_text())
    assert record["fingerprint"]["track"] == "state+pixels"
    assert record["fingerprint"]["action_mode"]["absolute"] is False
    assert [e["outcome"] for e in record["episodes"]] == ["time_limit", "time_limit"]


@pytest.mark.parametrize(
    "args, message",
    [
        (["reach_target_dual", "--policy", "nope"], "give one of expert, random"),
        (["reach_target_dual", "--policy", "bigym.nothing:f"], "cannot import"),
        (["reach_target_dual", "--cameras", "head,tail"], "unknown camera(s) tail"),
        (["reach_target_dual", "--depth"], "--depth needs --cameras"),
        (["reach_target_dual", "--vector", "threads"], "vector must be one of"),
        (["no_such_task"], "unknown task"),
        (["drawer_top_open", "--policy", "reach", "--episodes", "1", "--workers", "1"], "only drives the reach tasks"),
    ],
)
def test_eval_errors_are_readable(args, message):
    result = run(*args)
    assert result.exit_code == 1
    assert message in result.output, result.output


def test_eval_of_a_task_without_an_expert_says_so(monkeypatch):
    import bigym.experts

    # every task has one now: as if this had none (a copy, so that the registry's order,
    # which tables follow, stays as it is for the tests after this one)
    without = {task: path for task, path in bigym.experts.EXPERTS.items() if task != "SandwichFlip"}
    monkeypatch.setattr(bigym.experts, "EXPERTS", without)
    result = run("sandwich_flip")
    assert result.exit_code == 1
    assert "SandwichFlip has no expert yet" in result.output, result.output

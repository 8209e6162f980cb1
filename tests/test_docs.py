"""The documentation that is generated from the code must match the code."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from bigym.task_docs import readme_task_table, task_infos, tasks_markdown

REPO = Path(__file__).resolve().parents[1]


def test_docs_tasks_md_is_current():
    written = (REPO / "docs" / "tasks.md").read_text()
    assert written == tasks_markdown(), "docs/tasks.md is stale: run `bigym tasks --markdown docs/tasks.md`"


def test_readme_lists_every_task_with_its_preview():
    readme = (REPO / "README.md").read_text()
    assert readme_task_table() in readme, "README task table is stale: run `bigym tasks --readme README.md`"
    for info in task_infos():
        assert f"`{info.env_id}`" in readme, f"{info.env_id} missing from the README task table"
        assert (REPO / "docs" / "previews" / f"{info.snake}.png").exists(), f"no preview for {info.name}"


def test_every_task_says_what_to_do():
    for info in task_infos():
        assert info.summary, f"{info.name} has no one-line docstring"
        # a summary wrapped over two docstring lines is read whole, not cut at the first
        assert info.summary.endswith("."), f"{info.name}'s summary is cut short: {info.summary!r}"


def _documented_start_noise(snake: str) -> tuple[float, float, float] | None:
    """The start-noise cell of a task's row in docs/tasks.md (None for 'none')."""
    for line in (REPO / "docs" / "tasks.md").read_text().splitlines():
        if line.startswith(f"| `{snake}` |"):
            cell = line.split("|")[6].strip()
            return None if cell == "none" else tuple(float(v) for v in cell.split(","))
    raise AssertionError(f"{snake} has no row in docs/tasks.md")


@pytest.mark.parametrize("name", ["ReachTargetDual", "DrawerTopOpen"])
def test_documented_start_noise_is_what_reset_does(name):
    """docs/tasks.md's start noise, checked against the pelvis pose over many resets."""
    info = next(i for i in task_infos() if i.name == name)
    env = info.cls()
    try:
        offsets = []
        for seed in range(40):
            obs, _ = env.reset(seed=seed)
            offsets.append(obs["proprioception_floating_base"][[0, 1, 3]] - np.array(info.cls.robot_start))
        offsets = np.abs(np.array(offsets, dtype=np.float64))
    finally:
        env.close()
    documented = _documented_start_noise(info.snake)
    if documented is None:
        assert offsets.max() < 1e-6, f"{name}: the robot start varies but docs/tasks.md says 'none'"
    else:
        assert np.all(offsets <= np.array(documented) + 1e-6), f"{name}: start offsets exceed the documented noise"
        # 40 uniform draws reach at least 80% of each bound (fails with p < 1e-8 by chance).
        assert np.all(offsets.max(axis=0) >= 0.8 * np.array(documented)), f"{name}: noise narrower than documented"


def test_readme_setup_commands_match_ci():
    """The README's test command is the one .ci/run runs."""
    readme = (REPO / "README.md").read_text()
    ci = (REPO / ".ci" / "run").read_text()
    command = (
        "(command -v chromium || (apt-get update && apt-get install -y --no-install-recommends chromium)) && "
        "python3 -m venv .venv && . .venv/bin/activate && pip install torch==2.13.0 && "
        'pip install -e ".[dev,train,ray]" && python -m pytest -q -n auto --maxprocesses 4\n'
    )
    assert command in readme and command in ci


def test_readme_main_job_runs_as_written(tmp_path):
    """The README's first command, after its install step, runs and does what it says."""
    import re
    import shlex

    from typer.testing import CliRunner

    from bigym.cli import app

    readme = (REPO / "README.md").read_text()
    first = re.search(r"```bash\n(.*?)\n```", readme, re.S).group(1)
    job = first.split("&&")[-1].strip()
    words = shlex.split(job)
    assert words[0] == "MUJOCO_GL=egl" and words[1] == "bigym", job
    result = CliRunner().invoke(app, words[2:] + ["--json", str(tmp_path / "result.json")])
    assert result.exit_code == 0, result.output
    assert "(Wilson)" in result.output and "official" in result.output
    assert any(Path("videos").glob("*.mp4")), "the command writes videos of its first episodes"


def _benchmark(script: str):
    """A script of benchmarks/ as a module."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(script, REPO / "benchmarks" / f"{script}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _benchmark_table(script: str, records: str) -> str:
    """The Markdown table a benchmark script prints from its committed records."""
    return _benchmark(script).table(REPO / "results" / records)


def test_readme_expert_table_is_the_committed_records():
    """The README's expert reference table is what benchmarks/expert_reference.py prints
    from the records in results/expert/."""
    table = _benchmark_table("expert_reference", "expert")
    assert table.count("\n") >= 15, "premise: the records are there"
    assert table in (REPO / "README.md").read_text(), "README expert table is stale: rerun the benchmark"


def test_readme_baseline_table_is_the_committed_records():
    """The README's baseline results are what benchmarks/baselines.py prints from results/baselines/."""
    table = _benchmark_table("baselines", "baselines")
    assert table.count("\n") >= 3, "premise: the records are there"
    assert table in (REPO / "README.md").read_text(), "README baseline table is stale: rerun the benchmark"


def test_baseline_records_are_named_after_what_they_changed():
    """A record's file name lists the settings its run changed from today's defaults, so
    that changing a default does not leave a record that makes the benchmark skip a run."""
    module = _benchmark("baselines")
    records = sorted((REPO / "results" / "baselines").glob("*.json"))
    assert len(records) >= 3, "premise: the records are there"
    for path in records:
        expected = module.name_for_today(json.loads(path.read_text())) + ".json"
        assert path.name == expected, f"{path.name} ran other settings: it should be named {expected}"

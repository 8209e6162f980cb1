"""The documentation that is generated from the code must match the code."""

from __future__ import annotations

from pathlib import Path

import bigym
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
        assert info.cls.time_limit > 0


def test_readme_setup_commands_match_ci():
    """The README's test command is the one .ci/run runs."""
    readme = (REPO / "README.md").read_text()
    ci = (REPO / ".ci" / "run").read_text()
    command = 'python3 -m venv .venv && . .venv/bin/activate && pip install -e ".[dev]" && python -m pytest -q'
    assert command in readme and command in ci
    assert len(bigym.TASKS) >= 3

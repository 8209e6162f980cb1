"""Tests of the offline-RL extra (d3rlpy), run in their own environment: d3rlpy pins
gymnasium 1.0.0, older than the main test environment's (README, "Offline RL")."""

from __future__ import annotations

import os
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]
os.environ.setdefault("MENAGERIE_ROOT", str(REPO_ROOT.parent / "shared" / "menagerie"))
os.environ.setdefault("MUJOCO_GL", "egl")

import pytest  # noqa: E402
from rlkit import DEMOS, TASK  # noqa: E402

from bigym.demonstrations import DemoStore  # noqa: E402
from bigym.experts import generate_demos  # noqa: E402


@pytest.fixture(autouse=True)
def _run_in_tmp_dir(tmp_path, monkeypatch):
    """Keep MuJoCo's log file out of the repository."""
    monkeypatch.chdir(tmp_path)


@pytest.fixture(scope="session")
def demo_store(tmp_path_factory):
    """A few expert demos of a small task, recorded once per session."""
    root = tmp_path_factory.mktemp("rl-demos")
    store = DemoStore(root / "store", cache_dir=root / "cache")
    report = generate_demos(TASK, n=DEMOS, seed=0, workers=1, progress=False, verify=False, store=store)
    assert len(report.demos) == DEMOS, "premise: the expert recorded its demos"
    return store

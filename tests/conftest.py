"""Shared set-up for the bigym test suite.

The environment variables must be set before ``bigym`` (and through it ``mujoco``) is
imported: the menagerie models are read from the shared offline copy beside the repo, and
offscreen rendering uses EGL.
"""

from __future__ import annotations

import os
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]
os.environ.setdefault("MENAGERIE_ROOT", str(REPO_ROOT.parent / "shared" / "menagerie"))
# Tests run in a temporary working directory (see below): make relative paths absolute now.
for _name in ("MENAGERIE_ROOT", "BIGYM_HOME"):
    if os.environ.get(_name):
        os.environ[_name] = str(Path(os.environ[_name]).expanduser().resolve())
os.environ.setdefault("MUJOCO_GL", "egl")

import pytest  # noqa: E402

import bigym  # noqa: E402,F401  (registers the gymnasium ids)


@pytest.fixture(autouse=True)
def _run_in_tmp_dir(tmp_path, monkeypatch):
    """MuJoCo appends its warnings to ./MUJOCO_LOG.TXT: keep that out of the repository."""
    monkeypatch.chdir(tmp_path)


@pytest.fixture
def run_episode():
    """A function that steps ``env`` with ``policy`` from ``obs`` until the episode ends
    (success, failure or time limit) and returns the last step's info."""

    def run(env, policy, obs) -> dict:
        info: dict = {}
        for _ in range(env.max_episode_steps):
            obs, _, terminated, truncated, info = env.step(policy(obs))
            if terminated or truncated:
                break
        return info

    return run

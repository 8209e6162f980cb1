"""Fixtures for the expert tests."""

from __future__ import annotations

import pytest


def _close_all() -> None:
    from bigym.demonstrations.player import close_cached_envs
    from bigym.experts.generate import close_envs

    close_envs()
    close_cached_envs()


@pytest.fixture(scope="module", autouse=True)
def _close_cached_envs_after_module():
    """Close the envs that recording (``record_attempt``) and replay verification keep for
    reuse, per task and rate, after each module: a test process that went through the
    dataset's 38 tasks held 12 GB of them."""
    yield
    _close_all()


@pytest.fixture
def closes_envs():
    """For a test that goes through many tasks: close the kept envs after each case."""
    yield
    _close_all()

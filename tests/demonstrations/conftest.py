"""Shared demos for the demonstration tests: recorded once per session."""

from __future__ import annotations

import pytest
from demokit import record_reach

from bigym.demonstrations import DemoStore
from bigym.envs.reach_target import ReachTargetDual, ReachTargetSingle

_RECORDED: dict = {}


def single_absolute(seed: int):
    """A ReachTargetSingle expert demo with absolute actions at 500 Hz (recorded once)."""
    if seed not in _RECORDED:
        _RECORDED[seed] = record_reach(ReachTargetSingle, True, seed=seed)
    return _RECORDED[seed]


@pytest.fixture(scope="session")
def expert_demos():
    """Scripted-expert demos at 500 Hz for two tasks and both joint modes."""
    demos = {
        "single_absolute": single_absolute(2),
        "single_delta": record_reach(ReachTargetSingle, False, seed=1),
        "dual_absolute": record_reach(ReachTargetDual, True, seed=3),
        "dual_delta": record_reach(ReachTargetDual, False, seed=2),
    }
    for name, demo in demos.items():
        assert demo.metadata.success, f"the scripted expert failed to record {name}"
    return demos


@pytest.fixture()
def local_store(tmp_path, expert_demos):
    """A local store with three absolute ReachTargetSingle demos, and its own cache folder
    (not completed from the shipped dataset: these tests are about what the store holds)."""
    store = DemoStore(tmp_path / "store", cache_dir=tmp_path / "cache", on_demand=False)
    for seed in (2, 3, 4):
        store.add(single_absolute(seed))
    return store

"""A small store of expert demos for the baseline tests, recorded once per session."""

from __future__ import annotations

import pytest

from bigym.demonstrations import DemoStore
from bigym.experts import generate_demos

TASK = "ReachTargetMultiModal"


@pytest.fixture(scope="session")
def demo_store(tmp_path_factory):
    root = tmp_path_factory.mktemp("baseline-demos")
    store = DemoStore(root / "store", cache_dir=root / "cache")
    report = generate_demos(TASK, n=4, seed=0, workers=1, progress=False, verify=False, store=store)
    assert len(report.demos) == 4, "premise: the expert recorded its demos"
    return store

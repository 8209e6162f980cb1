"""Ray: the dataset build, replays, exports and evaluations give what the process pool gives,
on a local two-CPU Ray instance (as CI runs it)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from bigym.cli import app
from bigym.demonstrations import Demo, replay_many
from bigym.evaluation import EvaluationError, evaluate
from bigym.experts.generate import record_attempt
from bigym.observations import CameraConfig, ObservationConfig
from bigym.scale_out import RayUnavailableError, ensure_ray

EVALKIT = str(Path(__file__).parent / "evaluation")


@pytest.fixture(scope="module", autouse=True)
def local_ray():
    """One local Ray instance with two CPUs for the module (workers can import evalkit)."""
    import os

    import ray

    previous = os.environ.get("PYTHONPATH")
    os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [EVALKIT, previous]))
    if ray.is_initialized():  # another test's instance, maybe with other CPUs or environment
        ray.shutdown()
    ensure_ray(num_cpus=2)
    yield
    ray.shutdown()
    if previous is None:
        del os.environ["PYTHONPATH"]
    else:
        os.environ["PYTHONPATH"] = previous


def test_cli_dataset_build_on_ray_matches_the_manifest(tmp_path):
    """The shipped manifest was built on the process pool: Ray workers must pin numpy the same
    way, so all 50 files of a task built through Ray have the shipped bytes."""
    result = CliRunner().invoke(
        app, ["demos", "dataset", "build", str(tmp_path / "out"), "--task", "reach_target_single", "--workers", "2",
              "--backend", "ray"],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "all 50 demo files identical to the shipped manifest" in " ".join(result.output.split())


def test_replays_on_ray_equal_the_process_pool():
    demos = [Demo.from_bytes(record_attempt("ReachTargetDual", 0, seed, verify=False).data) for seed in (4, 5)]
    config = ObservationConfig(cameras=(CameraConfig("head", rgb=True, depth=True, resolution=(32, 32)),))
    pool = replay_many(demos, config, 50, workers=2, backend="process", progress=False)
    ray = replay_many(demos, config, 50, workers=2, backend="ray", progress=False)
    for a, b in zip(pool, ray):
        assert a.uuid == b.uuid and a.observations.keys() == b.observations.keys()
        assert all(np.array_equal(a.observations[k], b.observations[k]) for k in a.observations)
        assert np.array_equal(a.actions, b.actions) and np.array_equal(a.rewards, b.rewards)
    assert pool[0].observations["rgb_head"].std() > 0, "premise: the frames show something"


def test_evaluations_on_ray_equal_the_process_pool():
    pool = evaluate("bigym.experts:make_expert", "ReachTargetMultiModal", episodes=4, workers=2)
    ray = evaluate("bigym.experts:make_expert", "ReachTargetMultiModal", episodes=4, workers=2, backend="ray")
    assert [r.comparable() for r in ray.episodes] == [r.comparable() for r in pool.episodes]
    assert ray.fingerprint == pool.fingerprint and ray.backend == "ray"
    assert len({r.start for r in ray.episodes}) == 4, "premise: every seed is its own scene"


def test_a_policy_error_on_ray_names_the_episode():
    with pytest.raises(EvaluationError, match=r"seed 1000000, step 0: RuntimeError: this policy is broken"):
        evaluate("evalkit:broken", "ReachTargetMultiModal", episodes=2, workers=1, backend="ray")


def test_cli_export_on_ray_equals_the_process_pool(tmp_path, monkeypatch):
    import h5py

    from bigym.demonstrations import DemoStore

    monkeypatch.setenv("BIGYM_HOME", str(tmp_path / "home"))  # the CLI's replay cache, as the store's below
    store = DemoStore(tmp_path / "store", on_demand=False)
    store.add_many([Demo.from_bytes(record_attempt("ReachTargetDual", 0, seed, verify=False).data) for seed in (6, 7)])
    arrays = []
    for backend in ("process", "ray"):
        out = tmp_path / f"{backend}.hdf5"
        result = CliRunner().invoke(app, ["demos", "export", "robomimic", str(out), "--task", "ReachTargetDual",
                                          "--store", str(tmp_path / "store"), "--workers", "2", "--backend", backend,
                                          "--cameras", "head", "--resolution", "16"])  # fmt: skip
        assert result.exit_code == 0, result.output
        with h5py.File(out) as f:
            arrays.append({name: f[f"data/{name}"][()] for name in ("demo_0/actions", "demo_1/obs/rgb_head")})
        store.replays.clear()  # the second export replays again instead of reading the cache
    assert all(np.array_equal(arrays[0][k], arrays[1][k]) for k in arrays[0])


def test_without_ray_the_backend_says_how_to_install_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)
    with pytest.raises(RayUnavailableError, match=r"pip install 'bigym\[ray\]'"):
        ensure_ray()
    result = CliRunner().invoke(app, ["eval", "reach_target_dual", "--episodes", "1", "--backend", "ray"])
    assert result.exit_code == 1 and "bigym[ray]" in result.output

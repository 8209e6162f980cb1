"""The demos as d3rlpy's MDPDataset, and the IQL example trained and evaluated through bigym eval."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import d3rlpy
import gymnasium as gym
import numpy as np
import pytest
from rlkit import DEMOS, TASK

from bigym.demonstrations import Metadata
from bigym.demonstrations.transitions import transitions
from bigym.envs.reach_target import ReachTargetSingle
from bigym.evaluation import evaluate, load_factory

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "d3rlpy_iql.py"


@pytest.fixture(scope="module")
def example():
    return sys.modules[load_factory(f"{EXAMPLE}:policy").__module__]


@pytest.fixture(scope="module")
def replayed(example, demo_store):
    env = example.make_env(TASK)
    demos = demo_store.get_demos(Metadata.from_env(env))
    yield env, demos
    env.close()


def test_mdp_dataset_holds_the_replayed_demos(replayed):
    env, demos = replayed
    data = transitions(demos, env)
    dataset = data.to_d3rlpy()
    assert isinstance(dataset, d3rlpy.dataset.MDPDataset)
    assert len(dataset.episodes) == DEMOS == len(demos)
    for episode, demo, rows in zip(dataset.episodes, demos, data.episodes()):
        assert len(episode.observations) == len(demo)
        np.testing.assert_array_equal(episode.observations, data.spaces.flatten_steps(demo.observations)[: len(demo)])
        # the model's actions (the base as targets) turn back into the env's actions
        acted = [data.spaces.env_action(a, {k: v[t] for k, v in demo.observations.items()})
                 for t, a in enumerate(episode.actions)]  # fmt: skip
        np.testing.assert_allclose(np.array(acted), demo.actions, atol=2e-6)
        np.testing.assert_array_equal(episode.rewards[:, 0], demo.rewards.astype(np.float32))
        assert bool(episode.terminated) == bool(demo.terminated[-1]) and episode.rewards[-1, 0] == 1.0
        np.testing.assert_array_equal(episode.actions, data.actions[rows])
    assert dataset.episodes[0].actions.min() >= -1.0 and dataset.episodes[0].actions.max() <= 1.0


def test_iql_example_trains_and_evaluates_through_bigym_eval(example, demo_store, tmp_path):
    out = tmp_path / "iql"
    # 200 steps: with d3rlpy's default steps per epoch this would train nothing at all
    history = example.train(TASK, out, steps=200, demos=DEMOS, store=demo_store)
    assert len(history) == 1 and np.isfinite(history[0][1]["actor_loss"])
    assert (out / example.MODEL_FILE).is_file() and (out / example.SPACES_FILE).is_file()

    record = tmp_path / "eval.json"
    env = dict(os.environ, BIGYM_IQL_MODEL=str(out))
    bigym = str(Path(sys.executable).with_name("bigym"))
    command = [bigym, "eval", TASK, "--privileged", "--policy", f"{EXAMPLE}:policy"]
    command += ["--episodes", "2", "--workers", "1", "--json", str(record)]
    done = subprocess.run(command, check=False, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    result = json.loads(record.read_text())
    assert [e["seed"] for e in result["episodes"]] == [1_000_000, 1_000_001]
    assert result["fingerprint"]["observation_config"]["privileged_information"] is True


def test_the_policy_refuses_an_env_with_other_observations(example, demo_store, tmp_path, monkeypatch):
    out = tmp_path / "iql"
    example.train(TASK, out, steps=10, demos=1, store=demo_store)
    monkeypatch.setenv("BIGYM_IQL_MODEL", str(out))
    plain = ReachTargetSingle()
    try:
        with pytest.raises(ValueError, match="--privileged"):
            example.policy(plain)
    finally:
        plain.close()


def test_evaluation_runs_on_gymnasium_1_0_and_vector_mode_says_what_it_needs():
    assert gym.__version__.startswith("1.0"), "premise: d3rlpy's pin holds gymnasium at 1.0"
    result = evaluate("bigym.policies:HoldPolicy", TASK, episodes=2, workers=1)
    assert result.summary.episodes == 2
    with pytest.raises(ValueError, match="gymnasium >= 1.1"):
        evaluate("bigym.policies:HoldPolicy", TASK, episodes=2, workers=1, vector="sync")

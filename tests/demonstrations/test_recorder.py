"""DemoRecorder: records whatever drives the env, saves only on request."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import bigym  # noqa: F401  (registers the gymnasium ids)
from bigym.demonstrations import DemoRecorder, replay
from bigym.envs.reach_target import ReachTargetSingle


def test_records_actions_seed_and_checkpoints_without_writing(tmp_path):
    env = ReachTargetSingle(control_frequency=50)
    recorder = DemoRecorder(env, source="teleoperation", checkpoint_interval=4)
    with pytest.raises(RuntimeError, match="reset"):
        recorder.step(np.zeros(16, np.float32))
    recorder.reset()  # no seed given: one is drawn, so the demo stays replayable
    rng = np.random.default_rng(0)
    sent, successes = [], []
    for _ in range(10):
        action = rng.uniform(env.action_space.low, env.action_space.high).astype(np.float32)
        sent.append(action)
        successes.append(recorder.step(action)[4]["is_success"])
    with pytest.raises(ValueError):
        recorder.step(np.full(16, 9.0, np.float32))  # rejected by the env: not recorded
    assert recorder.num_steps == 10 and recorder.recording
    assert list(tmp_path.iterdir()) == []  # nothing written yet
    demo = recorder.to_demo()
    assert not recorder.recording
    np.testing.assert_array_equal(demo.actions, np.array(sent, np.float64))
    assert demo.metadata.seed is not None and demo.metadata.source == "teleoperation"
    assert list(demo.checkpoint_steps) == [4, 8, 10] and demo.metadata.checkpoint_interval == 4
    # the seed is drawn, so random actions occasionally do reach the target
    assert demo.metadata.frequency == 50 and demo.metadata.success is any(successes)
    assert replay(demo).report.checkpoints_checked == 3
    with pytest.raises(RuntimeError, match="nothing recorded"):
        recorder.to_demo()


def test_save_on_request_and_discard(tmp_path):
    env = gym.make("bigym/ReachTargetSingle-v0", control_frequency=100)
    recorder = DemoRecorder(env)
    recorder.reset(seed=4)
    for _ in range(5):
        recorder.step(np.zeros(16, np.float32))
    recorder.discard()
    assert recorder.num_steps == 0 and not recorder.recording
    recorder.reset(seed=5)
    recorder.step(np.zeros(16, np.float32))
    path = recorder.save(tmp_path, success=False)
    assert list(tmp_path.iterdir()) == [path]
    env.close()


def test_refuses_action_wrappers_and_foreign_envs():
    env = gym.wrappers.RescaleAction(ReachTargetSingle(), np.float32(-1), np.float32(1))
    with pytest.raises(TypeError, match="wrap the env in DemoRecorder first"):
        DemoRecorder(env)
    with pytest.raises(TypeError, match="records BiGym envs"):
        DemoRecorder(gym.make("CartPole-v1"))
    with pytest.raises(ValueError, match="source"):
        DemoRecorder(ReachTargetSingle(), source="dream")

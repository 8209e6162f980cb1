"""Flat transitions for offline RL: observations, scaled actions, rewards and episode ends."""

from __future__ import annotations

import dataclasses
import sys

import gymnasium as gym
import numpy as np
import pytest

from bigym.demonstrations import DemoError, make_env, replay_many
from bigym.demonstrations.transitions import FlatSpaces, transitions
from bigym.observations import CameraConfig, ObservationConfig

CONFIG = ObservationConfig(privileged_information=True)


@pytest.fixture(scope="module")
def env_and_demos(expert_demos):
    demo = expert_demos["single_absolute"]
    env = make_env(demo.metadata, CONFIG, 50)
    replayed = replay_many([demo], CONFIG, 50, progress=False)
    yield env, replayed
    env.close()


def test_rows_follow_the_replayed_episodes(env_and_demos):
    env, replayed = env_and_demos
    demo = replayed[0]
    data = transitions(replayed, env)
    steps = len(demo)
    assert len(data) == steps and data.episode_ends.tolist() == [steps]
    assert [s for s in data.episodes()] == [slice(0, steps)]
    spaces = data.spaces
    for t in (0, steps // 2, steps - 1):
        obs = {key: value[t] for key, value in demo.observations.items()}
        after = {key: value[t + 1] for key, value in demo.observations.items()}
        np.testing.assert_array_equal(data.observations[t], spaces.flatten(obs))
        np.testing.assert_array_equal(data.next_observations[t], spaces.flatten(after))
    np.testing.assert_array_equal(data.rewards, demo.rewards.astype(np.float32))
    # the expert's episode ends on its success: a terminal, not a timeout
    assert demo.terminated[-1] and data.terminals.tolist() == demo.terminated.astype(float).tolist()
    assert data.terminals[-1] == 1.0 and data.timeouts.sum() == 0.0 and data.rewards[-1] == 1.0
    assert data.uuids == [demo.uuid]


def test_actions_are_scaled_to_the_unit_box_and_back(env_and_demos):
    env, replayed = env_and_demos
    data = transitions(replayed, env, base="moves")
    assert not data.spaces.base_targets
    assert data.actions.dtype == np.float32
    assert data.actions.min() >= -1.0 and data.actions.max() <= 1.0
    np.testing.assert_allclose(data.spaces.unscale(data.actions), replayed[0].actions, atol=2e-6)
    low, high = env.action_space.low, env.action_space.high
    np.testing.assert_allclose(data.spaces.scale(low), -1.0)
    np.testing.assert_allclose(data.spaces.scale(high), 1.0)
    np.testing.assert_allclose(data.spaces.scale((low + high) / 2), 0.0, atol=1e-6)
    # predictions beyond the box are clipped to the action bounds, never past them
    np.testing.assert_allclose(data.spaces.unscale(np.full(len(low), 3.0)), high, rtol=1e-6)


def test_base_targets_give_back_the_env_actions_and_stay_inside_what_the_demos_visited(env_and_demos):
    env, replayed = env_and_demos
    demo = replayed[0]
    data = transitions(replayed, env)  # base="targets" by default
    spaces = data.spaces
    assert spaces.base_targets and data.actions.min() >= -1.0 and data.actions.max() <= 1.0
    base = list(spaces.base_actions)
    targets = demo.observations["proprioception_floating_base_actions"]
    # a model action is the base target after the step: the next observation's targets
    np.testing.assert_allclose(spaces.unscale(data.actions)[:, base], targets[1:], atol=2e-6)
    # and turns back into the env's move from the target observed before the step
    for t in range(len(demo)):
        obs = {key: value[t] for key, value in demo.observations.items()}
        np.testing.assert_allclose(spaces.env_action(data.actions[t], obs), demo.actions[t], atol=1e-6)
    # a wild prediction becomes a move within the env's bounds, never past them
    obs = {key: value[0] for key, value in demo.observations.items()}
    wild = spaces.env_action(np.full(spaces.action_size, 1.0), obs)
    assert env.action_space.contains(wild)
    # the saved spaces act the same
    loaded = FlatSpaces.from_dict(spaces.to_dict())
    assert loaded.base_actions == spaces.base_actions and loaded.base_observed == spaces.base_observed
    np.testing.assert_array_equal(loaded.env_action(data.actions[-1], obs), spaces.env_action(data.actions[-1], obs))
    with pytest.raises(ValueError, match="targets"):
        transitions(replayed, env, base="deltas")


def test_flat_observations_match_gymnasiums_flatten_wrapper(env_and_demos):
    env, _ = env_and_demos
    spaces = FlatSpaces.from_env(env)
    wrapped = gym.wrappers.FlattenObservation(env)
    flat, _ = wrapped.reset(seed=7)
    obs, _ = env.reset(seed=7)
    np.testing.assert_array_equal(spaces.flatten(obs), flat.astype(np.float32))
    assert spaces.observation_size == flat.shape[0] and spaces.action_size == env.action_space.shape[0]


def test_a_recording_that_stops_before_its_end_is_a_timeout(env_and_demos):
    env, replayed = env_and_demos
    demo = replayed[0]
    cut = len(demo) // 2
    assert not demo.terminated[:cut].any(), "premise: no terminal step in the first half"
    demo = dataclasses.replace(
        demo,
        actions=demo.actions[:cut],
        rewards=demo.rewards[:cut],
        terminated=demo.terminated[:cut],
        truncated=demo.truncated[:cut],
        observations={key: value[: cut + 1] for key, value in demo.observations.items()},
    )
    data = transitions([demo, demo], env)
    assert data.episode_ends.tolist() == [cut, 2 * cut]
    assert data.timeouts.tolist() == ([0.0] * (cut - 1) + [1.0]) * 2 and data.terminals.sum() == 0.0


def test_spaces_round_trip_through_a_file(env_and_demos, tmp_path):
    env, _ = env_and_demos
    spaces = FlatSpaces.from_env(env)
    spaces.save(tmp_path / "spaces.json")
    loaded = FlatSpaces.load(tmp_path / "spaces.json")
    assert loaded.keys == spaces.keys and loaded.sizes == spaces.sizes
    np.testing.assert_array_equal(loaded.action_low, spaces.action_low)
    np.testing.assert_array_equal(loaded.action_high, spaces.action_high)


def test_bad_inputs_are_refused_clearly(env_and_demos):
    env, replayed = env_and_demos
    with pytest.raises(DemoError, match="no demos"):
        transitions([], env)
    with pytest.raises(DemoError, match="lacks"):
        FlatSpaces.from_env(env).flatten({"proprioception": np.zeros(3)})
    cameras = ObservationConfig(cameras=(CameraConfig("head", resolution=(8, 8)),))
    camera_env = make_env(replayed[0].metadata, cameras, 50)
    try:
        with pytest.raises(DemoError, match="rgb_head"):
            FlatSpaces.from_env(camera_env)
    finally:
        camera_env.close()
    # an env that observes less than the demos hold is a mismatch, not a silent drop
    plain_env = make_env(replayed[0].metadata, ObservationConfig(), 50)
    try:
        with pytest.raises(DemoError, match="the env lacks"):
            transitions(replayed, plain_env)
    finally:
        plain_env.close()


def test_to_d3rlpy_without_d3rlpy_says_how_to_install(env_and_demos, monkeypatch):
    env, replayed = env_and_demos
    data = transitions(replayed, env)
    monkeypatch.setitem(sys.modules, "d3rlpy", None)
    monkeypatch.setitem(sys.modules, "d3rlpy.dataset", None)
    with pytest.raises(ImportError, match=r"bigym\[rl\]"):
        data.to_d3rlpy()

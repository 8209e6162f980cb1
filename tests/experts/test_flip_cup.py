"""The FlipCup expert turns the mug over in the hand (``bigym.experts.flip_cup``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case. This checks the way it succeeds: the mug comes up the right way while still held
(turned by the forearm's roll, not dropped or knocked until it lands upright), and both
roll directions of the right hand are drawn.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.manipulation import FlipCup
from bigym.experts.flip_cup import MUG, FlipCupExpert


@pytest.fixture(scope="module")
def env():
    env = FlipCup(action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500)
    yield env
    env.close()


def test_the_mug_is_upright_in_the_hand_before_it_is_set_down(env):
    obs, _ = env.reset(seed=0)
    expert = FlipCupExpert(env, seed=0)
    body = env.props[MUG].root_body_id
    up_at_start = float(env.data.xmat[body][8])
    for _ in range(env.max_episode_steps):
        obs, *_ = env.step(expert(obs))
        if expert.events and expert.events[-1][1].startswith("set down"):
            break
    else:
        pytest.fail(f"the expert never set the mug down: {expert.events}")
    assert up_at_start < -0.99  # it started upside down
    assert env.held(MUG)
    assert float(env.data.xmat[body][8]) > np.cos(np.deg2rad(20.0))  # turned over in the hand
    assert not expert.touches_support(MUG)  # held up in the air, not resting


def test_the_hand_and_the_roll_direction_vary(env):
    seen = set()
    for seed in range(16):
        obs, _ = env.reset(seed=seed)
        expert = FlipCupExpert(env, seed=seed)
        expert(obs)  # the plan draws its choices before the first movement
        seen.add((expert.choices["hand"], expert.choices["roll"]))
    assert {("right", "clockwise"), ("right", "anticlockwise"), ("left", "clockwise")} <= seen

"""The FlipCutlery expert turns the spoon bowl-down in the hand (``bigym.experts.flip_cutlery``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case. This checks the way it succeeds: the spoon is out of the mug, bowl down and upright,
still held over the mug before it is let go (turned by the forearm, not knocked over in
the mug), and either hand is drawn.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.manipulation import FlipCutlery
from bigym.experts.flip_cutlery import SPOON, FlipCutleryExpert


@pytest.fixture(scope="module")
def env():
    env = FlipCutlery(action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500)
    yield env
    env.close()


def test_the_spoon_is_bowl_down_in_the_hand_over_the_mug_before_it_is_let_go(env):
    obs, _ = env.reset(seed=0)
    expert = FlipCutleryExpert(env, seed=0)
    axis = env.data.xmat[env.props[SPOON].root_body_id].reshape(3, 3)[:, 1]  # handle to bowl
    bowl_up_at_start = float(axis[2])
    bowl_down_while_held = None
    for _ in range(env.max_episode_steps):
        obs, *_ = env.step(expert(obs))
        if expert.events and expert.events[-1][1].startswith("grip") and expert.events[-1][1].endswith(" 0"):
            break  # the fingers open: what came before was done in the hand
        if env.held(SPOON) and axis[2] < -0.9:
            bowl_down_while_held = float(axis[2])
    else:
        pytest.fail(f"the expert never let the spoon go: {expert.events}")
    assert bowl_up_at_start > 0.85  # it started bowl up in the mug
    assert bowl_down_while_held is not None, "the spoon was never held bowl down"
    head = env.data.site_xpos[env.props[SPOON].site_id("head")]
    inside = env.data.site_xpos[env.props["mug"].site_id("inside")]
    assert np.linalg.norm(head[:2] - inside[:2]) < 0.03  # let go over the mug's middle
    assert axis[2] < -np.cos(np.deg2rad(25.0))  # stood upright, bowl first


def test_either_hand_takes_the_spoon(env):
    hands = set()
    for seed in range(8):
        obs, _ = env.reset(seed=seed)
        expert = FlipCutleryExpert(env, seed=seed)
        expert(obs)  # the plan draws its choices before the first movement
        hands.add(expert.choices["hand"])
    assert hands == {"left", "right"}

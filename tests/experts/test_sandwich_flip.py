"""The SandwichFlip expert turns the sandwich over with the spatula and settles it by
tilting the pan (``bigym.experts.sandwich_flip``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case. This checks the way it succeeds: no gripper ever touches the sandwich; it is upside
down before the other hand takes the pan (turned by the blade, not by the pan); the blade,
set down steeply, stays clear of the pan's near rim, so that the spatula does not turn in
the hand; the pan is then lifted off the hob and tilted; the episode ends with the sandwich
upside down and flat in the pan, back on the hob, and no hand on the pan.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.sandwich import SandwichFlip
from bigym.experts.expert import LEFT
from bigym.experts.geometry import rotation_log
from bigym.experts.sandwich import PAN, SANDWICH, SPATULA
from bigym.experts.sandwich_flip import SandwichFlipExpert

SEED = 11
#: the steps of the turn, in which the blade is steered tipped steeply
TURN_STEPS = ("set down", "draw back", "lift")


@pytest.fixture(scope="module")
def env():
    env = SandwichFlip(action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500)
    yield env
    env.close()


def test_the_blade_turns_the_sandwich_over_and_the_tilted_pan_lays_it_flat(env):
    obs, _ = env.reset(seed=SEED)
    expert = SandwichFlipExpert(env, seed=SEED)
    pan, sandwich = env.props[PAN].root_body_id, env.props[SANDWICH].root_body_id
    hob = env.mask("cabinet_1", "hob")
    spatula, pinch = env.props[SPATULA].root_body_id, env.robot.pinch_site_ids[LEFT]
    up_when_pan_taken = None
    most_pan_tilt = 0.0
    lifted = False
    in_hand = None  # how the spatula sat in the hand as the set-down began
    most_turn_in_hand = 0.0
    info: dict = {}
    for _ in range(env.max_episode_steps):
        obs, _, terminated, _, info = env.step(expert(obs))
        if expert.finished:
            break
        assert not env.held(SANDWICH)
        assert not terminated or info.get("is_success"), f"failed: {expert.events}"
        if expert.events and expert.events[-1][1] in TURN_STEPS:
            sits = env.data.xmat[spatula].reshape(3, 3).T @ env.data.site_xmat[pinch].reshape(3, 3)
            in_hand = sits if in_hand is None else in_hand
            turned = float(np.degrees(np.linalg.norm(rotation_log(sits @ in_hand.T))))
            most_turn_in_hand = max(most_turn_in_hand, turned)
        if env.held(PAN):
            if up_when_pan_taken is None:
                up_when_pan_taken = float(env.data.xmat[sandwich][8])
            lifted = lifted or not env.touching(env.mask(PAN), hob)
            most_pan_tilt = max(most_pan_tilt, float(np.degrees(np.arccos(env.data.xmat[pan][8]))))
    assert expert.finished, f"the plan did not end: {expert.events}"
    assert up_when_pan_taken is not None and up_when_pan_taken < 0.0  # turned over by the blade
    # laid across the rim, the blade was levered round in the hand by 17 degrees on this
    # seed (by 40-70 where the spatula then fell out of the hand)
    assert in_hand is not None and most_turn_in_hand < 6.0
    assert lifted and most_pan_tilt > 20.0
    for _ in range(250):  # half a second more, hands off
        obs, _, _, _, info = env.step(expert(obs))
    assert info.get("is_success"), expert.events
    assert env.data.xmat[sandwich][8] < -np.cos(np.deg2rad(10.0))
    assert env.touching(env.mask(PAN), hob) and not env.held(PAN)

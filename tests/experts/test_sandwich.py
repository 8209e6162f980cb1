"""The SandwichRemove expert lifts the sandwich out on the spatula (``bigym.experts.sandwich``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case. This checks the way it succeeds: the sandwich leaves the pan riding on the blade,
over the rim, touched by nothing but the spatula (not pushed or dragged over the rim),
the pan stays on the hob, and the sandwich ends on the board.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.sandwich import PAN_FLOOR, SandwichRemove
from bigym.experts.sandwich import GRIP, PAN, REGRIP_SHORT, SANDWICH, SPATULA, SandwichRemoveExpert
from bigym.props import FryingPan, Sandwich


@pytest.fixture(scope="module")
def env():
    env = SandwichRemove(action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500)
    yield env
    env.close()


def test_the_sandwich_rides_out_of_the_pan_on_the_blade_onto_the_board(env):
    obs, _ = env.reset(seed=0)
    expert = SandwichRemoveExpert(env, seed=0)
    sandwich, pan = env.props[SANDWICH], env.props[PAN]
    pan_start = pan.get_pose(env.data)[0].copy()
    floor = pan_start[2] + PAN_FLOOR
    others = ~(env.mask(SANDWICH).mask | env.mask(SPATULA).mask)  # every other geom
    highest_on_blade = 0.0
    for _ in range(env.max_episode_steps):
        obs, reward, terminated, truncated, _ = env.step(expert(obs))
        if terminated or truncated:
            break
        bottom = sandwich.get_pose(env.data)[0][2] - Sandwich.SIZE[2] / 2 - floor
        touches_spatula = env.touching(env.mask(SANDWICH), env.mask(SPATULA))
        # on the spatula alone
        if bottom > highest_on_blade and touches_spatula and not env.touching(env.mask(SANDWICH).mask, others):
            highest_on_blade = bottom
    assert terminated and reward > 0, f"no success: {expert.events}"
    assert highest_on_blade > FryingPan.DEPTH  # carried over the rim on the blade alone
    assert env.touching(env.mask(SANDWICH), env.mask("board"))
    assert np.linalg.norm(pan.get_pose(env.data)[0] - pan_start) < 0.02  # the pan stayed put


def test_the_blade_goes_in_square_to_a_face_of_the_sandwich(env):
    faces = set()
    for seed in range(6):
        obs, _ = env.reset(seed=seed)
        expert = SandwichRemoveExpert(env, seed=seed)
        while "face" not in expert.choices:
            obs, *_ = env.step(expert(obs))
        faces.add(expert.choices["face"])
    assert len(faces) > 1  # which face depends on how the sandwich lies: not always the same


def test_a_hand_that_closed_on_the_handles_end_takes_it_further_up(env):
    # on seed 10 the fingers shove the spatula along as they slide in and close on the
    # handle's last 3 cm; the hand must slide up and hold it near GRIP before pushing
    obs, _ = env.reset(seed=10)
    expert = SandwichRemoveExpert(env, seed=10)
    obs, *_ = env.step(expert(obs))
    while not any(text == "slide under" for _, text in expert.events):
        obs, *_ = env.step(expert(obs))
        assert env.data.time < 15.0, f"never got to the push: {expert.events}"
    assert any("further up" in text for _, text in expert.events)
    assert GRIP[1] - expert.held[0][1] <= REGRIP_SHORT

"""The DishwasherUnloadCups expert (``bigym.experts.dishwasher_unload_cups``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case (which also rejects a mug dropped on the counter). This checks the way it succeeds:
each mug ends upside down, resting on the counter, one on either side of the robot; and
that the hand of the front mug goes first when one mug stands behind the other.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.dishwasher_cups import DishwasherUnloadCups
from bigym.envs.dishwasher_plates import COUNTER_TOP
from bigym.experts.dishwasher_unload_cups import CupUnloadExpert
from bigym.experts.expert import SIDE_INDEX


@pytest.fixture(scope="module")
def env():
    env = DishwasherUnloadCups(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500
    )
    yield env
    env.close()


def test_each_mug_ends_upside_down_resting_on_the_counter(env, run_episode):
    obs, _ = env.reset(seed=0)
    expert = CupUnloadExpert(env, seed=0)
    info = run_episode(env, expert, obs)
    assert info.get("is_success"), expert.events
    ys = []
    for mug in env.items:
        prop = env.props[mug]
        body = prop.root_body_id
        assert env.data.xmat[body].reshape(3, 3)[2, 2] < -np.cos(np.deg2rad(5.0)), mug  # upside down, flat
        assert abs(env.data.xpos[body][2] - (COUNTER_TOP + prop.height)) < 0.005, mug  # its rim on the counter
        assert env.touching(env.mask(mug), env.target_mask) and not env.held(mug)
        ys.append(env.data.xpos[body][1])
    assert abs(ys[0] - ys[1]) > 0.2  # apart, one put down by each hand


def test_the_front_mugs_hand_goes_first(env):
    seen = 0
    for seed in range(12):
        obs, _ = env.reset(seed=seed)
        centres = {mug: env.data.xpos[env.props[mug].root_body_id].copy() for mug in env.items}
        expert = CupUnloadExpert(env, seed=seed)
        env.step(expert(obs))
        first = SIDE_INDEX[expert.choices["first taken"]]
        mine = expert.mug_of[first]
        other = next(mug for mug in env.items if mug != mine)
        if abs(centres[mine][1] - centres[other][1]) < 0.05:  # one behind the other
            seen += 1
            assert centres[mine][0] < centres[other][0]
    assert seen > 0

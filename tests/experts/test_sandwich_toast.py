"""The SandwichToast expert sweeps the sandwich into the pan held at the counter's edge
(``bigym.experts.sandwich_toast``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case. This checks the way it succeeds: the sandwich first touches the pan while the pan is
held in front of the counter, low against its edge (swept in, not lifted or pushed over the
rim on the hob), held level, touched by no gripper, never touched by the spatula's hand
(left over the pan, its links rubbed on the rim and pushed it out of the other hand), and
the pan ends back on the hob with the sandwich lying flat in it.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.sandwich import SandwichToast
from bigym.experts.expert import LEFT
from bigym.experts.sandwich import PAN, SANDWICH
from bigym.experts.sandwich_toast import COUNTER_FRONT, COUNTER_TOP, SandwichToastExpert
from bigym.props import FryingPan


@pytest.fixture(scope="module")
def env():
    env = SandwichToast(action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500)
    yield env
    env.close()


def test_the_sandwich_is_swept_into_the_pan_held_below_the_counters_edge(env):
    obs, _ = env.reset(seed=0)
    expert = SandwichToastExpert(env, seed=0)
    pan = env.props[PAN]
    sandwich_mask, pan_mask = env.mask(SANDWICH), env.mask(PAN)
    spatula_hand = env.contacts.geom_set(env.robot.gripper_geom_ids_by_side[LEFT])
    pan_when_entered = None
    tilt_when_entered = None
    for _ in range(env.max_episode_steps):
        obs, reward, terminated, truncated, _ = env.step(expert(obs))
        assert not env.held(SANDWICH)
        assert not env.touching(spatula_hand, pan_mask), f"the spatula's hand touched the pan at {expert.time:.2f} s"
        if pan_when_entered is None and env.touching(sandwich_mask, pan_mask):
            pan_when_entered = pan.get_pose(env.data)[0].copy()
            tilt_when_entered = float(np.degrees(np.arccos(env.data.xmat[pan.root_body_id][8])))
        if terminated or truncated:
            break
    assert terminated and reward > 0, f"no success: {expert.events}"
    assert pan_when_entered is not None
    assert pan_when_entered[0] + FryingPan.RADIUS < COUNTER_FRONT  # held in front of the counter
    assert pan_when_entered[2] < COUNTER_TOP - 0.03  # held low against the edge (on the hob it is at 0.87)
    assert tilt_when_entered < 5.0  # held level: the hand turns it by how far it is seen to tilt
    assert env.touching(pan_mask, env.mask("cabinet_1", "hob"))  # back on the hob
    assert abs(env.data.xmat[env.props[SANDWICH].root_body_id][8]) > np.cos(np.deg2rad(10.0))

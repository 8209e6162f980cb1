"""The TakeCups expert (``bigym.experts.take_cups``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case (which also rejects a mug dropped on the way). This checks the way it succeeds: both
glass doors are opened, both mugs come off the shelf and end upright on the counter in
front of the cabinet, apart, let go.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.pick_and_place import COUNTER_TOP, TakeCups
from bigym.experts.put_cups import CABINET, CABINET_FRONT, DOORS
from bigym.experts.take_cups import DOOR_MARGIN, TakeCupsExpert


@pytest.fixture(scope="module")
def env():
    env = TakeCups(action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500)
    yield env
    env.close()


def test_both_mugs_end_upright_on_the_counter_with_both_doors_open(env, run_episode):
    obs, _ = env.reset(seed=21)
    expert = TakeCupsExpert(env, seed=21)
    info = run_episode(env, expert, obs)
    assert info.get("is_success"), expert.events
    for door in DOORS:
        assert expert.joint_state(CABINET, door) > 1.0 - DOOR_MARGIN, door
    ys = []
    for mug in env.objects:
        body = env.props[mug].root_body_id
        assert env.data.xmat[body].reshape(3, 3)[2, 2] > np.cos(np.deg2rad(5.0)), mug  # upright, flat
        assert abs(env.data.xpos[body][2] - COUNTER_TOP) < 0.005, mug  # its base on the counter
        assert env.data.xpos[body][0] < CABINET_FRONT - 0.05, mug  # out from under the wall cabinet
        assert env.object_placed(mug) and not env.held(mug)
        ys.append(env.data.xpos[body][1])
    assert abs(ys[0] - ys[1]) > 0.1  # side by side, not touching

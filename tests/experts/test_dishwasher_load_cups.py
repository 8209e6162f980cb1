"""The DishwasherLoadCups expert (``bigym.experts.dishwasher_load_cups``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case (which also rejects a mug dropped onto the tray). This checks the way it succeeds:
each mug ends upside down, resting on the upper tray's floor in its front half, the left
hand's mug further left; the tray is not pushed in on the way; and which mug is put down
first varies.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.dishwasher_cups import DishwasherLoadCups
from bigym.envs.dishwasher_plates import DISHWASHER
from bigym.experts.dishwasher_load_cups import CupLoadExpert
from bigym.experts.expert import LEFT, RIGHT


@pytest.fixture(scope="module")
def env():
    env = DishwasherLoadCups(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500
    )
    yield env
    env.close()


def test_each_mug_ends_upside_down_on_the_trays_front_half(env, run_episode):
    obs, _ = env.reset(seed=1)
    expert = CupLoadExpert(env, seed=1)
    slide = env.model.jnt_qposadr[env.model.joint(f"{DISHWASHER}/tray_mid").id]
    start = float(env.data.qpos[slide])
    # the left hand takes the mug further left (+y)
    left_mug, right_mug = sorted(env.items, key=lambda mug: -env.data.xpos[env.props[mug].root_body_id][1])
    info = run_episode(env, expert, obs)
    assert info.get("is_success"), expert.events
    assert abs(float(env.data.qpos[slide]) - start) < 0.01, "the tray was pushed"  # nobody leant on it
    floor = int(np.flatnonzero(expert.tray_floor)[0])
    floor_top = env.data.geom_xpos[floor, 2] + env.model.geom_size[floor, 2]
    front = env.data.geom_xpos[floor, 0] - env.model.geom_size[floor, 0]
    ys = {}
    for side, mug in ((LEFT, left_mug), (RIGHT, right_mug)):
        prop = env.props[mug]
        body = prop.root_body_id
        frame = env.data.xmat[body].reshape(3, 3)
        assert frame[2, 2] < -np.cos(np.deg2rad(5.0)), mug  # upside down, flat
        origin = env.data.xpos[body]
        assert abs(origin[2] - (floor_top + prop.height)) < 0.005, mug  # its rim on the floor
        # in the front half: between the tray's front wall and its middle divider
        assert 0.0 < origin[0] - front - prop.radius < 0.23, (mug, origin)
        ys[side] = origin[1]
    assert ys[LEFT] - ys[RIGHT] > 0.2  # apart, the left hand's on the left
    # put down in the order it chose
    puts = [event.split()[-1] for _, event in expert.events if event.startswith("put ")]
    assert puts == (["L", "R"] if expert.choices["first put down"] == "left" else ["R", "L"])

"""The PutCups expert (``bigym.experts.put_cups``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case (which also rejects a mug dropped on the way). This checks the way it succeeds: one
glass door is opened, and both mugs end upright on the shelf in that door's half, one
behind the other.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.pick_and_place import WALL_SHELF_BOTTOM_TOP, PutCups
from bigym.experts.put_cups import CABINET, MUG_GAP, PutCupsExpert


@pytest.fixture(scope="module")
def env():
    env = PutCups(action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500)
    yield env
    env.close()


def test_both_mugs_end_upright_behind_the_one_open_door(env, run_episode):
    obs, _ = env.reset(seed=1)
    expert = PutCupsExpert(env, seed=1)
    info = run_episode(env, expert, obs)
    assert info.get("is_success"), expert.events
    (job,) = expert.choices["hands"]
    door = job.split(":")[0].removeprefix(f"{CABINET}/")
    other = "door_left" if door == "door_right" else "door_right"
    assert expert.joint_state(CABINET, door) > 0.8 and expert.joint_state(CABINET, other) < 0.1
    half = 1.0 if door == "door_right" else -1.0  # door_right covers the +y half
    xs = []
    for mug in env.objects:
        body = env.props[mug].root_body_id
        assert env.data.xmat[body].reshape(3, 3)[2, 2] > np.cos(np.deg2rad(5.0)), mug  # upright, flat
        assert abs(env.data.xpos[body][2] - WALL_SHELF_BOTTOM_TOP) < 0.005, mug  # its base on the shelf
        assert half * env.data.xpos[body][1] > 0.03, mug  # in the open door's half
        assert env.object_placed(mug)
        xs.append(env.data.xpos[body][0])
    assert abs(xs[0] - xs[1]) > MUG_GAP - 0.02  # one behind the other


def test_the_body_stands_on_the_open_halfs_side_before_the_mugs_go_in(env):
    """Seed 47 took the mugs standing 7 cm across the cabinet's middle from the open half:
    reaching in at the back of the half, the elbow met the open door and the mug was let go
    short of the shelf. The body now steps over before the mugs go up."""
    from bigym.experts.put_cups import STAND_INTO_HALF

    obs, _ = env.reset(seed=47)
    expert = PutCupsExpert(env, seed=47)
    across_at_put = None
    info: dict = {}
    for _ in range(env.max_episode_steps):
        obs, _, terminated, truncated, info = env.step(expert(obs))
        if across_at_put is None and any(e.startswith("put ") for _, e in expert.events):
            across_at_put = float(expert.base_pose()[1])  # where the body stands as the first goes up
        if terminated or truncated:
            break
    assert info.get("is_success"), expert.events
    (job,) = expert.choices["hands"]
    half = 1.0 if job.split(":")[0].endswith("door_right") else -1.0
    assert across_at_put is not None and half * across_at_put >= STAND_INTO_HALF - 0.005

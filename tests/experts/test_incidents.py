"""The generator's incident watch: drops and objects pushed into surfaces are named; a quiet
scene and a task without free objects give nothing."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from bigym.envs.manipulation import StackBlocks
from bigym.envs.reach_target import ReachTargetSingle
from bigym.experts.incidents import IncidentWatch
from bigym.policies import HoldPolicy


@pytest.fixture()
def blocks():
    env = StackBlocks(control_frequency=500)
    yield env
    env.close()


def run(env, watch: IncidentWatch, steps: int) -> list[str]:
    """Hold the robot still for ``steps`` steps; every incident the watch names."""
    policy = HoldPolicy(env)
    found = []
    for _ in range(steps):
        env.step(policy(None))
        incident = watch.check()
        if incident is not None:
            found.append(incident)
    return found


def test_blocks_resting_on_the_table_are_no_incident(blocks):
    blocks.reset(seed=0)
    watch = IncidentWatch(blocks)
    assert watch.names == ["block_1", "block_2", "block_3"]
    assert run(blocks, watch, 300) == []


def test_a_block_falling_from_a_height_is_a_drop(blocks):
    blocks.reset(seed=0)
    x, y, _ = blocks.data.xpos[blocks.props["block_2"].root_body_id]
    blocks.props["block_2"].set_pose(blocks.data, (x, y, 1.3), (1.0, 0.0, 0.0, 0.0))
    watch = IncidentWatch(blocks)
    found = run(blocks, watch, 300)
    assert found and found[0].startswith("block_2 dropped at t=")


def test_a_block_sunk_into_the_table_is_pushed_into_a_surface(blocks):
    blocks.reset(seed=0)
    x, y, _ = blocks.data.xpos[blocks.props["block_3"].root_body_id]
    blocks.props["block_3"].set_pose(blocks.data, (x, y, 0.95 + 0.025 - 0.012), (1.0, 0.0, 0.0, 0.0))
    mujoco.mj_forward(blocks.model, blocks.data)
    watch = IncidentWatch(blocks)
    assert watch.check() is not None and "block_3 pushed into a surface" in watch.check()


def test_a_task_without_free_objects_has_nothing_to_watch():
    env = ReachTargetSingle(control_frequency=500)
    try:
        env.reset(seed=0)
        watch = IncidentWatch(env)
        assert watch.names == [] and np.size(watch.bodies) == 0
        assert run(env, watch, 50) == []
    finally:
        env.close()


def test_a_fall_within_the_objects_own_allowance_is_no_drop(blocks):
    # a block let fall ~8 cm (about 1.25 m/s when it lands), as a spoon is let go into a mug
    blocks.reset(seed=0)
    x, y, z = blocks.data.xpos[blocks.props["block_2"].root_body_id]
    blocks.props["block_2"].set_pose(blocks.data, (x, y, z + 0.08), (1.0, 0.0, 0.0, 0.0))
    state = blocks.data.qpos.copy(), blocks.data.qvel.copy(), blocks.data.time
    assert run(blocks, IncidentWatch(blocks), 250)[0].startswith("block_2 dropped at t=")
    blocks.data.qpos[:], blocks.data.qvel[:], blocks.data.time = state
    assert run(blocks, IncidentWatch(blocks, {"block_2": 1.6}), 250) == []
    blocks.data.qpos[:], blocks.data.qvel[:], blocks.data.time = state
    # the allowance is the named object's alone
    blocks.props["block_3"].set_pose(blocks.data, (x + 0.2, y, z + 0.08), (1.0, 0.0, 0.0, 0.0))
    assert run(blocks, IncidentWatch(blocks, {"block_2": 1.6}), 250)[0].startswith("block_3 dropped at t=")


def test_an_allowance_for_an_object_the_task_lacks_is_refused(blocks):
    with pytest.raises(ValueError, match="spoon"):
        IncidentWatch(blocks, {"spoon": 1.6})

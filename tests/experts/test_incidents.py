"""The generator's incident watch: drops, objects knocked over and objects pushed into
surfaces are named; a quiet scene, a held object turned over and a task without free
objects give nothing."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
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
    blocks.props["block_3"].set_pose(blocks.data, (x, y - 0.12, z + 0.08), (1.0, 0.0, 0.0, 0.0))
    assert run(blocks, IncidentWatch(blocks, {"block_2": 1.6}), 250)[0].startswith("block_3 dropped at t=")


def test_an_allowance_for_an_object_the_task_lacks_is_refused(blocks):
    with pytest.raises(ValueError, match="spoon"):
        IncidentWatch(blocks, {"spoon": 1.6})


def tip_onto_its_side(env, name: str) -> None:
    """Turn a resting block a quarter turn about x where it stands (a cube rests the same)."""
    prop = env.props[name]
    position = env.data.xpos[prop.root_body_id].copy()
    half = np.sqrt(0.5)
    prop.set_pose(env.data, position, (half, half, 0.0, 0.0))
    mujoco.mj_forward(env.model, env.data)


def test_a_block_tipped_over_while_no_hand_holds_it_is_knocked_over(blocks):
    blocks.reset(seed=0)
    watch = IncidentWatch(blocks)
    assert watch.check() is None  # upright, as it stood at the start
    tip_onto_its_side(blocks, "block_2")
    incident = watch.check()
    assert incident is not None and incident.startswith("block_2 knocked over at t=")
    assert "tilted 90 deg unheld" in incident


def test_an_object_the_demonstrator_may_tip_is_not_knocked_over(blocks):
    blocks.reset(seed=0)
    watch = IncidentWatch(blocks, may_tip=["block_2"])
    assert watch.check() is None
    tip_onto_its_side(blocks, "block_2")
    assert watch.check() is None
    assert np.degrees(watch.peak_tilt[watch.names.index("block_2")]) == pytest.approx(90.0, abs=0.5)
    tip_onto_its_side(blocks, "block_3")  # the exemption is the named object's alone
    assert watch.check().startswith("block_3 knocked over")
    with pytest.raises(ValueError, match="may_tip names \\['spoon'\\]"):
        IncidentWatch(blocks, may_tip=["spoon"])


def test_a_mug_turned_over_in_the_hand_is_held_not_knocked_over():
    # FlipCup: the expert grips the mug from two sides and turns it over; the watch sees
    # it held, follows its turn, and the mug stands as it was let go
    from bigym.envs.manipulation import FlipCup
    from bigym.experts import make_expert

    env = FlipCup(action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500)
    try:
        obs, _ = env.reset(seed=0)
        expert = make_expert(env, seed=0)
        watch = IncidentWatch(env, expert.drop_speeds, expert.may_tip)
        start_up = env.data.xmat[watch.bodies[0], 6:9].copy()
        held_steps, incidents, success = 0, [], False
        for _ in range(4000):  # its demo on seed 0 lasts 3692 steps
            obs, _, terminated, truncated, info = env.step(expert(obs))
            held_steps += int(watch.held()[0])
            incident = watch.check()
            if incident is not None:
                incidents.append(incident)
            success = success or info["is_success"]
            if terminated or truncated:
                break
        turned = np.degrees(np.arccos(np.clip(env.data.xmat[watch.bodies[0], 6:9] @ start_up, -1, 1)))
        assert success and incidents == []
        assert held_steps > 500 and turned > 150.0
        assert np.degrees(watch.peak_tilt[0]) < 20.0
    finally:
        env.close()


def test_every_expert_names_only_objects_of_its_tasks_as_allowed_to_fall_or_tip():
    # a name that is not a free object of the task would make every attempt of it fail
    from bigym.demonstrations.player import resolve_task
    from bigym.experts import EXPERTS, expert_class

    checked = 0
    for task in EXPERTS:
        expert = expert_class(task)
        if not (expert.drop_speeds or expert.may_tip):
            continue
        env = resolve_task(task)(control_frequency=500)
        try:
            IncidentWatch(env, expert.drop_speeds, expert.may_tip)
        finally:
            env.close()
        checked += 1
    assert checked >= 4  # flip_cutlery, both cutlery unloads, sandwich_remove


def test_one_finger_against_an_object_is_no_hold_so_a_tip_it_gives_is_a_knock(blocks):
    # a single finger pad touching a block only pushes it: the block's tilt keeps counting
    # from how it stood, and a quarter turn there is a knock; held from two sides (the
    # FlipCup test above) the reference would follow it
    blocks.reset(seed=0)
    model, data = blocks.model, blocks.data
    watch = IncidentWatch(blocks)
    assert watch.check() is None
    pad, other = model.geom("left_gripper/left_pad1").id, model.geom("left_gripper/right_pad1").id
    frame = data.geom_xmat[pad].reshape(3, 3)
    thin = int(np.argmin(model.geom_size[pad]))
    inward = frame[:, thin] * np.sign(frame[:, thin] @ (data.geom_xpos[other] - data.geom_xpos[pad]))
    block = blocks.props["block_2"]
    half = float(model.geom_size[block.collision_geom_ids[0]][0])  # a cube
    centre = data.geom_xpos[pad] + inward * (model.geom_size[pad][thin] + half - 0.0005)
    root = np.sqrt(0.5)
    block.set_pose(data, centre, (root, root, 0.0, 0.0))  # a quarter turn
    mujoco.mj_forward(model, data)
    mask = blocks.mask("block_2")
    not_gripper = np.ones(model.ngeom, dtype=bool)
    not_gripper[blocks.robot.gripper_geom_ids] = False
    assert blocks.touching(mask, blocks.contacts.geom_set([pad]))
    assert not blocks.touching(mask, blocks.contacts.geom_set([other]))
    assert not blocks.touching(mask, not_gripper)  # nothing but the gripper touches it
    assert not watch.held()[watch.names.index("block_2")]
    incident = watch.check()
    assert incident is not None and incident.startswith("block_2 knocked over at t=")

"""Resets at rest, success states and near misses of the table-top tasks: StackBlocks,
FlipCup, FlipCutlery, MovePlate, MoveTwoPlates."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from bigym.envs import manipulation, move_plates
from bigym.observations import ObservationConfig
from bigym.props.base import quat_axis_angle, quat_mul, quat_yaw

from testkit import task_state

TASKS = [
    manipulation.StackBlocks,
    manipulation.FlipCup,
    manipulation.FlipCutlery,
    move_plates.MovePlate,
    move_plates.MoveTwoPlates,
]
STATE = mujoco.mjtState.mjSTATE_INTEGRATION
_ENVS: dict[type, object] = {}


def _env(cls):
    """One env per task class for the whole module (building one takes ~0.5 s)."""
    if cls not in _ENVS:
        _ENVS[cls] = cls(observation_config=ObservationConfig(privileged_information=True))
    return _ENVS[cls]


@pytest.fixture(scope="module", autouse=True)
def _close_envs():
    yield
    for env in _ENVS.values():
        env.close()
    _ENVS.clear()


def _zero(env) -> np.ndarray:
    return np.zeros(env.action_space.shape, np.float32)


def _settle(env, steps: int = 25) -> None:
    """Let the physics run ``steps`` control steps with the robot holding still."""
    for _ in range(steps):
        env.step(_zero(env))


def _forward(env) -> None:
    mujoco.mj_forward(env.model, env.data)


def _quat_of(env, prop: str) -> np.ndarray:
    return env.props[prop].get_pose(env.data)[1]


def _rotation(quat) -> np.ndarray:
    out = np.zeros(9)
    mujoco.mju_quat2Mat(out, np.asarray(quat, float))
    return out.reshape(3, 3)


def _gap(env, prop: str, other_geoms) -> float:
    """Smallest signed distance between the collision geoms of ``prop`` and ``other_geoms``."""
    fromto = np.zeros(6)
    return min(
        mujoco.mj_geomDistance(env.model, env.data, int(a), int(b), 0.5, fromto)
        for a in env.props[prop].collision_geom_ids
        for b in other_geoms
    )


def _drop_onto(env, prop: str, other_geoms, depth: float = 1e-4) -> None:
    """Lower free ``prop`` straight down until it just presses into ``other_geoms``
    (bisection on its height: 0 to 2 ``depth`` of penetration)."""
    _forward(env)
    pos, quat = env.props[prop].get_pose(env.data)

    def gap_at(dz: float) -> float:
        env.props[prop].set_pose(env.data, pos + (0.0, 0.0, dz), quat)
        _forward(env)
        return _gap(env, prop, other_geoms)

    high = 0.0
    while gap_at(high) <= 0.0:  # first lift it clear
        high += 0.02
    low = high
    while gap_at(low) >= 0.0:  # then lower it in 2 mm steps until it first penetrates
        high, low = low, low - 0.002
    for _ in range(40):
        mid = 0.5 * (high + low)
        gap = gap_at(mid)
        if -2 * depth < gap < 0.0:
            return
        if gap >= 0.0:
            high = mid
        else:
            low = mid
    raise AssertionError(f"could not rest {prop} on the given geoms")


def _grip(env, point) -> None:
    """Move the robot base (x, y, z) so that a pad of its left gripper sits at ``point``:
    the gripper then touches whatever surface passes through ``point``."""
    robot = env.robot
    pad = next(g for g in robot.gripper_geom_ids_by_side[0] if env.model.geom(g).name.endswith("right_pad1"))
    _forward(env)
    delta = np.asarray(point, float) - env.data.geom_xpos[pad]
    for axis, dof in enumerate(("x", "y", "z")):
        env.data.qpos[robot.base_qpos[dof]] += delta[axis]
    _forward(env)
    assert np.allclose(env.data.geom_xpos[pad], point, atol=1e-6)


# --------------------------------------------------------------------------- all tasks
@pytest.mark.parametrize("cls", TASKS, ids=lambda c: c.__name__)
def test_reset_is_seeded_and_starts_unsolved(cls):
    env = _env(cls)
    states = []
    for seed in (0, 0, 1, 2, 3):
        obs, info = env.reset(seed=seed)
        assert not info["is_success"] and not env._success() and not env._failure()
        assert env.observation_space.contains(obs)
        state = np.zeros(mujoco.mj_stateSize(env.model, STATE))
        mujoco.mj_getState(env.model, env.data, state, STATE)
        states.append(state)
    assert np.array_equal(states[0], states[1]), "same seed, different reset"
    scenes = []
    for seed in (0, 1):
        env.reset(seed=seed)
        scenes.append(task_state(env))
    assert not np.array_equal(scenes[0], scenes[1]), "different seeds place the task's objects the same way"
    assert 5.0 <= env.time_limit <= 120.0


@pytest.mark.parametrize("cls", TASKS, ids=lambda c: c.__name__)
def test_objects_start_at_rest(cls):
    """2 s of zero actions after reset move no object more than a few mm and never end
    the episode; no object starts in contact with the robot."""
    env = _env(cls)
    free = env._free_props
    robot_geoms = np.isin(env.model.geom_bodyid, env.robot.body_ids)
    for seed in (5, 6):
        env.reset(seed=seed)
        start = {name: prop.get_pose(env.data) for name, prop in free.items()}
        for name in free:
            assert not env.touching(env.mask(name), robot_geoms), f"{name} starts touching the robot"
        for _ in range(100):
            _, reward, terminated, truncated, info = env.step(_zero(env))
            assert not terminated and reward == 0.0 and "unstable" not in info
        for name, prop in free.items():
            pos, quat = prop.get_pose(env.data)
            assert np.linalg.norm(pos - start[name][0]) < 0.003, f"{name} moved (seed {seed})"
            assert abs(np.dot(quat, start[name][1])) > np.cos(np.deg2rad(1.0) / 2), f"{name} turned (seed {seed})"


def test_randomised_static_props_report_their_pose():
    env = _env(manipulation.StackBlocks)
    obs, _ = env.reset(seed=4)
    pad = env.props["target_pad"]
    assert np.allclose(obs["target_pad_pose"][:3], env.data.xpos[pad.root_body_id], atol=1e-6)
    assert abs(obs["target_pad_pose"][0] - 1.4) <= 0.05 + 1e-6 and abs(obs["target_pad_pose"][1]) <= 0.2 + 1e-6
    env = _env(move_plates.MovePlate)
    poses = []
    for seed in (1, 2):
        obs, _ = env.reset(seed=seed)
        poses.append(obs["drainer_target_pose"].copy())
        assert obs["drainer_start_pose"][1] > 0.2 and obs["drainer_target_pose"][1] < -0.2
    assert not np.array_equal(*poses)


# --------------------------------------------------------------------------- StackBlocks
BLOCK = 0.05


def _stack(env, xy, levels=(0, 1, 2), dxy=((0, 0), (0, 0), (0, 0))) -> None:
    """Blocks 1..3 at ``xy`` (+ ``dxy``) on the table top, at the given stack levels,
    pressing 0.1 mm into what is below them."""
    for name, level, (dx, dy) in zip(("block_1", "block_2", "block_3"), levels, dxy, strict=True):
        z = 0.95 + 0.002 + BLOCK / 2 + level * BLOCK - (level + 1) * 1e-4
        env.props[name].set_pose(env.data, (xy[0] + dx, xy[1] + dy, z), (1.0, 0.0, 0.0, 0.0))
    _forward(env)


def _pad_xy(env) -> np.ndarray:
    return env.props["target_pad"].get_pose(env.data)[0][:2]


def test_stack_blocks_success_on_the_pad():
    env = _env(manipulation.StackBlocks)
    env.reset(seed=0)
    _stack(env, _pad_xy(env))
    assert env._success()
    _settle(env, 25)
    assert env._success()
    _, reward, terminated, _, info = env.step(_zero(env))
    assert reward == 1.0 and terminated and info["is_success"]


def test_stack_blocks_held_top_block_is_not_done():
    env = _env(manipulation.StackBlocks)
    env.reset(seed=1)
    _stack(env, _pad_xy(env))
    assert env._success()
    top = env.props["block_3"].get_pose(env.data)[0]
    _grip(env, top + (-BLOCK / 2, 0.0, 0.0))
    assert env.held("block_3")
    assert not env._success()


def test_stack_blocks_beside_the_pad_is_not_done():
    env = _env(manipulation.StackBlocks)
    env.reset(seed=2)
    _stack(env, _pad_xy(env) + (0.0, 0.15))
    assert env.touching(env.mask("block_2"), env.mask("block_1"))
    assert not env._success()


def test_stack_blocks_two_stacked_third_on_the_table_is_not_done():
    env = _env(manipulation.StackBlocks)
    env.reset(seed=3)
    pad = _pad_xy(env)
    _stack(env, pad, levels=(0, 1, 0), dxy=((0, 0), (0, 0), (0.0, 0.2)))
    env.props["block_3"].set_pose(env.data, (pad[0], pad[1] + 0.2, 0.95 + BLOCK / 2 - 1e-4))
    _forward(env)
    assert env.touching(env.mask("block_2"), env.mask("block_1"))
    assert not env._success()


@pytest.mark.parametrize("lifted", ["block_2", "block_3"])
def test_stack_blocks_gap_in_the_stack_is_not_done(lifted):
    """A block floating 1 cm above the one below it (and everything above it too)."""
    env = _env(manipulation.StackBlocks)
    env.reset(seed=6)
    _stack(env, _pad_xy(env))
    assert env._success()
    for name in ("block_2", "block_3")[("block_2", "block_3").index(lifted) :]:
        pos, quat = env.props[name].get_pose(env.data)
        env.props[name].set_pose(env.data, pos + (0.0, 0.0, 0.01), quat)
    _forward(env)
    assert not env._success()


def test_stack_blocks_two_side_by_side_under_one_is_not_a_stack():
    """Two blocks side by side on the pad with the third bridging them: every pair
    touches, but the blocks are not stacked three high."""
    env = _env(manipulation.StackBlocks)
    env.reset(seed=4)
    half = BLOCK / 2 - 5e-5
    _stack(env, _pad_xy(env), levels=(0, 0, 1), dxy=((0, -half), (0, half), (0, 0)))
    for a, b in (("block_1", "target_pad"), ("block_2", "target_pad"), ("block_1", "block_2"), ("block_3", "block_2")):
        assert env.touching(env.mask(a), env.mask(b)), (a, b)
    assert not env._success()


def test_stack_blocks_block_on_the_floor_fails():
    env = _env(manipulation.StackBlocks)
    env.reset(seed=5)
    assert not env._failure()
    env.props["block_2"].set_pose(env.data, (0.2, 0.8, BLOCK / 2 - 1e-4))
    _forward(env)
    assert env._failure()


# --------------------------------------------------------------------------- FlipCup
def _counter(env) -> np.ndarray:
    return env.props["cabinet"].part_geom_ids("counter")


def _mug_on_counter(env, tilt_deg: float = 0.0, xy=(0.8, 0.05), yaw: float = 2.5) -> None:
    quat = quat_mul(quat_axis_angle((0.0, 1.0, 0.0), np.deg2rad(tilt_deg)), quat_yaw(yaw))
    env.props["mug"].set_pose(env.data, (xy[0], xy[1], 0.9), quat)
    _drop_onto(env, "mug", _counter(env))


def test_flip_cup_upright_mug_succeeds():
    env = _env(manipulation.FlipCup)
    env.reset(seed=0)
    env.props["mug"].set_pose(env.data, (0.8, 0.05, 0.8605), quat_yaw(3.0))
    _forward(env)
    _settle(env, 25)
    _, reward, terminated, _, info = env.step(_zero(env))
    assert reward == 1.0 and terminated and info["is_success"]


@pytest.mark.parametrize(("tilt", "expected"), [(3.0, True), (8.0, False), (180.0, False)])
def test_flip_cup_upright_within_5_degrees(tilt, expected):
    env = _env(manipulation.FlipCup)
    env.reset(seed=1)
    _mug_on_counter(env, tilt)
    assert env.touching(env.mask("mug"), env.mask("cabinet", "counter"))
    assert env._success() == expected


def test_flip_cup_held_mug_is_not_done():
    env = _env(manipulation.FlipCup)
    env.reset(seed=2)
    _mug_on_counter(env)
    assert env._success()
    pos = env.props["mug"].get_pose(env.data)[0]
    _grip(env, pos + (-env.props["mug"].radius, 0.0, 0.06))
    assert env.held("mug")
    assert not env._success()


def test_flip_cup_mug_off_the_counter_is_not_done():
    env = _env(manipulation.FlipCup)
    env.reset(seed=3)
    _mug_on_counter(env)
    pos, quat = env.props["mug"].get_pose(env.data)
    env.props["mug"].set_pose(env.data, pos + (0.0, 0.0, 0.01), quat)
    _forward(env)
    assert not env._success()


def test_flip_cup_mug_on_the_floor_fails():
    env = _env(manipulation.FlipCup)
    env.reset(seed=4)
    env.props["mug"].set_pose(env.data, (0.3, 0.6, -1e-4))
    _forward(env)
    assert env._failure() and not env._success()


# --------------------------------------------------------------------------- FlipCutlery
def _spoon_axis(env) -> np.ndarray:
    return _rotation(_quat_of(env, "spoon"))[:, 1]


def _flip_spoon(env, seed: int) -> None:
    """Reset, then put the spoon bowl-down into the mug and let it settle."""
    env.reset(seed=seed)
    mug_pos = env.props["mug"].get_pose(env.data)[0]
    spoon = env.props["spoon"]
    down = quat_mul(quat_axis_angle((1.0, 0.0, 0.0), 0.1), quat_axis_angle((1.0, 0.0, 0.0), -np.pi / 2))
    spoon.set_pose(env.data, mug_pos + (0.0, 0.0, 0.015 + spoon.length / 2), down)
    _forward(env)
    _settle(env, 50)


def test_flip_cutlery_spoon_bowl_down_in_the_mug_succeeds():
    env = _env(manipulation.FlipCutlery)
    _flip_spoon(env, 0)
    assert _spoon_axis(env)[2] < -np.cos(np.deg2rad(50.0))
    assert env._success()
    _, reward, terminated, _, info = env.step(_zero(env))
    assert reward == 1.0 and terminated and info["is_success"]


def test_flip_cutlery_start_spoon_is_bowl_up():
    env = _env(manipulation.FlipCutlery)
    env.reset(seed=1)
    _settle(env, 5)
    assert env.touching(env.mask("spoon"), env.mask("mug"))
    assert _spoon_axis(env)[2] > np.cos(np.deg2rad(35.0))
    assert not env._success()


def test_flip_cutlery_held_spoon_is_not_done():
    env = _env(manipulation.FlipCutlery)
    _flip_spoon(env, 2)
    assert env._success()
    spoon = env.props["spoon"]
    pos, quat = spoon.get_pose(env.data)
    handle_end = pos + _rotation(quat) @ (0.0, -spoon.length / 2 + 0.01, 0.0)
    _grip(env, handle_end)
    assert env.held("spoon") and not env.held("mug")
    assert not env._success()


def test_flip_cutlery_held_mug_is_not_done():
    env = _env(manipulation.FlipCutlery)
    _flip_spoon(env, 3)
    assert env._success()
    mug = env.props["mug"]
    pos = mug.get_pose(env.data)[0]
    axis = _spoon_axis(env)
    # the mug's side away from where the spoon's handle leans out
    side = -np.array([axis[0], axis[1], 0.0]) / np.linalg.norm(axis[:2])
    _grip(env, pos + side * mug.radius + (0.0, 0.0, 0.03))
    assert env.held("mug") and not env.held("spoon")
    assert not env._success()


def test_flip_cutlery_spoon_above_the_mug_is_not_done():
    env = _env(manipulation.FlipCutlery)
    _flip_spoon(env, 4)
    assert env._success()
    pos, quat = env.props["spoon"].get_pose(env.data)
    env.props["spoon"].set_pose(env.data, pos + (0.0, 0.0, 0.2), quat)
    _forward(env)
    assert not env._success()


def test_flip_cutlery_spoon_lying_across_the_mug_is_not_done():
    env = _env(manipulation.FlipCutlery)
    env.reset(seed=5)
    mug = env.props["mug"]
    pos = mug.get_pose(env.data)[0]
    env.props["spoon"].set_pose(env.data, pos + (0.0, 0.0, mug.height + 0.05), quat_yaw(0.3))
    _drop_onto(env, "spoon", mug.collision_geom_ids)
    assert env.touching(env.mask("spoon"), env.mask("mug"))
    assert not env._success()


def test_flip_cutlery_spoon_on_the_floor_fails():
    env = _env(manipulation.FlipCutlery)
    env.reset(seed=6)
    env.props["spoon"].set_pose(env.data, (0.3, 0.6, 0.001), quat_yaw(0.0))
    _forward(env)
    assert env._failure()


# --------------------------------------------------------------------------- MovePlate(s)
def _plate_in_slot(env, plate: str, drainer: str, slot: int, flipped: bool = False) -> None:
    """Put ``plate`` in ``slot`` of ``drainer`` in the rest pose used at reset (turned
    180 deg about the slot's vertical when ``flipped``)."""
    rack = env.props[drainer]
    origin = env.data.xpos[rack.root_body_id]
    slot_pos = origin + env.model.site_pos[rack.site_id(rack.slot_keys[slot])]
    offset, quat = move_plates.PLATE_IN_SLOT_OFFSET, move_plates.PLATE_IN_SLOT_QUAT
    if flipped:
        turn = quat_yaw(np.pi)
        offset, quat = _rotation(turn) @ offset, quat_mul(turn, quat)
    env.props[plate].set_pose(env.data, slot_pos + offset, quat)
    _forward(env)


@pytest.mark.parametrize("flipped", [False, True], ids=["normal+y", "normal-y"])
def test_move_plate_in_the_target_drainer_succeeds(flipped):
    env = _env(move_plates.MovePlate)
    env.reset(seed=0)
    _plate_in_slot(env, "plate", "drainer_target", 4, flipped)
    _settle(env, 25)
    assert env._success()
    _, reward, terminated, _, info = env.step(_zero(env))
    assert reward == 1.0 and terminated and info["is_success"]


def test_move_plate_held_is_not_done():
    env = _env(move_plates.MovePlate)
    env.reset(seed=1)
    _plate_in_slot(env, "plate", "drainer_target", 2)
    assert env._success()
    pos, quat = env.props["plate"].get_pose(env.data)
    rotation = _rotation(quat)
    top = pos + rotation[:, 2] * 0.0095 + (0.0, 0.0, env.props["plate"].radius - 0.004)
    _grip(env, top)
    assert env.held("plate")
    assert not env._success()


def test_move_plate_hovering_in_a_slot_is_not_done():
    env = _env(move_plates.MovePlate)
    env.reset(seed=6)
    _plate_in_slot(env, "plate", "drainer_target", 0)
    assert env._success()
    pos, quat = env.props["plate"].get_pose(env.data)
    env.props["plate"].set_pose(env.data, pos + (0.0, 0.0, 0.01), quat)
    _forward(env)
    assert not env.touching(env.mask("plate"), env.mask("drainer_target"))
    assert not env._success()


def _slot_distance(env, plate: str) -> float:
    rack = env.props["drainer_target"]
    pos, quat = env.props[plate].get_pose(env.data)
    centre = pos + _rotation(quat)[:, 2] * env.props[plate].height / 2
    slots = np.array([env.data.site_xpos[rack.site_id(k)] for k in rack.slot_keys])
    return float(np.min(np.linalg.norm(slots - centre, axis=1)))


def test_move_plate_lying_flat_on_the_target_drainer_is_not_done():
    env = _env(move_plates.MovePlate)
    env.reset(seed=2)
    rack = env.props["drainer_target"]
    origin = env.data.xpos[rack.root_body_id]
    env.props["plate"].set_pose(env.data, origin + (0.0, 0.0, 0.2))
    _drop_onto(env, "plate", rack.collision_geom_ids)
    assert _slot_distance(env, "plate") < move_plates.SLOT_DISTANCE
    assert env.touching(env.mask("plate"), env.mask("drainer_target"))
    assert not env.touching(env.mask("plate"), env.mask("table"))
    assert not env._success()


def test_move_plate_upright_on_the_drainer_wall_is_not_in_a_slot():
    """Upright, touching the target drainer, off the table, released, but balanced on the
    end wall: more than 5 cm from every slot."""
    env = _env(move_plates.MovePlate)
    env.reset(seed=3)
    rack = env.props["drainer_target"]
    origin = env.data.xpos[rack.root_body_id]
    quat = quat_axis_angle((1.0, 0.0, 0.0), -np.pi / 2)
    env.props["plate"].set_pose(env.data, origin + (0.0, 0.1375 - 0.0095, 0.35), quat)
    _drop_onto(env, "plate", rack.collision_geom_ids)
    assert env.touching(env.mask("plate"), env.mask("drainer_target"))
    assert not env.touching(env.mask("plate"), env.mask("table"))
    assert _slot_distance(env, "plate") > move_plates.SLOT_DISTANCE
    assert not env._success()


def test_move_plate_touching_the_table_is_not_done():
    """A plate in a slot of a drainer sunk into the table also touches the table top."""
    env = _env(move_plates.MovePlate)
    env.reset(seed=4)
    rack = env.props["drainer_target"]
    origin = env.data.xpos[rack.root_body_id].copy()
    rack.set_pose(env.data, origin - (0.0, 0.0, 0.0375))
    _forward(env)
    _plate_in_slot(env, "plate", "drainer_target", 3)
    assert env.touching(env.mask("plate"), env.mask("drainer_target"))
    assert env.touching(env.mask("plate"), env.mask("table"))
    assert not env._success()
    rack.set_pose(env.data, origin)
    _forward(env)
    _plate_in_slot(env, "plate", "drainer_target", 3)
    assert env._success()


def test_move_plate_on_the_floor_fails():
    env = _env(move_plates.MovePlate)
    env.reset(seed=5)
    assert not env._failure()
    env.props["plate"].set_pose(env.data, (0.3, 0.8, -1e-4))
    _forward(env)
    assert env._failure()


def test_move_two_plates_needs_both():
    env = _env(move_plates.MoveTwoPlates)
    env.reset(seed=0)
    y1, y2 = (env.props[p].get_pose(env.data)[0][1] for p in ("plate_1", "plate_2"))
    assert abs(y1 - y2) > 0.04, "the plates start in distinct slots"
    _plate_in_slot(env, "plate_1", "drainer_target", 1)
    assert env.plate_in_target(0) and not env.plate_in_target(1)
    assert not env._success()
    _plate_in_slot(env, "plate_2", "drainer_target", 4, flipped=True)
    _settle(env, 10)
    assert env._success()

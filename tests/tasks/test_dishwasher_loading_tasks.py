"""Dishwasher loading and unloading tasks: seeded resets at rest, success states and the
near misses of every criterion (held, beside the target, lying down, one item missing,
dishwasher / cabinet / drawer still open), and failure on the floor."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from testkit import touch_with_gripper

from bigym.envs import dishwasher_cups as cups
from bigym.envs import dishwasher_cutlery as cutlery
from bigym.envs import dishwasher_plates as plates
from bigym.observations import ObservationConfig
from bigym.props.base import quat_axis_angle, quat_yaw

TASKS = [
    plates.DishwasherUnloadPlates,
    plates.DishwasherLoadPlates,
    plates.DishwasherUnloadPlatesLong,
    cups.DishwasherUnloadCups,
    cups.DishwasherLoadCups,
    cups.DishwasherUnloadCupsLong,
    cutlery.DishwasherUnloadCutlery,
    cutlery.DishwasherLoadCutlery,
    cutlery.DishwasherUnloadCutleryLong,
]
LONG = {
    "DishwasherUnloadPlatesLong": ("wall_cabinet", ("door_left", "door_right")),
    "DishwasherUnloadCupsLong": ("wall_cabinet", ("door_left", "door_right")),
    "DishwasherUnloadCutleryLong": ("cutlery_cabinet", ("drawer_small_1", "drawer_small_4")),
}
FLAT_ALONG_X = quat_yaw(np.pi / 2)  # cutlery lying flat, length along world x


@pytest.fixture(scope="module", params=TASKS, ids=lambda c: c.__name__)
def env(request):
    environment = request.param(observation_config=ObservationConfig(privileged_information=True))
    yield environment
    environment.close()


def _zero(env) -> np.ndarray:
    return np.zeros(env.action_space.shape, np.float32)


def _settle(env, steps: int = 200) -> None:
    """Let contacts form (0.4 s of physics, the robot holding its pose), then refresh."""
    for _ in range(steps):
        mujoco.mj_step(env.model, env.data)
    mujoco.mj_forward(env.model, env.data)


def _set(env, name: str, pos, quat=None) -> None:
    env.props[name].set_pose(env.data, pos, quat)


# ------------------------------------------------------------------ goal states
def _plate_in(env, plate: str, holder: str, slot: str) -> None:
    _set(env, plate, env.props[holder].site_pos(env.data, slot) + plates.PLATE_IN_SLOT, plates.PLATE_QUAT)


def _mug_upside_down_at(env, mug: str, point) -> None:
    env._place_upside_down(mug, np.asarray(point, float), np.pi)


def _lying_in_tray(env, item: str, slot: str) -> None:
    tray = env.props["cutlery_tray"]
    _set(env, item, tray.site_pos(env.data, slot) + (0.0, 0.0, 0.004), FLAT_ALONG_X)


def _carry(env, item: str) -> tuple[int, np.ndarray, np.ndarray]:
    """The pose of ``item`` in the frame of the dishwasher tray (or basket) it rests on."""
    trays = env.props["dishwasher"].part_geom_ids("tray_bottom", "basket", "tray_mid")
    n = env.data.ncon
    contact = env.data.contact
    mine = np.isin(contact.geom1[:n], env.props[item].collision_geom_ids) | np.isin(
        contact.geom2[:n], env.props[item].collision_geom_ids
    )
    other = np.where(np.isin(contact.geom1[:n], trays), contact.geom1[:n], contact.geom2[:n])
    hits = other[mine & (np.isin(contact.geom1[:n], trays) | np.isin(contact.geom2[:n], trays))]
    assert len(hits), f"test set-up: {item} is not on a tray"
    body = int(env.model.geom_bodyid[hits[0]])
    rot = env.data.xmat[body].reshape(3, 3)
    pos, quat = env.props[item].get_pose(env.data)
    local_quat = np.zeros(4)
    mujoco.mju_mulQuat(local_quat, _conj(env.data.xquat[body]), quat)
    return body, rot.T @ (pos - env.data.xpos[body]), local_quat


def _conj(q):
    return np.array([q[0], -q[1], -q[2], -q[3]])


def _goal(env, skip: str | None = None) -> None:
    """Put every item (but ``skip``, left where it started) where the task wants it; in
    the long tasks close the dishwasher (carrying ``skip`` in with its tray) and the
    wall cabinet or drawers."""
    name = type(env).__name__
    todo = [i for i in env.items if i != skip]
    mujoco.mj_forward(env.model, env.data)
    if env.close_at_end:
        carried = {i: _carry(env, i) for i in env.items if i not in todo}
        env.props["dishwasher"].set_state(env.data, 0.0)
        for prop in env.closed_props:
            env.props[prop].set_state(env.data, 0.0)
        mujoco.mj_kinematics(env.model, env.data)
        for i, (body, local_pos, local_quat) in carried.items():
            quat = np.zeros(4)
            mujoco.mju_mulQuat(quat, env.data.xquat[body], local_quat)
            pos = env.data.xpos[body] + env.data.xmat[body].reshape(3, 3) @ local_pos
            _set(env, i, pos, quat)
    if name in ("DishwasherUnloadPlates", "DishwasherUnloadPlatesLong"):
        for plate, slot in zip(todo, ("plate_slot_2", "plate_slot_5"), strict=False):
            _plate_in(env, plate, "drainer", slot)
    elif name == "DishwasherLoadPlates":
        for plate, slot in zip(todo, ("plate_slot_2_3", "plate_slot_1_8"), strict=False):
            _plate_in(env, plate, "dishwasher", slot)
    elif name == "DishwasherUnloadCups":
        # one on the cabinet's counter, one on the counter over the dishwasher
        for mug, point in zip(todo, ((0.6, -0.65, 0.86), (0.55, 0.1, 0.86)), strict=False):
            _mug_upside_down_at(env, mug, point)
    elif name == "DishwasherLoadCups":
        dishwasher = env.props["dishwasher"]
        for mug, slot in zip(todo, ("cup_slot_1_2", "cup_slot_2_7"), strict=False):
            _mug_upside_down_at(env, mug, dishwasher.site_pos(env.data, slot))
    elif name == "DishwasherUnloadCupsLong":
        for mug in todo:
            _set(env, mug, (0.83, -0.6, 1.4705))  # upright on the cabinet's bottom shelf
    elif name in ("DishwasherUnloadCutlery", "DishwasherUnloadCutleryLong"):
        for item, slot in zip(todo, ("slot_2", "slot_5"), strict=False):
            _lying_in_tray(env, item, slot)
    elif name == "DishwasherLoadCutlery":
        keep = {i: env.props[i].get_pose(env.data) for i in env.items if i not in todo}
        env._items_in_basket(np.random.default_rng(3))
        for i, (pos, quat) in keep.items():
            _set(env, i, pos, quat)
    else:  # pragma: no cover
        raise AssertionError(name)
    _settle(env)


def _goal_state(env, seed: int = 0, skip: str | None = None) -> None:
    env.reset(seed=seed)
    _goal(env, skip)


_grab = touch_with_gripper


# ------------------------------------------------------------------ reset
def test_reset_is_seeded_varied_and_not_done(env):
    state = mujoco.mjtState.mjSTATE_INTEGRATION
    snapshots = []
    for seed in (5, 5, 6):
        obs, info = env.reset(seed=seed)
        assert not info["is_success"] and not env._success() and not env._failure()
        assert env.observation_space.contains(obs)
        snapshot = np.zeros(mujoco.mj_stateSize(env.model, state))
        mujoco.mj_getState(env.model, env.data, snapshot, state)
        snapshots.append(snapshot)
    assert np.array_equal(snapshots[0], snapshots[1]), "same seed, different initial state"
    assert not np.array_equal(snapshots[0], snapshots[2]), "different seeds, same initial state"
    # the objects themselves are placed differently across seeds
    poses = []
    for seed in range(4):
        env.reset(seed=seed)
        poses.append(np.concatenate([env.props[i].get_pose(env.data)[0] for i in env.items]))
    assert min(np.linalg.norm(a - b) for k, a in enumerate(poses) for b in poses[k + 1 :]) > 1e-3


def test_objects_start_in_place_untouched(env):
    target = env.target_mask
    for seed in range(3):
        env.reset(seed=seed)
        for item in env.items:
            assert not env.held(item), f"{item} touches a gripper at reset"
            assert not env.touching(env.mask(item), target), f"{item} starts on its target"
            assert not env.touching(env.mask(item), env.floor_mask)
        state = env.props["dishwasher"].get_state(env.data)
        opened = [lo >= 0.5 for lo, _ in env.dishwasher_start]
        assert np.all((state > 0.9) == opened), state
        for name in env.closed_props:
            assert np.all(env.props[name].get_state(env.data) < 0.05)


def test_reset_is_at_rest(env):
    """2 s of zero actions: no object moves more than 1 cm, nothing ends the episode."""
    env.reset(seed=2)
    names = list(env._free_props)

    def points():
        out = []
        for n in names:
            body = env.props[n].root_body_id
            rot = env.data.xmat[body].reshape(3, 3)
            out.append(env.data.xpos[body] + 0.1 * rot.T)  # origin + 10 cm along each axis
        return np.array(out)

    start = points()
    for _ in range(int(2 * env.control_frequency)):
        _, reward, terminated, truncated, info = env.step(_zero(env))
        assert reward == 0.0 and not terminated and not truncated, info
    moved = np.linalg.norm(points() - start, axis=-1).max()
    assert moved < 0.01, f"moved {moved:.4f} m at rest"


def test_privileged_observation(env):
    obs, _ = env.reset(seed=1)
    for key, names in env.privileged_layout.items():
        assert obs[key].shape == (len(names),), key
    for name in env.observed_static:
        pose = obs[f"{name}_pose"]
        body = env.props[name].root_body_id
        np.testing.assert_allclose(pose[:3], env.data.xpos[body], atol=1e-6)
        env.reset(seed=2)
        assert not np.allclose(env.data.xpos[body], pose[:3]), f"{name} is not randomised"


def test_random_actions_run(env):
    env.reset(seed=3)
    rng = np.random.default_rng(3)
    low, high = env.action_space.low, env.action_space.high
    for _ in range(60):
        action = rng.uniform(low, high).astype(np.float32) * np.float32(0.3)
        _, reward, terminated, truncated, info = env.step(action)
        assert reward in (0.0, 1.0) and "unstable" not in info
        if terminated or truncated:
            env.reset(seed=4)


def test_time_limit(env):
    assert 15.0 <= env.time_limit <= 65.0
    assert env.max_episode_steps == int(np.ceil(env.time_limit * env.control_frequency))


# ------------------------------------------------------------------ success and near misses
def test_goal_state_succeeds_and_pays(env):
    _goal_state(env)
    assert env._success()
    _, reward, terminated, _, info = env.step(_zero(env))
    assert info["is_success"] and reward == 1.0 and terminated


def test_held_item_is_not_done(env):
    for item in env.items:
        _goal_state(env)
        target = env.target_mask
        _grab(env, item)
        assert env.held(item), "test set-up: the gripper should touch the item"
        assert env.touching(env.mask(item), target), "test set-up: the item should still be in place"
        assert not env._success(), f"{item} counted as placed while held"


def test_every_item_is_needed(env):
    """An item left where it started (in the dishwasher, the drainer, the mug...) fails."""
    for item in env.items:
        _goal_state(env, skip=item)
        assert not env._failure(), f"test set-up: {item} fell"
        assert not env._success(), f"success without moving {item}"


def _beside(env, item: str) -> None:
    """Put ``item`` next to the task's target: on a counter, on the open door, or (the
    cutlery to load) in the bottom tray but outside the basket."""
    name = type(env).__name__
    if name in ("DishwasherUnloadCups", "DishwasherLoadCups"):
        env.props["dishwasher"].set_joint_state(env.data, "door", 1.0)
        _mug_upside_down_at(env, item, (-0.1, -0.15, 0.2605))  # on the open door
    elif name == "DishwasherUnloadCupsLong":
        _mug_upside_down_at(env, item, (0.55, -0.7, 0.86))  # on the counter under the cabinet
    elif name == "DishwasherUnloadPlatesLong":
        _set(env, item, (0.55, -0.6, 0.862))  # flat on the counter under the cabinet
    elif name == "DishwasherLoadPlates":
        _set(env, item, (0.6, -0.2, 0.862))  # flat on the counter
    elif name == "DishwasherLoadCutlery":
        # flat on the bottom tray's floor between its front rail and the first plate rack
        slot = env.props["dishwasher"].site_pos(env.data, "plate_slot_1_4")
        _set(env, item, slot + (-0.085, 0.0, -0.116 + 0.006))
    else:  # the other unloading tasks: flat on the counter over the dishwasher
        _set(env, item, (0.55, 0.15, 0.8645), FLAT_ALONG_X)


def test_item_beside_the_target_is_not_done(env):
    item = env.items[0]
    _goal_state(env)
    assert env._success()
    _beside(env, item)
    _settle(env, 100)
    assert not env.touching(env.mask(item), env.target_mask)
    assert not env._failure() and not env.held(item)
    assert not env._success()
    if type(env).__name__ == "DishwasherLoadCutlery":
        assert env.touching(env.mask(item), env.mask("dishwasher", "tray_bottom"))


def test_load_plates_needs_upright_plates():
    """A plate lying flat on the bottom tray's racks touches the tray but is not loaded."""
    env = plates.DishwasherLoadPlates()
    try:
        _goal_state(env)
        assert env._success()
        site = env.props["dishwasher"].site_pos(env.data, "plate_slot_2_4")
        rack_top = site[2] - 0.116 + 0.07  # the slot's dividers are 7 cm high
        _set(env, "plate_1", (site[0], site[1], rack_top - 0.0005))
        mujoco.mj_forward(env.model, env.data)
        assert env.touching(env.mask("plate_1"), env.target_mask)
        assert not env._success()
        # tilted 30 deg off the slot orientation it is not upright either
        _goal_state(env)
        pos, _ = env.props["plate_1"].get_pose(env.data)
        tilted = quat_axis_angle((0.0, 0.0, 1.0), np.deg2rad(30.0))
        env.props["plate_1"].set_pose(env.data, pos, _mul(tilted, plates.PLATE_QUAT))
        mujoco.mj_forward(env.model, env.data)
        assert not env.upright("plate_1", plates.UPRIGHT_DEG, world_axis=(0, 1, 0), either_sign=True)
        assert not env._success()
    finally:
        env.close()


def _mul(a, b):
    out = np.zeros(4)
    mujoco.mju_mulQuat(out, np.asarray(a, float), np.asarray(b, float))
    return out


@pytest.mark.parametrize("name", sorted(LONG))
def test_long_tasks_need_everything_closed(name):
    cls = {c.__name__: c for c in TASKS}[name]
    env = cls()
    try:
        prop, keys = LONG[name]
        for owner, key in [("dishwasher", k) for k in ("door", "tray_bottom", "tray_mid")] + [(prop, k) for k in keys]:
            _goal_state(env)
            assert env._success()
            env.props[owner].set_joint_state(env.data, key, 0.15)
            mujoco.mj_forward(env.model, env.data)
            assert not env._success(), f"{owner}/{key} at 0.15 counted as closed"
            env.props[owner].set_joint_state(env.data, key, 0.08)
            mujoco.mj_forward(env.model, env.data)
            assert env._success(), f"{owner}/{key} at 0.08 should count as closed"
    finally:
        env.close()


# ------------------------------------------------------------------ failure
def test_item_on_the_floor_fails(env):
    for item in env.items:
        env.reset(seed=0)
        _set(env, item, (-0.6, 0.8, -0.001))
        mujoco.mj_forward(env.model, env.data)
        assert env._failure(), f"{item} on the floor is not a failure"
        _, reward, terminated, _, _ = env.step(_zero(env))
        assert terminated and reward == 0.0

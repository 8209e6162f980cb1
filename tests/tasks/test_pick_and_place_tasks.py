"""Resets, success and near-miss states of the pick-and-place tasks (cups, box, cookware)."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from testkit import touch_with_gripper

from bigym.envs import pick_and_place as pp
from bigym.props.base import quat_axis_angle, quat_yaw

TASKS = [pp.PutCups, pp.TakeCups, pp.PickBox, pp.StoreBox, pp.SaucepanToHob, pp.StoreKitchenware]
UP = quat_yaw(np.pi)  # upright, handle towards the robot
FLAT = quat_yaw(0.0)
BOX_HALF_HEIGHT = pp.LargeBox.SIZE[2] / 2.0

# Object poses (pos, quat) of each task's success state: the object resting on the target.
GOALS = {
    pp.PutCups: {"mug_1": ((1.03, 0.12, pp.WALL_SHELF_BOTTOM_TOP), UP), "mug_2": ((1.03, -0.12, 1.822), UP)},
    pp.TakeCups: {"mug_1": ((0.8, 0.12, pp.COUNTER_TOP), UP), "mug_2": ((0.85, -0.1, pp.COUNTER_TOP), UP)},
    pp.PickBox: {"box": ((0.85, 0.0, pp.COUNTER_TOP + BOX_HALF_HEIGHT), quat_yaw(0.3))},
    pp.StoreBox: {"box": ((0.9, 0.0, pp.BASE_SHELF_TOP + BOX_HALF_HEIGHT), quat_yaw(1.2))},
    pp.SaucepanToHob: {"saucepan": ((0.8, -0.12, pp.HOB_TOP), quat_yaw(-2.5))},
    pp.StoreKitchenware: {
        "pan": ((0.98, 0.14, pp.BASE_SHELF_TOP), quat_yaw(np.pi)),
        "saucepan": ((0.9, -0.15, pp.BASE_SHELF_TOP), quat_yaw(np.pi)),
    },
}

# Near misses: the object resting on a surface that is not the target.
ELSEWHERE = {
    pp.PutCups: {"mug_1": ((0.8, 0.0, pp.COUNTER_TOP), UP)},  # still on the counter
    pp.TakeCups: {"mug_1": ((0.9, 0.0, pp.BASE_SHELF_TOP), UP)},  # in the base cabinet
    pp.PickBox: {"box": ((0.9, 0.0, pp.BASE_SHELF_TOP + BOX_HALF_HEIGHT), FLAT)},  # on the shelf inside
    pp.StoreBox: {"box": ((0.9, 0.0, 0.13 + BOX_HALF_HEIGHT), FLAT)},  # on the cabinet's bottom
    pp.SaucepanToHob: {"saucepan": ((0.85, 0.0, pp.BASE_SHELF_TOP), UP)},  # still on the shelf
    pp.StoreKitchenware: {"pan": ((0.98, 0.14, 0.13), UP)},  # on the cabinet's bottom, not the shelf
}


@pytest.fixture(scope="module", params=TASKS, ids=lambda c: c.__name__)
def env(request):
    environment = request.param()
    yield environment
    environment.close()


def _zero(env) -> np.ndarray:
    return np.zeros(env.action_space.shape, np.float32)


def _place(env, poses, dz: float = pp.CLEARANCE) -> None:
    for name, (pos, quat) in poses.items():
        env.props[name].set_pose(env.data, np.add(pos, (0.0, 0.0, dz)), quat)


def _settle(env, steps: int = 100) -> None:
    """Let contacts form (0.2 s of physics, robot holding its pose), then refresh them."""
    for _ in range(steps):
        mujoco.mj_step(env.model, env.data)
    mujoco.mj_forward(env.model, env.data)


def _goal_state(env, seed: int = 0) -> None:
    env.reset(seed=seed)
    _place(env, GOALS[type(env)])
    _settle(env)


_grab = touch_with_gripper


# ------------------------------------------------------------------ reset
def test_reset_is_seeded_at_rest_and_not_done(env):
    state = mujoco.mjtState.mjSTATE_INTEGRATION
    size = mujoco.mj_stateSize(env.model, state)
    states = []
    for seed in (5, 5, 6):
        _, info = env.reset(seed=seed)
        assert not info["is_success"] and not env._success() and not env._failure()
        snapshot = np.zeros(size)
        mujoco.mj_getState(env.model, env.data, snapshot, state)
        states.append(snapshot)
    assert np.array_equal(states[0], states[1]) and not np.array_equal(states[0], states[2])

    # 2 s of zero actions: nothing moves more than 1 cm, nothing ends the episode.
    for seed in (0, 1):
        env.reset(seed=seed)
        start = {name: env.props[name].get_pose(env.data)[0] for name in env.objects}
        for _ in range(int(2 * env.control_frequency)):
            _, reward, terminated, truncated, info = env.step(_zero(env))
            assert reward == 0.0 and not terminated and not truncated, info
        for name, pos in start.items():
            moved = np.linalg.norm(env.props[name].get_pose(env.data)[0] - pos)
            assert moved < 0.01, f"{name} moved {moved:.4f} m at rest"


def test_reset_touches_only_the_start_support(env):
    """Objects start on their support, touching no target part, gripper or other object."""
    start_support = {
        pp.PutCups: ("cabinet", "counter"),
        pp.TakeCups: ("wall_cabinet", "shelf_bottom"),
        pp.PickBox: None,  # the floor
        pp.StoreBox: ("cabinet", "counter"),
        pp.SaucepanToHob: ("cabinet", "shelf"),
        pp.StoreKitchenware: ("cabinet", "hob"),
    }[type(env)]
    for seed in range(6):
        env.reset(seed=seed)
        _settle(env, 20)
        for name in env.objects:
            obj = env.mask(name)
            support = env.floor_mask if start_support is None else env.mask(*start_support)
            assert env.touching(obj, support), (seed, name)
            assert not env.touching(obj, env.target_mask) and not env.held(name)
            others = ~(obj.mask | support.mask)  # every geom but these (a one-off boolean mask)
            assert not env.touching(obj, others), f"seed {seed}: {name} touches something besides its support"


# ------------------------------------------------------------------ success
def test_goal_state_succeeds_and_pays(env):
    _goal_state(env)
    assert env._success()
    assert not env._failure()
    _, reward, terminated, _, info = env.step(_zero(env))
    assert info["is_success"] and reward == 1.0 and terminated


def test_held_object_is_not_done(env):
    for name in env.objects:
        _goal_state(env)
        _grab(env, name)
        assert env.held(name), "test set-up: the gripper should touch the object"
        assert env.touching(env.mask(name), env.target_mask), "test set-up: the object left its target"
        assert not env._success(), f"{name} counted as placed while held"


def test_hovering_object_is_not_done(env):
    """Right above the target but 1 cm clear of it: no contact, no success."""
    for name in env.objects:
        env.reset(seed=1)
        goal = GOALS[type(env)]
        _place(env, goal)
        _place(env, {name: goal[name]}, dz=0.01)
        mujoco.mj_forward(env.model, env.data)
        others = [n for n in env.objects if n != name]
        for other in others:
            env.props[other].set_pose(env.data, np.add(goal[other][0], (0, 0, -0.0002)), goal[other][1])
        mujoco.mj_forward(env.model, env.data)
        assert all(env.object_placed(n) for n in others)
        assert not env._success()


def test_object_on_another_surface_is_not_done(env):
    for seed in (2, 3):
        env.reset(seed=seed)
        goal = dict(GOALS[type(env)])
        goal.update(ELSEWHERE[type(env)])
        _place(env, goal)
        _settle(env)
        (name,) = ELSEWHERE[type(env)]
        assert not env.object_placed(name)
        assert not env._success()


@pytest.mark.parametrize("task", [pp.PutCups, pp.TakeCups, pp.StoreKitchenware], ids=lambda c: c.__name__)
def test_each_object_is_needed(task):
    """With two objects, one on the target and one still at its start is not enough."""
    env = task()
    try:
        _check_each_object_is_needed(env)
    finally:
        env.close()


def _check_each_object_is_needed(env):
    goal = GOALS[type(env)]
    for missing in env.objects:
        env.reset(seed=4)
        _place(env, {n: p for n, p in goal.items() if n != missing})
        _settle(env)
        assert not env._success(), f"success with {missing} not moved"
        assert env.object_placed(next(n for n in env.objects if n != missing))


def test_object_on_the_floor_fails(env):
    env.reset(seed=0)
    name = env.objects[-1]
    prop = env.props[name]
    _, quat = prop.get_pose(env.data)
    if isinstance(env, pp.PickBox):
        # The box starts on the floor: that is the task, not a failure.
        _settle(env, 20)
        assert env.touching(env.mask("box"), env.floor_mask)
        assert not env._failure()
        return
    height = BOX_HALF_HEIGHT if isinstance(env, pp.StoreBox) else 0.0
    prop.set_pose(env.data, (0.5, -0.8, height - 0.0002), quat)
    mujoco.mj_forward(env.model, env.data)
    assert env._failure()
    _, reward, terminated, _, info = env.step(_zero(env))
    assert terminated and reward == 0.0 and not info["is_success"]


# ------------------------------------------------------------------ task specifics
def test_put_cups_accepts_either_wall_shelf():
    env = pp.PutCups()
    try:
        for z in (pp.WALL_SHELF_BOTTOM_TOP, 1.822):
            env.reset(seed=0)
            _place(env, {"mug_1": ((1.03, 0.12, z), UP), "mug_2": ((1.03, -0.12, z), UP)})
            _settle(env)
            assert env._success(), z
        # A mug on the base cabinet's counter does not count for the wall cabinet.
        env.reset(seed=0)
        _place(env, {"mug_1": ((1.03, 0.12, pp.WALL_SHELF_BOTTOM_TOP), UP)})
        _settle(env)
        assert env.object_placed("mug_1") and not env.object_placed("mug_2") and not env._success()
    finally:
        env.close()


def test_spawn_ranges():
    """Cups on distinct grid cells, the box upright on its end, pans on both burners."""
    cups, box, ware = pp.TakeCups(), pp.PickBox(), pp.StoreKitchenware()
    try:
        orders = set()
        for seed in range(8):
            cups.reset(seed=seed)
            a, b = (cups.props[n].get_pose(cups.data)[0] for n in cups.objects)
            assert np.linalg.norm(a[:2] - b[:2]) > 0.09
            for p in (a, b):
                assert abs(p[0] - 1.05) <= 0.03 + 1e-9 and abs(p[1]) <= 0.18 + 1e-9
            box.reset(seed=seed)
            pos, quat = box.props["box"].get_pose(box.data)
            rot = np.zeros(9)
            mujoco.mju_quat2Mat(rot, quat)
            assert abs(rot.reshape(3, 3)[2, 0]) > 0.999  # long axis vertical
            assert np.linalg.norm(pos[:2] - (0.8, -1.0)) < 0.05
            ware.reset(seed=seed)
            x_pan = ware.props["pan"].get_pose(ware.data)[0][0]
            orders.add(bool(x_pan < 0.9))
        assert orders == {True, False}, "the pans should swap burners across seeds"
    finally:
        for e in (cups, box, ware):
            e.close()


def test_quat_euler_matches_rotation_matrices():
    """quat_euler(roll, pitch, yaw) is Rz(yaw) @ Ry(pitch) @ Rx(roll), checked against matrices
    written out from cos and sin (not against the quaternion helpers it is built from)."""
    import mujoco

    from bigym.props.base import quat_euler

    def rx(a):
        c, s = np.cos(a), np.sin(a)
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])

    def ry(a):
        c, s = np.cos(a), np.sin(a)
        return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])

    def rz(a):
        c, s = np.cos(a), np.sin(a)
        return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])

    rng = np.random.default_rng(0)
    cases = [(a, np.pi / 2, 0.0) for a in (-2.0, 0.4, 3.0)] + [tuple(rng.uniform(-np.pi, np.pi, 3)) for _ in range(20)]
    for roll, pitch, yaw in cases:
        quat = quat_euler(roll=roll, pitch=pitch, yaw=yaw)
        assert np.linalg.norm(quat) == pytest.approx(1.0)
        matrix = np.zeros(9)
        mujoco.mju_quat2Mat(matrix, quat)
        np.testing.assert_allclose(matrix.reshape(3, 3), rz(yaw) @ ry(pitch) @ rx(roll), atol=1e-12)
    # The order matters: roll then pitch is not pitch then roll.
    matrix = np.zeros(9)
    mujoco.mju_quat2Mat(matrix, quat_euler(roll=0.5, pitch=0.7))
    assert not np.allclose(matrix.reshape(3, 3), rx(0.5) @ ry(0.7))

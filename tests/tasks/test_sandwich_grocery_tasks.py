"""Sandwich and grocery tasks: seeded resets at rest, success states and near misses.

Constructed states put objects 1 mm into their supports and run ``mj_forward``, so the
contacts the detectors look for exist without any physics step.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from bigym.demonstrations import model_fingerprint
from bigym.envs import groceries, sandwich
from bigym.envs.groceries import POOL, StoreGroceriesLower, StoreGroceriesUpper
from bigym.envs.sandwich import PAN_FLOOR, SandwichFlip, SandwichRemove, SandwichToast
from bigym.observations import ObservationConfig
from bigym.props import Sandwich
from bigym.props.base import quat_axis_angle, quat_mul, quat_yaw

ALL = [SandwichToast, SandwichFlip, SandwichRemove, StoreGroceriesLower, StoreGroceriesUpper]
SINK = 0.001  # how far constructed objects sit in their support
HALF = Sandwich.SIZE[2] / 2
STATE = mujoco.mjtState.mjSTATE_INTEGRATION


@pytest.fixture(scope="module")
def envs():
    made = {cls: cls(observation_config=ObservationConfig(privileged_information=True)) for cls in ALL}
    yield made
    for env in made.values():
        env.close()


def _env(envs, cls, seed=0):
    env = envs[cls]
    env.reset(seed=seed)
    return env


def _part_top(env, prop, part):
    ids = env.props[prop].part_geom_ids(part)
    return float(np.max(env.data.geom_xpos[ids, 2] + env.model.geom_size[ids, 2]))


def _tilt(angle_deg, base=(1.0, 0.0, 0.0, 0.0)):
    return quat_mul(quat_axis_angle((1.0, 0.0, 0.0), np.deg2rad(angle_deg)), base)


UPSIDE_DOWN = quat_axis_angle((1.0, 0.0, 0.0), np.pi)


def _grip(env, point):
    """Shift the robot's floating base so that the left gripper's pad sits on ``point``."""
    model, data, robot = env.model, env.data, env.robot
    pad = next(g for g in robot.gripper_geom_ids_by_side[0] if model.geom(g).name.endswith("pad1"))
    mujoco.mj_forward(model, data)
    delta = np.asarray(point) - data.geom_xpos[pad]
    for axis, dof in enumerate("xyz"):
        data.qpos[robot.base_qpos[dof]] += delta[axis]
    mujoco.mj_forward(model, data)


# ---------------------------------------------------------------------------- generic
@pytest.mark.parametrize("cls", ALL, ids=lambda c: c.__name__)
def test_reset_is_seeded_and_at_rest(envs, cls):
    """Same seed, same state; other seed, other state; then 2 s of zero actions move no
    object more than 1 cm and trigger neither success nor failure."""
    env = envs[cls]
    states = []
    for seed in (5, 5, 6):
        env.reset(seed=seed)
        state = np.zeros(mujoco.mj_stateSize(env.model, STATE))
        mujoco.mj_getState(env.model, env.data, state, STATE)
        states.append(state)
    assert np.array_equal(states[0], states[1])
    assert not np.array_equal(states[0], states[2])
    for seed in (0, 1):
        obs, info = env.reset(seed=seed)
        assert not info["is_success"] and not env._success() and not env._failure()
        assert env.observation_space.contains(obs)
        start = {n: p.get_pose(env.data)[0] for n, p in env._free_props.items()}
        action = np.zeros(env.action_space.shape, np.float32)
        for _ in range(int(2.0 * env.control_frequency)):
            _, reward, terminated, truncated, info = env.step(action)
            assert reward == 0.0 and not terminated and not truncated and "unstable" not in info
        moved = {n: np.linalg.norm(p.get_pose(env.data)[0] - start[n]) for n, p in env._free_props.items()}
        assert max(moved.values()) < 0.01, moved


@pytest.mark.parametrize("cls", ALL, ids=lambda c: c.__name__)
def test_detector_false_at_reset(envs, cls):
    for seed in range(2, 8):
        env = _env(envs, cls, seed)
        assert not env._success() and not env._failure()


# ---------------------------------------------------------------------------- sandwich
def _pan(env):
    return env.props["pan"].get_pose(env.data)


def _settle_pan_on_hob(env):
    """Sink the pan 1 mm into the hob (contact without stepping)."""
    pos, quat = _pan(env)
    pos[2] = _part_top(env, "cabinet_1", "hob") - SINK
    env.props["pan"].set_pose(env.data, pos, quat)
    return pos


def _sandwich_in_pan(env, quat=(1.0, 0.0, 0.0, 0.0), lift=0.0):
    pan = _settle_pan_on_hob(env)
    if isinstance(env, SandwichToast):  # the spatula lies in the empty pan: move it to a far burner
        hob4 = env.props["cabinet_1"].site_pos(env.data, "hob_site_4")
        env.props["spatula"].set_pose(env.data, hob4 + (0, 0, 0.0), quat_yaw(np.pi / 2))
    env.props["sandwich"].set_pose(env.data, pan + (0.0, 0.0, PAN_FLOOR + HALF - SINK + lift), quat)
    mujoco.mj_forward(env.model, env.data)


def _sandwich_on_board(env, quat=(1.0, 0.0, 0.0, 0.0), offset=(0.0, 0.0)):
    board = env.props["board"].get_pose(env.data)[0].copy()
    board[2] = _part_top(env, "cabinet_2", "counter") - SINK
    env.props["board"].set_pose(env.data, board, env.props["board"].get_pose(env.data)[1])
    env.props["sandwich"].set_pose(env.data, board + (*offset, sandwich.BOARD_TOP + HALF - SINK), quat)
    mujoco.mj_forward(env.model, env.data)


@pytest.mark.parametrize("quat", [(1.0, 0.0, 0.0, 0.0), UPSIDE_DOWN, _tilt(8.0)], ids=["up", "down", "tilt8"])
def test_toast_success_either_face_down(envs, quat):
    env = _env(envs, SandwichToast, 1)
    _sandwich_in_pan(env, quat)
    assert env._success() and not env._failure()


def test_toast_near_misses(envs):
    env = _env(envs, SandwichToast, 2)
    _sandwich_in_pan(env, _tilt(15.0))
    assert not env._success(), "tilted 15 deg counts as flat"
    _sandwich_in_pan(env, _tilt(90.0))
    assert not env._success(), "on its side counts as flat"
    _sandwich_in_pan(env, lift=0.03)
    assert not env._success(), "hovering over the pan counts as in it"
    _sandwich_in_pan(env)
    pos, quat = _pan(env)
    env.props["pan"].set_pose(env.data, pos + (0, 0, 0.05), quat)  # pan lifted off the hob
    sw = env.props["sandwich"].get_pose(env.data)
    env.props["sandwich"].set_pose(env.data, sw[0] + (0, 0, 0.05), sw[1])
    mujoco.mj_forward(env.model, env.data)
    assert env.touching(env.sandwich_mask, env.pan_mask)
    assert not env._success(), "pan off the hob"
    # beside the pan, flat on the hob
    env.reset(seed=2)
    _settle_pan_on_hob(env)
    hob2 = env.props["cabinet_1"].site_pos(env.data, "hob_site_2")
    env.props["sandwich"].set_pose(env.data, hob2 + (0, 0, HALF - SINK))
    mujoco.mj_forward(env.model, env.data)
    assert env.touching(env.sandwich_mask, env.hob_mask)
    assert not env._success(), "on the hob beside the pan"


@pytest.mark.parametrize("cls", [SandwichToast, SandwichFlip, SandwichRemove], ids=lambda c: c.__name__)
def test_gripper_on_sandwich_fails_and_blocks_success(envs, cls):
    env = _env(envs, cls, 3)
    if cls is SandwichRemove:
        _sandwich_on_board(env)
    else:
        _sandwich_in_pan(env, UPSIDE_DOWN)
    assert env._success() and not env._failure()
    top = env.props["sandwich"].get_pose(env.data)[0] + (0, 0, HALF)
    _grip(env, top)
    assert env.held("sandwich")
    assert not env._success()
    assert env._failure()


@pytest.mark.parametrize("cls", [SandwichToast, SandwichFlip, SandwichRemove], ids=lambda c: c.__name__)
@pytest.mark.parametrize("prop", ["sandwich", "pan"])
def test_sandwich_or_pan_on_floor_fails(envs, cls, prop):
    env = _env(envs, cls, 4)
    env.props[prop].set_pose(env.data, (0.3, -1.2, HALF - SINK if prop == "sandwich" else -SINK))
    mujoco.mj_forward(env.model, env.data)
    assert env._failure()


def test_flip_success_only_upside_down(envs):
    env = _env(envs, SandwichFlip, 1)
    _sandwich_in_pan(env, UPSIDE_DOWN)
    assert env._success()
    _sandwich_in_pan(env, _tilt(172.0))
    assert env._success(), "8 deg from upside down is within tolerance"
    _sandwich_in_pan(env, _tilt(165.0))
    assert not env._success(), "15 deg from upside down"
    _sandwich_in_pan(env)
    assert env.touching(env.sandwich_mask, env.pan_mask)
    assert not env._success(), "right side up is not flipped"
    _sandwich_in_pan(env, UPSIDE_DOWN)
    pos, quat = _pan(env)
    env.props["pan"].set_pose(env.data, pos + (0.0, 0.0, 0.02), quat)
    mujoco.mj_forward(env.model, env.data)
    assert not env._success(), "pan off the hob"
    env.reset(seed=1)
    _settle_pan_on_hob(env)
    _sandwich_on_board(env, UPSIDE_DOWN)
    assert not env._success(), "flipped onto the board"


def test_remove_success_and_near_misses(envs):
    env = _env(envs, SandwichRemove, 2)
    for quat in ((1.0, 0.0, 0.0, 0.0), UPSIDE_DOWN, _tilt(8.0)):
        _sandwich_on_board(env, quat)
        assert env._success()
    _sandwich_on_board(env, _tilt(15.0))
    assert not env._success(), "tilted 15 deg on the board"
    _sandwich_on_board(env, _tilt(90.0))
    assert not env._success(), "on its side on the board"
    # flat on the counter beside the board
    env.reset(seed=2)
    board = env.props["board"].get_pose(env.data)[0]
    counter = _part_top(env, "cabinet_2", "counter")
    env.props["sandwich"].set_pose(env.data, (board[0], board[1] + 0.3, counter + HALF - SINK))
    mujoco.mj_forward(env.model, env.data)
    assert not env._success(), "beside the board"
    # still in the pan (the start)
    env.reset(seed=2)
    _sandwich_in_pan(env)
    assert not env._success(), "still in the pan"


def test_spatula_starts_in_the_pan_and_sandwich_where_it_should(envs):
    for cls in (SandwichToast, SandwichFlip, SandwichRemove):
        env = _env(envs, cls, 0)
        for _ in range(10):
            env.step(np.zeros(env.action_space.shape, np.float32))
        assert env.touching(env.mask("spatula"), env.pan_mask | env.sandwich_mask)
        assert env.touching(env.pan_mask, env.hob_mask)
        on = env.pan_mask if env.start_in_pan else env.board_mask
        assert env.touching(env.sandwich_mask, on)
    assert envs[SandwichRemove].props["sandwich"].toasted and not envs[SandwichFlip].props["sandwich"].toasted
    assert envs[SandwichFlip].props["sandwich"].rounded and not envs[SandwichToast].props["sandwich"].rounded


# ---------------------------------------------------------------------------- groceries
def _store(env, spots, names=None):
    """Stand the chosen items (or ``names``) on ``spots`` = [(prop, part, x, y)], 1 mm sunk."""
    names = env.chosen if names is None else names
    for name, (prop, part, x, y) in zip(names, spots, strict=True):
        yaw = np.pi / 2 if name == "cereals" else 0.0  # long side along x (the depth)
        env.props[name].set_pose(env.data, (x, y, _part_top(env, prop, part) - SINK), quat_yaw(yaw))
    mujoco.mj_forward(env.model, env.data)


LOWER_SHELF = [("cabinet_1", "shelf", x, y) for x in (0.68, 0.93) for y in (-0.14, 0.14)]
LOWER_MIXED = LOWER_SHELF[:2] + [("cabinet_2", "shelf_bottom", 0.8, -0.75), ("cabinet_1", "shelf_bottom", 0.8, 0.1)]
UPPER = [
    ("wall_cabinet", "shelf_bottom", 0.93, -0.15),
    ("wall_cabinet", "shelf_bottom", 0.93, 0.15),
    ("wall_cabinet", "shelf", 0.93, 0.0),
    ("open_shelf", "shelf", 0.93, -0.6),
]


def test_groceries_draw_four_of_the_pool_per_seed(envs):
    """Four distinct kinds per episode, the same for the same seed; the others are parked
    far out of sight, welded, touching nothing; the compiled model never changes."""
    env = envs[StoreGroceriesLower]
    assert len(POOL) >= 7
    fingerprint = model_fingerprint(env.model)
    far = env.model.vis.map.zfar * env.model.stat.extent
    draws = set()
    for seed in range(8):
        env.reset(seed=seed)
        chosen = env.chosen
        assert len(set(chosen)) == groceries.CHOSEN == 4
        env.reset(seed=seed)
        assert env.chosen == chosen
        draws.add(chosen)
        for _ in range(5):
            env.step(np.zeros(env.action_space.shape, np.float32))
        for name in env.pool:
            prop = env.props[name]
            pos = prop.get_pose(env.data)[0]
            if name in chosen:
                assert not env.data.eq_active[env.weld_ids[name]]
                assert 0.8 < pos[2] < 0.9  # on the counter
            else:
                assert env.data.eq_active[env.weld_ids[name]]
                assert np.linalg.norm(pos - env.park[name]) < 1e-3
                assert np.linalg.norm(pos) > far  # beyond every camera's far plane
                assert not env.touching(env.item_masks[name], np.ones(env.model.ngeom, bool))
        assert model_fingerprint(env.model) == fingerprint
    assert len(draws) > 3


@pytest.mark.parametrize("spots", [LOWER_SHELF, LOWER_MIXED], ids=["shelf", "mixed"])
def test_lower_success(envs, spots):
    env = _env(envs, StoreGroceriesLower, 1)
    _store(env, spots)
    assert env._success() and not env._failure()


def test_upper_success(envs):
    env = _env(envs, StoreGroceriesUpper, 1)
    _store(env, UPPER)
    assert env._success() and not env._failure()


@pytest.mark.parametrize("cls", [StoreGroceriesLower, StoreGroceriesUpper], ids=lambda c: c.__name__)
def test_groceries_near_misses(envs, cls):
    spots = LOWER_SHELF if cls is StoreGroceriesLower else UPPER
    for seed in (2, 3):
        env = _env(envs, cls, seed)
        start = {n: env.props[n].get_pose(env.data)[0] for n in env.chosen}
        # three stored, the fourth still on the counter
        _store(env, spots[:3], env.chosen[:3])
        last = env.chosen[3]
        env.props[last].set_pose(env.data, start[last] - (0, 0, SINK + 0.0005))
        mujoco.mj_forward(env.model, env.data)
        assert not env._success(), "one item left on the counter"
        # all stored, one held
        _store(env, spots)
        assert env._success()
        held = env.chosen[2]
        _grip(env, env.props[held].site_pos(env.data, "grasp"))
        assert env.held(held) and not env._success(), "a held item counts as stored"
        env.reset(seed=seed)
        # on the cupboard's roof / on the counter top instead of a shelf
        if cls is StoreGroceriesLower:
            roof, xs = ("cabinet_1", "counter"), (0.72, 0.93)
        else:
            roof, xs = ("wall_cabinet", "walls"), (0.88, 1.0)
        wrong = [(*roof, xs[k % 2], -0.15 + 0.3 * (k // 2)) for k in range(4)]
        _store(env, wrong)
        assert all(env.touching(env.item_masks[n], env.mask(*roof)) for n in env.chosen)
        assert not env._success(), "items on top instead of inside"


@pytest.mark.parametrize("cls", [StoreGroceriesLower, StoreGroceriesUpper], ids=lambda c: c.__name__)
def test_grocery_on_floor_fails(envs, cls):
    env = _env(envs, cls, 5)
    assert not env._failure()
    item = env.chosen[0]
    env.props[item].set_pose(env.data, (0.3, -1.0, -SINK))
    mujoco.mj_forward(env.model, env.data)
    assert env._failure()


def test_success_follows_the_chosen_items(envs):
    """Success looks at the items drawn this episode, whatever the parked ones do: storing
    them succeeds (the parked ones stay under the floor); sending one of them back to its
    parking spot undoes it."""
    env = _env(envs, StoreGroceriesLower, 6)
    _store(env, LOWER_SHELF)
    assert env._success()
    env.props[env.chosen[0]].set_pose(env.data, env.park[env.chosen[0]])
    mujoco.mj_forward(env.model, env.data)
    assert not env._success()

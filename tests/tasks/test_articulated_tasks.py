"""Success and near-miss states of the drawer, cupboard and dishwasher tasks."""

from __future__ import annotations

import mujoco
import pytest

from bigym.envs import cupboards, dishwasher

ARTICULATED = [
    cupboards.DrawerTopOpen,
    cupboards.DrawerTopClose,
    cupboards.DrawersOpenAll,
    cupboards.DrawersCloseAll,
    cupboards.WallCupboardOpen,
    cupboards.WallCupboardClose,
    cupboards.CupboardsOpenAll,
    cupboards.CupboardsCloseAll,
    dishwasher.DishwasherOpen,
    dishwasher.DishwasherClose,
    dishwasher.DishwasherOpenTrays,
    dishwasher.DishwasherCloseTrays,
]


def _targets(env):
    """(prop, joint key) pairs that must reach the goal."""
    if isinstance(env, dishwasher._DishwasherTask):
        return [("dishwasher", key) for key in env.targets]
    return [(prop, key) for prop, keys in env.targets for key in keys]


def _set(env, pairs, value):
    for prop, key in pairs:
        env.props[prop].set_joint_state(env.data, key, value)
    mujoco.mj_forward(env.model, env.data)


@pytest.fixture(scope="module", params=ARTICULATED, ids=lambda c: c.__name__)
def env(request):
    environment = request.param()
    yield environment
    environment.close()


def test_goal_state_succeeds_and_pays(env):
    env.reset(seed=0)
    _set(env, _targets(env), env.goal)
    assert env._success()
    _, reward, terminated, _, info = env.step(env.action_space.sample() * 0)
    assert info["is_success"] and reward == 1.0 and terminated


def test_goal_within_tolerance_succeeds(env):
    env.reset(seed=1)
    _set(env, _targets(env), abs(env.goal - 0.09))
    assert env._success()


@pytest.mark.parametrize("miss", [0.15, 0.3])
def test_each_joint_short_of_the_goal_fails(env, miss):
    """A drawer at 0.85 open (or 0.15 when closing) is not done, whichever joint it is."""
    targets = _targets(env)
    for short in targets:
        env.reset(seed=2)
        _set(env, targets, env.goal)
        _set(env, [short], abs(env.goal - miss))
        assert not env._success(), f"{short} at {abs(env.goal - miss)} counted as done"


def test_non_target_joints_do_not_count(env):
    """Opening everything else does not solve a task about other joints."""
    env.reset(seed=3)
    others = [
        (name, key)
        for name, prop in env._articulated.items()
        for key in prop.joint_keys
        if (name, key) not in _targets(env)
    ]
    _set(env, others, env.goal)
    assert not env._success()

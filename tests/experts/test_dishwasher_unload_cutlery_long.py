"""The DishwasherUnloadCutleryLong expert (``bigym.experts.dishwasher_unload_cutlery_long``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case. This checks the way it succeeds: the drawer is opened by the free hand while the
other one holds the fork, the fork is let go resting in a compartment of the drawer's
tray with the drawer still fully open, the drawer is shut only after that, and the
dishwasher last; and that the hand taking the fork varies, with the body standing so
that the fork is in front of that hand.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.dishwasher_cutlery import DishwasherUnloadCutleryLong
from bigym.experts.dishwasher_unload_cutlery_long import CABINET, DRAWER, ITEM, CutleryDrawerExpert
from bigym.experts.expert import LEFT, RIGHT, SIDE_INDEX
from bigym.experts.geometry import yaw_matrix


@pytest.fixture(scope="module")
def env():
    env = DishwasherUnloadCutleryLong(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500
    )
    yield env
    env.close()


def lower_end(env) -> np.ndarray:
    """The fork's handle end (its lower end when it stands or is held)."""
    body = env.props[ITEM].root_body_id
    axis = env.data.xmat[body].reshape(3, 3)[:, 1]
    return env.data.xpos[body] - axis * 0.5 * env.props[ITEM].length


def test_fork_laid_in_the_open_drawer_then_drawer_and_dishwasher_shut(env):
    obs, _ = env.reset(seed=0)
    expert = CutleryDrawerExpert(env, seed=0)
    tray = env.mask("cutlery_tray")
    events: dict[str, float] = {}
    held_when_opened = None
    released = None  # (end over the compartment's floor, drawer state, touching the tray)
    info = {}
    for _ in range(env.max_episode_steps):
        obs, _, terminated, truncated, info = env.step(expert(obs))
        drawer = expert.joint_state(CABINET, DRAWER)
        held = env.held(ITEM)
        if held and "taken" not in events and lower_end(env)[2] > 0.6:
            events["taken"] = env.data.time
        if "opened" not in events and drawer > 0.9:
            events["opened"], held_when_opened = env.data.time, held
        if "opened" in events and released is None and not held:
            floor = env.props["cutlery_tray"].site_pos(env.data, f"slot_{expert.choices[f'{ITEM} slot']}")[2]
            released = (lower_end(env)[2] - floor, drawer, env.touching(env.mask(ITEM), tray))
            events["released"] = env.data.time
        if "released" in events and "shut" not in events and drawer < 0.1:
            events["shut"] = env.data.time
        if terminated or truncated:
            break
    assert info.get("is_success"), expert.events
    assert list(events) == ["taken", "opened", "released", "shut"], events
    assert held_when_opened  # the other hand opened it
    above_floor, drawer_then, touching = released
    assert above_floor < 0.03, released  # let go resting on its end, not dropped in
    assert drawer_then > 0.9 and touching, released
    hand = SIDE_INDEX[expert.choices["fork hand"]]
    assert expert.choices[f"{ITEM} slot"] in expert.slots[hand]
    assert expert.joint_state("dishwasher", "door") < 0.1 and expert.joint_state("dishwasher", "tray_bottom") < 0.1


def test_either_hand_takes_the_fork_standing_with_the_fork_in_front_of_it(env):
    hands = set()
    for seed in range(6):
        obs, _ = env.reset(seed=seed)
        expert = CutleryDrawerExpert(env, seed=seed)
        for _ in range(env.max_episode_steps):
            obs, *_ = env.step(expert(obs))
            if any(name.startswith("pick") for _, name in expert.events):
                break
        side = SIDE_INDEX[expert.choices["fork hand"]]
        hands.add(side)
        base = expert.base_pose()
        fork = yaw_matrix(base[3]).T @ (expert.end(ITEM, 1.0) - base[:3])
        assert fork[1] > 0.0 if side == LEFT else fork[1] < 0.0, (seed, side, fork)
    assert hands == {LEFT, RIGHT}

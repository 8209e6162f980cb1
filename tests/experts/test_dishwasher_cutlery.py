"""The DishwasherUnloadCutlery expert lays each piece in the tray (``bigym.experts.dishwasher_cutlery``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case. This checks the way it succeeds: each piece is stood on its end in the tray while
still held, tipped over about that end, and let go only once it nearly lies flat (not
dropped standing, which often throws it over the tray's wall), in a compartment on
its hand's side; and the hand that goes first varies.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.dishwasher_cutlery import DishwasherUnloadCutlery
from bigym.experts.dishwasher_cutlery import ITEMS, SLOTS, TRAY, CutleryUnloadExpert
from bigym.experts.expert import LEFT, RIGHT


@pytest.fixture(scope="module")
def env():
    env = DishwasherUnloadCutlery(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500
    )
    yield env
    env.close()


def elevation(env, item: str) -> float:
    """How steeply (deg) a piece rises from its handle end to its head."""
    axis = env.data.xmat[env.props[item].root_body_id].reshape(3, 3)[:, 1]
    return float(np.degrees(np.arcsin(np.clip(axis[2], -1.0, 1.0))))


def test_each_piece_is_stood_in_the_tray_tipped_over_and_let_go_nearly_flat(env):
    obs, _ = env.reset(seed=0)
    expert = CutleryUnloadExpert(env, seed=0)
    tray = env.mask(TRAY)
    stood_upright = {}  # piece -> its elevation when it first touched the tray, held
    let_go = {}  # piece -> its elevation when its hand opened
    info = {}
    for _ in range(env.max_episode_steps):
        obs, _, terminated, truncated, info = env.step(expert(obs))
        for item in ITEMS:
            if item not in stood_upright and env.held(item) and env.touching(env.mask(item), tray):
                stood_upright[item] = elevation(env, item)
            if item in stood_upright and item not in let_go and not env.held(item):
                let_go[item] = elevation(env, item)
        if terminated or truncated:
            break
    assert info.get("is_success"), expert.events
    assert set(let_go) == set(ITEMS), let_go
    for item in ITEMS:
        assert stood_upright[item] > 55.0, (item, stood_upright)  # on its end, held
        assert let_go[item] < 35.0, (item, let_go)  # tipped over in the hand, then let go
        # a compartment on its hand's side (slot 1 at the tray's +y end, the body's left)
        side = LEFT if expert.choices["left hand"] == item else RIGHT
        assert expert.choices[f"{item} slot"] in SLOTS[side]
        assert env.touching(env.mask(item), tray)


def test_the_hand_that_goes_first_varies(env):
    firsts = set()
    for seed in range(6):
        obs, _ = env.reset(seed=seed)
        expert = CutleryUnloadExpert(env, seed=seed)
        for _ in range(env.max_episode_steps):  # drawn once the body stands at the basket
            if "first" in expert.choices:
                break
            obs, *_ = env.step(expert(obs))
        firsts.add(expert.choices.get("first"))
    assert firsts == {"left", "right"}

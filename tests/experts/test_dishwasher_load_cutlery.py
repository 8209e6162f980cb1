"""The DishwasherLoadCutlery expert stands each piece in the basket (``bigym.experts.dishwasher_load_cutlery``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case. This checks the way it succeeds: both pieces are held before either leaves the mug
(taken one at a time, drawing the first out jostles the mug and the other piece falls),
each is let go only once its foot rests on its compartment's floor (not dropped into the
basket), in a compartment on its hand's side, and ends standing; and the way the body
turns to the mug follows how the pieces lean. Seed 1 is a shipped demo's: the expert
sometimes lets the long knife go on top of a wall of the far row, and the generator's drop
check rejects those demos (seed 0 is one).
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.dishwasher_cutlery import DishwasherLoadCutlery
from bigym.experts.dishwasher_cutlery import ITEMS
from bigym.experts.dishwasher_load_cutlery import LANDED, MUG, SLOTS, CutleryLoadExpert
from bigym.experts.expert import LEFT, RIGHT


@pytest.fixture(scope="module")
def env():
    env = DishwasherLoadCutlery(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500
    )
    yield env
    env.close()


def foot_height(env, item: str) -> float:
    """Height (m) of a piece's handle end."""
    body = env.props[item].root_body_id
    axis = env.data.xmat[body].reshape(3, 3)[:, 1]
    return float(env.data.xpos[body][2] - axis[2] * 0.5 * env.props[item].length)


def elevation(env, item: str) -> float:
    """How steeply (deg) a piece rises from its handle end to its head."""
    axis = env.data.xmat[env.props[item].root_body_id].reshape(3, 3)[:, 1]
    return float(np.degrees(np.arcsin(np.clip(axis[2], -1.0, 1.0))))


def test_both_pieces_are_held_before_either_leaves_the_mug_and_each_is_let_go_resting(env):
    obs, _ = env.reset(seed=1)
    expert = CutleryLoadExpert(env, seed=1)
    basket = env.mask("dishwasher", "basket")
    left_mug = {}  # piece -> whether the other piece was held when its foot rose over the rim
    released = {}  # piece -> (foot height over its compartment's floor, slot) when let go
    info = {}
    for _ in range(env.max_episode_steps):
        obs, _, terminated, truncated, info = env.step(expert(obs))
        for item, other in zip(ITEMS, ITEMS[::-1], strict=True):
            rim = env.props[MUG].site_pos(env.data, "rim")[2]
            if item not in left_mug and env.held(item) and foot_height(env, item) > rim:
                left_mug[item] = env.held(other)
            if item in left_mug and item not in released and not env.held(item):
                slot = expert.choices[f"{item} slot"]
                floor = env.props["dishwasher"].site_pos(env.data, f"basket_slot_{slot}")[2]
                released[item] = (foot_height(env, item) - floor, slot)
        if terminated or truncated:
            break
    assert info.get("is_success"), expert.events
    assert left_mug == {item: True for item in ITEMS}, left_mug
    assert set(released) == set(ITEMS), released
    for item in ITEMS:
        above_floor, slot = released[item]
        assert above_floor < LANDED + 0.005, (item, released)  # resting, not dropped in
        side = LEFT if expert.choices["left hand"] == item else RIGHT
        assert slot in SLOTS[side]  # on its hand's side (slot 1 at the basket's +y end)
        assert env.touching(env.mask(item), basket)
        assert elevation(env, item) > 55.0, (item, elevation(env, item))  # standing, leaning on a wall


def test_the_body_turns_to_the_mug_as_the_pieces_lean_and_the_first_hand_varies(env):
    facings, firsts = [], set()
    for seed in range(6):
        obs, _ = env.reset(seed=seed)
        expert = CutleryLoadExpert(env, seed=seed)
        for _ in range(env.max_episode_steps):  # both drawn before the hands move
            if "first" in expert.choices:
                break
            obs, *_ = env.step(expert(obs))
        knife, fork = expert.end("knife", 1.0), expert.end("fork", 1.0)
        line = np.arctan2(knife[1] - fork[1], knife[0] - fork[0])
        # the tops stand side by side for the body: their line within 50 deg of its lateral
        # axis (it turns up to 46 deg, plus its stance's spread)
        across = abs(np.angle(np.exp(2j * (line - expert.facing - 0.5 * np.pi)))) / 2.0
        assert across < np.deg2rad(50.0), (seed, np.degrees(line), expert.facing)
        facings.append(expert.facing)
        firsts.add(expert.choices["first"])
    assert max(facings) - min(facings) > 0.5, facings
    assert firsts == {"left", "right"}

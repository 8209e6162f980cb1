"""The groceries demonstrator's choices: which hand takes which item, and where on a long
box the fingers close."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from bigym.experts.expert import LEFT, RIGHT
from bigym.experts.generate import _env, close_envs
from bigym.experts.groceries import CUPBOARD, DOOR, TURN_TOWARDS, GroceriesExpert
from bigym.props.base import quat_yaw


@pytest.fixture(scope="module")
def env():
    env = _env("StoreGroceriesLower")
    yield env
    close_envs()


def _expert(env, seed: int, door_open: bool, ys=(0.03, -0.17, -0.37, -0.57), episode: int = 0) -> GroceriesExpert:
    """An expert on a fresh episode (``episode`` seeds the reset) whose four items stand in
    a row at ``ys``, with the body kept out of the open door's way (as after the door) or not."""
    obs, _ = env.reset(seed=episode)
    for name, y in zip(env.chosen, ys, strict=True):
        position = env.data.xpos[env.props[name].root_body_id].copy()
        env.props[name].set_pose(env.data, (0.7, y, position[2]))
    mujoco.mj_forward(env.model, env.data)
    expert = GroceriesExpert(env, seed=seed)
    expert(obs)  # starts the script
    if door_open:
        expert.keep_clear_of_open_door(CUPBOARD, DOOR)
    return expert


def test_an_item_the_right_hand_cannot_stand_beside_goes_to_the_left_hand(env):
    """The open door keeps the body right of the leftmost item: whatever order is drawn,
    that item is among the left hand's (the first half). Without the door in the way the
    drawn order sometimes gives it to the right hand, so the rule is what keeps it left."""
    leftmost_rank = {True: set(), False: set()}
    for door_open in (True, False):
        for seed in range(40):
            expert = _expert(env, seed, door_open)
            order = expert.item_order()
            assert sorted(order) == sorted(env.chosen)
            leftmost = max(order, key=expert.item_y)
            leftmost_rank[door_open].add(order.index(leftmost))
    assert leftmost_rank[True] <= {0, 1}
    assert leftmost_rank[False] - {0, 1}


def test_a_long_box_is_reached_from_its_near_end(env):
    """The cereal box's colliders reach 0.095 m from its origin along its length and 0.035 m
    across it, whichever way it stands: the fingers close near the end they come from."""
    obs, _ = env.reset(seed=0)
    expert = GroceriesExpert(env, seed=0)
    for yaw in (0.0, 0.7, -2.0):
        env.props["cereals"].set_pose(env.data, (0.7, 0.0, 0.9), quat_yaw(yaw))
        mujoco.mj_forward(env.model, env.data)
        length = np.array([-np.sin(yaw), np.cos(yaw), 0.0])  # the box's local y
        across = np.array([np.cos(yaw), np.sin(yaw), 0.0])
        assert expert.item_reach("cereals", length) == pytest.approx(0.095, abs=1e-6)
        assert expert.item_reach("cereals", -length) == pytest.approx(0.095, abs=1e-6)
        assert expert.item_reach("cereals", across) == pytest.approx(0.035, abs=1e-6)
    # a round item reaches as far every way
    env.props["soup_can"].set_pose(env.data, (0.7, 0.3, 0.9))
    mujoco.mj_forward(env.model, env.data)
    reaches = [expert.item_reach("soup_can", np.array([np.cos(a), np.sin(a), 0.0])) for a in (0.0, 1.0, 2.5)]
    assert max(reaches) - min(reaches) < 1e-9 and 0.02 < reaches[0] < 0.06


def test_the_cereal_box_goes_to_the_right_hand_where_it_can_stand_near_enough(env):
    """Second nearest the open door, an item is the left hand's in the nearest-first order
    (the right hand cannot stand beside it); the cereal box (standing so that either hand
    can take it) goes to the right hand there all the same, taken from the door's edge,
    across the body (the left hand, beside the door, dropped it in most seeds). Whatever
    else stands there stays with the left hand."""
    episode = 2  # draws the cereal box
    ranks: dict[str, set[int]] = {}
    for seed in range(30):
        expert = _expert(env, seed, door_open=True, episode=episode)
        assert "cereals" in env.chosen
        second = sorted(env.chosen, key=expert.item_y, reverse=True)[1]
        order = expert.item_order()
        ranks.setdefault(second, set()).add(order.index(second))
    assert ranks.get("cereals", set()) and ranks["cereals"] <= {2, 3}
    # the same place with another item in it (the items' order along the row shifted by one)
    other_ranks = set()
    for seed in range(30):
        expert = _expert(env, seed, door_open=True, ys=(-0.17, 0.03, -0.37, -0.57), episode=episode)
        second = sorted(env.chosen, key=expert.item_y, reverse=True)[1]
        assert second != "cereals"
        other_ranks.add(expert.item_order().index(second))
    assert other_ranks & {0, 1}


def test_a_box_goes_to_the_hand_that_takes_it_without_turning_the_body_towards_that_hand(env):
    """The fingers close across the detergent's narrow faces, so the body turns with the
    box's yaw; turned towards the hand that takes it, that shoulder draws back from the
    counter (the hand fell short three times running). Turned any way on the counter, far
    from the door, the box goes to the hand that turns the body away from itself or less
    than ``TURN_TOWARDS`` towards it; both hands get boxes."""
    hands = set()
    for yaw in np.linspace(-np.pi / 2, np.pi / 2, 13):
        expert = _expert(env, 0, door_open=True, episode=9)  # draws the detergent
        position = env.data.xpos[env.props["detergent"].root_body_id].copy()
        env.props["detergent"].set_pose(env.data, (0.7, -0.57, position[2]), quat_yaw(yaw))
        mujoco.mj_forward(env.model, env.data)
        normal = yaw + 0.5 * np.pi  # the narrow faces' normal: the box's local y
        _, turn_left = expert.face_closing(LEFT, normal, faces=2, facing_yaw=0.0)
        _, turn_right = expert.face_closing(RIGHT, normal, faces=2, facing_yaw=0.0)
        hand = expert.box_hand("detergent")
        if turn_left > TURN_TOWARDS:  # towards the left hand
            assert hand == RIGHT and turn_right > -TURN_TOWARDS
        elif turn_right < -TURN_TOWARDS:  # towards the right hand
            assert hand == LEFT
        else:
            assert hand is None
        hands.add(hand)
    assert {LEFT, RIGHT} <= hands

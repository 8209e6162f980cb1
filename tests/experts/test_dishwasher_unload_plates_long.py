"""The DishwasherUnloadPlatesLong expert (``bigym.experts.dishwasher_unload_plates_long``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case. This checks the way it succeeds: the plate is let go standing upright in the slot
the expert chose, at rest, inside the cabinet, while the cabinet door is open; the
cabinet and then the dishwasher are shut after that; and the half of the cabinet (so
the door and the hand) varies over seeds.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.dishwasher_plates import PLATE_IN_SLOT, DishwasherUnloadPlatesLong
from bigym.experts.dishwasher_unload_plates_long import PlateCabinetExpert
from bigym.experts.wall_cabinet import CABINET, DOORS

PLATE = "plate_1"


@pytest.fixture(scope="module")
def env():
    env = DishwasherUnloadPlatesLong(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500
    )
    yield env
    env.close()


def test_the_plate_is_let_go_upright_in_its_slot_then_cabinet_and_dishwasher_shut(env):
    obs, _ = env.reset(seed=1)
    expert = PlateCabinetExpert(env, seed=1)
    body = env.props[PLATE].root_body_id
    released = None  # (plate origin off its slot's rest, face normal, a cabinet door open)
    shut_after_release = None
    held_inside = False
    info = {}
    for _ in range(env.max_episode_steps):
        obs, _, terminated, truncated, info = env.step(expert(obs))
        held = env.held(PLATE)
        held_inside = held_inside or (held and env.data.xpos[body][0] > 0.7)
        if released is None and held_inside and not held:
            rest = env.props["drainer"].site_pos(env.data, expert.choices["slot"]) + PLATE_IN_SLOT
            door_open = max(expert.joint_state(CABINET, key) for key in DOORS)
            released = (env.data.xpos[body] - rest, env.data.xmat[body].reshape(3, 3)[:, 2].copy(), door_open)
        if (
            released is not None
            and shut_after_release is None
            and max(expert.joint_state(CABINET, key) for key in DOORS) < 0.1
        ):
            shut_after_release = expert.joint_state("dishwasher", "door")
        if terminated or truncated:
            break
    assert info.get("is_success"), expert.events
    off, normal, door_open = released
    # standing upright in its slot: within the slot's 7 mm across, its face along y
    assert abs(off[1]) < 0.012 and abs(off[0]) < 0.03 and abs(off[2]) < 0.015, off
    assert abs(normal[1]) > np.cos(np.deg2rad(20.0)), normal
    assert door_open > 0.9, released
    # the cabinet was shut while the dishwasher was still open
    assert shut_after_release is not None and shut_after_release > 0.5


def test_either_half_of_the_cabinet_with_its_door_and_hand(env):
    choices = set()
    for seed in range(6):
        env.reset(seed=seed)
        expert = PlateCabinetExpert(env, seed=seed)
        expert.start()
        half, slot = expert.choose_slot()
        door = expert.door_of_half(half)
        # the door covers the slot's side of the cabinet, and the hand is on that side
        middle = expert.cabinet_middle()
        slot_y = env.props["drainer"].site_pos(env.data, slot)[1]
        assert np.sign(slot_y - middle) == half
        assert np.sign(expert.site(CABINET, f"{door}_handle")[1] - middle) == half
        choices.add((half, door))
    assert len(choices) == 2

"""The DishwasherLoadPlates expert (``bigym.experts.dishwasher_load_plates``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case (which also rejects a plate dropped in). This checks the way it succeeds: each plate
ends upright, all the way down in the gap of the tray's front row chosen for it, with a
free slot at least between the two and the left hand's plate further left; and that which
hand goes first varies.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.dishwasher_plates import DISHWASHER, FRONT_ROW, DishwasherLoadPlates
from bigym.experts.dishwasher_load_plates import LOAD_IN_SLOT, LOAD_SLOTS, PlateLoadExpert
from bigym.experts.expert import SIDE_INDEX
from bigym.experts.move_plates import SLOT_GAP


@pytest.fixture(scope="module")
def env():
    env = DishwasherLoadPlates(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500
    )
    yield env
    env.close()


def test_each_plate_ends_upright_all_the_way_down_in_the_gap_chosen_for_it(env, run_episode):
    obs, _ = env.reset(seed=1)
    expert = PlateLoadExpert(env, seed=1)
    info = run_episode(env, expert, obs)
    assert info.get("is_success"), expert.events
    tray = env.props[DISHWASHER]
    rests = [tray.site_pos(env.data, key) + LOAD_IN_SLOT for key in FRONT_ROW]  # where the tray is now
    slot_of = {}
    for plate in env.items:
        body = env.props[plate].root_body_id
        origin = env.data.xpos[body]
        k = int(np.argmin([np.linalg.norm(origin - rest) for rest in rests]))
        off = origin - rests[k]
        # between the two tines of that gap (the gap leaves 7 mm of play; a plate may slide
        # along the tines), all the way down, upright with its face along them
        assert abs(off[1]) < 0.008 and abs(off[0]) < 0.04 and abs(off[2]) < 0.01, (plate, off)
        assert abs(env.data.xmat[body].reshape(3, 3)[1, 2]) > np.cos(np.deg2rad(10.0)), plate
        slot_of[plate] = FRONT_ROW[k]
    assert sorted(slot_of.values()) == sorted(expert.choices["slots"])  # the gaps it chose
    assert set(slot_of.values()) <= set(LOAD_SLOTS)  # not the narrow gap beside the wall
    ks = sorted(FRONT_ROW.index(slot) for slot in slot_of.values())
    assert ks[1] - ks[0] > SLOT_GAP
    # the left hand put its plate further left (+y): the front row's slots run from -y to +y
    hands = dict(entry.split(":")[::-1] for entry in expert.choices["hands"])
    assert FRONT_ROW.index(slot_of[hands["left"]]) > FRONT_ROW.index(slot_of[hands["right"]])


def test_which_hand_goes_first_varies(env):
    firsts = set()
    for seed in range(6):
        obs, _ = env.reset(seed=seed)
        expert = PlateLoadExpert(env, seed=seed)
        env.step(expert(obs))
        firsts.add(SIDE_INDEX[expert.choices["hands"][0].split(":")[1]])
    assert len(firsts) == 2

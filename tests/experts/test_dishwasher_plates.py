"""The DishwasherUnloadPlates expert (``bigym.experts.dishwasher_plates``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case. This checks the way it succeeds: each hand takes the plate on its side, and each
plate is let go standing upright at rest in its own slot (not dropped in), with a free
slot at least between the two; and that which hand goes first varies.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.dishwasher_plates import PLATE_IN_SLOT, DishwasherUnloadPlates
from bigym.experts.dishwasher_plates import DRAINER, PlateUnloadExpert
from bigym.experts.expert import SIDE_INDEX
from bigym.experts.move_plates import SLOT_GAP


@pytest.fixture(scope="module")
def env():
    env = DishwasherUnloadPlates(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500
    )
    yield env
    env.close()


def test_each_plate_is_let_go_upright_at_rest_in_its_own_slot(env):
    obs, _ = env.reset(seed=1)
    expert = PlateUnloadExpert(env, seed=1)
    drainer = env.props[DRAINER]
    was_held = {plate: False for plate in env.items}
    released = {}  # plate -> (origin minus its resting place in the nearest slot, slot index, face normal)
    # (when it was last let go)
    info = {}
    for _ in range(env.max_episode_steps):
        obs, _, terminated, truncated, info = env.step(expert(obs))
        for plate in env.items:
            body = env.props[plate].root_body_id
            held = env.held(plate)
            if was_held[plate] and not held:  # the last letting go counts (a slipped plate is taken again)
                origin = env.data.xpos[body]
                rests = [drainer.site_pos(env.data, key) + PLATE_IN_SLOT for key in drainer.slot_keys]
                k = int(np.argmin([np.linalg.norm(origin - rest) for rest in rests]))
                released[plate] = (origin - rests[k], k, env.data.xmat[body].reshape(3, 3)[:, 2].copy())
            was_held[plate] = held
        if terminated or truncated:
            break
    assert info.get("is_success"), expert.events
    assert set(released) == set(env.items), released
    for plate, (off, _, normal) in released.items():
        assert np.all(np.abs(off) < 0.015), (plate, off)  # in the slot, resting, not dropped in
        assert abs(normal[1]) > np.cos(np.deg2rad(15.0)), (plate, normal)  # upright, face along y
    slots = sorted(k for _, k, _ in released.values())
    assert slots[1] - slots[0] > SLOT_GAP
    # the left hand took (and put in) the plate further left (+y): slot keys run from +y to -y
    hands = dict(entry.split(":")[::-1] for entry in expert.choices["hands"])
    assert released[hands["left"]][1] < released[hands["right"]][1]


def test_which_hand_goes_first_varies(env):
    firsts = set()
    for seed in range(6):
        obs, _ = env.reset(seed=seed)
        expert = PlateUnloadExpert(env, seed=seed)
        env.step(expert(obs))
        firsts.add(SIDE_INDEX[expert.choices["hands"][0].split(":")[1]])
    assert len(firsts) == 2

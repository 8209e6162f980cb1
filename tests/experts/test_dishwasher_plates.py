"""The DishwasherUnloadPlates expert (``bigym.experts.dishwasher_plates``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case. This checks the way it succeeds: each hand takes the plate on its side, and each
plate is let go standing upright at rest in its own slot (not dropped in), with a free
slot at least between the two; and that which hand goes first varies.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.dishwasher_plates import PLATE_IN_SLOT, PLATE_QUAT, DishwasherUnloadPlates
from bigym.experts.dishwasher_plates import DRAINER, PlateUnloadExpert
from bigym.experts.expert import SIDE_INDEX
from bigym.experts.move_plates import SLOT_GAP
from bigym.props.base import quat_axis_angle, quat_mul


@pytest.fixture(scope="module")
def env():
    env = DishwasherUnloadPlates(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500
    )
    yield env
    env.close()


@pytest.mark.parametrize("seed", [1, 0])
def test_each_plate_is_let_go_upright_at_rest_in_its_own_slot(env, seed):
    """Seed 0: the IK left the first plate leaning and 8 cm off over its slot, and it was let
    go on the holders and fell off the drainer's back, until the hand straightened it and
    moved it over the slot by what it saw."""
    obs, _ = env.reset(seed=seed)
    expert = PlateUnloadExpert(env, seed=seed)
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


@pytest.mark.parametrize("lean_deg", [-8.0, -5.0, 0.0, 5.0, 8.0])
def test_a_plate_posed_where_fit_error_is_nil_goes_between_the_holders(env, lean_deg):
    """The plate, leaning by ``lean_deg`` (face tipped up) and seated at the height of its
    slot where :meth:`fit_error` says it fits, overlaps no part of the drainer; put where
    its origin would be upright (no allowance for the lean), a face tipped up 5 degrees or
    more puts its rim on the holders (tipped down, the slot's wider side takes it)."""
    env.reset(seed=0)
    expert = PlateUnloadExpert(env, seed=0)
    model, data = env.model, env.data
    drainer = env.props[DRAINER]
    plate = env.items[0]
    body = env.props[plate].root_body_id
    address = model.jnt_qposadr[model.body_jntadr[body]]
    drainer_root = model.body_rootid[drainer.root_body_id]
    goal = drainer.site_pos(data, drainer.slot_keys[2]) + PLATE_IN_SLOT
    quat = quat_mul(quat_axis_angle((1.0, 0.0, 0.0), np.deg2rad(lean_deg)), PLATE_QUAT)

    def overlap(position) -> float:
        data.qpos[address : address + 3] = position
        data.qpos[address + 3 : address + 7] = quat
        mujoco.mj_forward(model, data)
        depths = []
        for contact in data.contact[: data.ncon]:
            bodies = model.geom_bodyid[[contact.geom1, contact.geom2]]
            if body in bodies and drainer_root in model.body_rootid[bodies]:
                depths.append(contact.dist)
        return -min(depths, default=0.0)

    upright_rest = overlap(goal)  # posed leaning, its origin at the slot's rest point
    fits = goal.copy()
    fits[:2] -= expert.fit_error(body, goal)  # read from that pose
    assert np.linalg.norm(fits - goal) > 0.0
    assert overlap(fits) < 0.001
    if lean_deg >= 5.0:
        assert upright_rest > 0.001

"""ContactState answers "does A touch B" exactly as a plain scan of data.contact does."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from bigym.contacts import MAX_BITS, ContactState
from bigym.envs.manipulation import StackBlocks
from bigym.envs.pick_and_place import PutCups
from bigym.props.base import geoms_in_contact

from testkit import touch_with_gripper


def _reference(data, a, b) -> bool:
    return geoms_in_contact(data, a.mask, b.mask)


@pytest.mark.parametrize("cls", [StackBlocks, PutCups], ids=lambda c: c.__name__)
def test_every_query_agrees_with_a_plain_contact_scan(cls):
    env = cls()
    try:
        # The task's own sets, and every prop (supports such as tables and counters included).
        sets = list(env._mask_cache.values()) + [env.floor_mask, env.gripper_mask]
        sets += [env.mask(name) for name in sorted(env.props)][: 24 - len(sets)]
        sets.append(env.union(*sets[:2]))
        assert all(s.bit for s in sets), "premise: every set has a bit"
        rng = np.random.default_rng(0)
        checked = touching = 0
        for seed in range(3):
            env.reset(seed=seed)
            for step in range(60):
                env.step(rng.uniform(env.action_space.low, env.action_space.high).astype(np.float32) * 0.3)
                if step % 20:
                    continue
                for held in (False, True):  # fresh reads, and one shared reading
                    if held:
                        env.contacts.hold()
                    for a in sets:
                        for b in sets:
                            expected = _reference(env.data, a, b)
                            assert env.contacts.touching(a, b) == expected
                            assert env.contacts.touching(a.mask, b.mask) == expected  # the mask path
                            checked += 1
                            touching += expected
                    env.contacts.release()
        assert checked > 0 and 0 < touching < checked, "premise: both answers occur"
    finally:
        env.close()


def test_fresh_reads_outside_a_step_see_state_edits():
    """Tests and experts edit the state and call mj_forward between questions."""
    env = PutCups()
    try:
        env.reset(seed=0)
        mug, gripper = env.mask("mug_1"), env.gripper_mask
        assert not env.touching(mug, gripper)
        touch_with_gripper(env, "mug_1")
        assert env.touching(mug, gripper)
    finally:
        env.close()


def test_sets_beyond_the_bits_fall_back_to_masks():
    model = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><geom name='floor' type='plane' size='1 1 .1'/>"
        + "".join(f"<body pos='{i * 0.3} 0 0.05'><freejoint/><geom type='box' size='.1 .1 .1'/></body>" for i in range(3))
        + "</worldbody></mujoco>"
    )
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    contacts = ContactState(model, data)
    sets = [contacts.geom_set([g]) for g in range(model.ngeom) for _ in range(MAX_BITS // model.ngeom + 1)]
    assert sets[MAX_BITS - 1].bit and not sets[MAX_BITS].bit, "the 32nd set has no bit"
    floor, box = contacts.geom_set([0]), contacts.geom_set([1])
    assert floor.bit == 0 and contacts.touching(floor, box) and not contacts.touching(box, contacts.geom_set([2]))
    with pytest.raises(ValueError, match="out of range"):
        contacts.geom_set([model.ngeom])

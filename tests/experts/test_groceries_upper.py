"""The StoreGroceriesUpper expert (``bigym.experts.groceries_upper``).

That the task succeeds and its demo replays at every rate is ``test_experts``' generic
case (which also rejects an item dropped on the way). This checks the way it succeeds:
all four items stand upright on the open shelf, side by side, let go, two carried in each
hand, the pair nearest the shelf first.
"""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.groceries import StoreGroceriesUpper
from bigym.experts.groceries_upper import SHELF_TOP, UpperGroceriesExpert


@pytest.fixture(scope="module")
def env():
    env = StoreGroceriesUpper(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500
    )
    yield env
    env.close()


def test_four_items_stand_side_by_side_on_the_open_shelf(env, run_episode):
    obs, _ = env.reset(seed=7)
    start_y = {item: float(env.data.xpos[env.props[item].root_body_id][1]) for item in env.chosen}
    expert = UpperGroceriesExpert(env, seed=7)
    info = run_episode(env, expert, obs)
    assert info.get("is_success"), expert.events
    shelf = env.mask("open_shelf", "shelf")
    ys = []
    for item in env.chosen:
        body = env.props[item].root_body_id
        assert env.touching(env.mask(item), shelf), item
        assert not env.held(item), item
        assert abs(env.data.xpos[body][2] - SHELF_TOP) < 0.005, item  # its base on the board
        assert env.data.xmat[body].reshape(3, 3)[2, 2] > np.cos(np.deg2rad(5.0)), item  # upright
        ys.append(float(env.data.xpos[body][1]))
    ys.sort()
    assert min(np.diff(ys)) > 0.1  # side by side, apart
    hands = [entry.split(":")[1] for entry in expert.choices["hands"]]
    assert sorted(hands) == ["left", "left", "right", "right"]
    # the first pair taken is the one nearest the shelf (lowest y on the counter)
    first_pair = [entry.split(":")[0] for entry in expert.choices["hands"][:2]]
    assert set(first_pair) == set(sorted(start_y, key=start_y.get)[:2])

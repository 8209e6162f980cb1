"""The box carry's hold (``bigym.experts.boxes``): the two fists move as one rigid squeeze.

That the expert puts the box on the counter and its demo replays at every rate is
``test_experts``' generic case for ``PickBox``.
"""

from __future__ import annotations

import numpy as np

from bigym.experts.boxes import BoxExpert


def test_box_expert_hold_is_one_rigid_squeeze():
    """Both hands follow one hold path: their gap is what the hold says, wherever the box
    is moved and however the base moves."""
    from bigym.action_modes import JointPositionActionMode
    from bigym.envs.pick_and_place import PickBox

    env = PickBox(action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500)
    try:
        obs, _ = env.reset(seed=0)
        expert = BoxExpert(env, seed=0)
        expert(obs)  # starts the plan
        expert._box_path = (lambda t: np.array([0.4, 0.0, -0.2, 0.1]), expert.time, 0.0)
        end = expert.hold_box(np.array([0.5, 0.1, 0.0]), 0.05, 1.0)
        for t in np.linspace(expert.time, end, 5):
            left = expert.hands[0].position(t)
            right = expert.hands[1].position(t)
            base = expert.base_ref(t)
            lateral = np.array([-np.sin(base[3]), np.cos(base[3]), 0.0])
            gap = float((left - right) @ lateral) / 2.0
            progress = (t - expert.time) / (end - expert.time)
            expected = 0.1 + (0.05 - 0.1) * float(expert.human.profile(progress))
            assert abs(gap - expected) < 1e-9
        np.testing.assert_allclose(expert.box_now(), [0.4, 0.0, -0.2, 0.1])  # nothing moved yet
    finally:
        env.close()

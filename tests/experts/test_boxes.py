"""The box carry (``bigym.experts.boxes``): the expert squeezes the 5 kg box of
``PickBox`` between its fists, lifts it off the floor and puts it on the counter, and its
demo replays to success at 50 Hz, the evaluation rate.

The expert is not in the registry (``EXPERTS``) and ``PickBox`` not in the dataset: its
demos replay at 500 and 50 Hz, but at 25 and 20 Hz the floating base takes each new
target in a jolt (``benchmarks/base_jolt.py``) that shakes the box out of the squeeze in
most of them. A case may use up to ``SPARE_SEEDS`` extra seeds (about 3 in 4 recordings
pass at 500 and 50 Hz).
"""

from __future__ import annotations

import numpy as np

from bigym.demonstrations import Demo
from bigym.experts.boxes import BoxExpert
from bigym.experts.generate import close_envs, record_attempt

SPARE_SEEDS = 3


def test_box_expert_puts_the_box_on_the_counter_and_its_demo_replays_at_50_hz():
    failures = []
    try:
        for seed in range(0, 1 + SPARE_SEEDS):
            attempt = record_attempt("PickBox", index=0, seed=seed, expert_class=BoxExpert, rates=(50.0,))
            if attempt.success:
                break
            failures.append(f"seed {seed}: {attempt.reason}")
        assert attempt.success, "; ".join(failures)
        demo = Demo.from_bytes(attempt.data, "test")
        assert attempt.choices["faces"] in ("wide", "narrow")
        assert demo.metadata.extra["expert_choices"] == attempt.choices
        assert demo.metadata.source == "expert"
    finally:
        close_envs()


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

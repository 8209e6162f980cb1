"""The human-likeness figures on synthetic wrist paths whose answers are known."""

from __future__ import annotations

import numpy as np
import pytest

from bigym.experts.motion import minimum_jerk_profile
from bigym.experts.stats import Trajectory, active_hands, measure, plan_key

RATE = 100.0


def _trajectory(left: np.ndarray, right: np.ndarray, plan: str = "") -> Trajectory:
    wrists = np.stack([left, right], axis=1)
    return Trajectory(wrists, wrists.copy(), RATE, len(left) / RATE, plan=plan)


def _reach(progress: np.ndarray, bend: float = 0.0) -> np.ndarray:
    """0.4 m along x with ``progress`` in [0, 1], bowed sideways by ``bend`` metres."""
    x = 0.4 * progress
    y = bend * np.sin(np.pi * progress)
    return np.stack([x, y, np.zeros_like(x)], axis=1)


def test_straight_constant_speed_and_curved_bell_shaped_movements():
    tau = np.linspace(0.0, 1.0, 101)
    still = np.zeros((101, 3))
    plain = _trajectory(_reach(tau), still)
    human = _trajectory(_reach(minimum_jerk_profile(tau), bend=0.06), still)
    plain_figures, human_figures = measure([plain], "plain"), measure([human], "human")
    assert plain_figures.straightness == pytest.approx(1.0, abs=1e-3)
    assert human_figures.straightness > 1.03  # bowed: longer than the straight distance
    # a minimum-jerk movement has the bell-shaped speed profile; a constant speed has not
    assert human_figures.bell_correlation > 0.95
    assert plain_figures.bell_correlation < human_figures.bell_correlation - 0.3
    assert human_figures.speed_peaks == 1.0


def test_hand_split_and_duration_spread():
    tau = np.linspace(0.0, 1.0, 81)
    still = np.zeros((81, 3))
    left = _trajectory(_reach(tau), still)
    right = _trajectory(still, _reach(tau))
    both = _trajectory(_reach(tau), _reach(tau))
    assert [active_hands(t) for t in (left, right, both)] == ["left", "right", "both"]
    figures = measure([left, right, both, left], "set")
    assert figures.hand_split == {"left": 0.5, "right": 0.25, "both": 0.25}
    assert figures.duration_std == 0.0  # every trajectory lasts 0.81 s


def test_plans_count_the_distinct_discrete_choices():
    tau = np.linspace(0.0, 1.0, 81)
    still = np.zeros((81, 3))
    keys = [
        plan_key({"hands": ["door:left"], "order": ["door"], "stance": 0.3}),
        plan_key({"order": ["door"], "hands": ["door:left"], "stance": 0.7}),  # same plan
        plan_key({"hands": ["door:right"], "order": ["door"]}),
        plan_key({"hands": ["door:left"], "order": ["door"], "burner": "hob_site_2"}),  # another target
    ]
    assert keys[0] == keys[1] != keys[2] != keys[3] != keys[0]
    trajectories = [_trajectory(_reach(tau), still, plan=key) for key in keys]
    figures = measure(trajectories, "set")
    assert figures.plans == 3
    assert figures.top_plan_share == pytest.approx(2 / 4)

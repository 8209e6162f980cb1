"""Reach demonstrators: bring a wrist (or both) to the target sphere(s).

Multi-modality: in ``ReachTargetMultiModal`` the hand is chosen like a person would,
mostly the one on the target's side but with a soft boundary, so that over the task's
symmetric target region each hand is used about half of the time. The base steps
forward only when the target is beyond a comfortable reach.
"""

from __future__ import annotations

import numpy as np

from bigym.experts.expert import SIDE_INDEX, SIDE_NAMES, Expert, Script
from bigym.experts.geometry import yaw_matrix

#: comfortable forward reach of the wrist from the pelvis (m); beyond it the robot steps
COMFORT_REACH = 0.5
#: softness (m) of the hand choice around the robot's mid-plane
HAND_CHOICE_SOFTNESS = 0.12


class ReachExpert(Expert):
    """Reach the target(s) of the reach tasks with the wrist."""

    tasks = ("ReachTargetSingle", "ReachTargetMultiModal", "ReachTargetDual")

    def plan(self) -> Script:
        env = self.env
        base = self.base_pose()
        to_local = yaw_matrix(base[3]).T
        goals: list[tuple[int, np.ndarray]] = []
        for target, hand in zip(env.target_positions.copy(), env.target_hands):
            local = to_local @ (target - np.array([base[0], base[1], 0.0]))
            side = self.hand_on_side(local[1], HAND_CHOICE_SOFTNESS) if hand == "any" else SIDE_INDEX[hand]
            goals.append((side, target))
        self.choices["hands"] = [SIDE_NAMES[s] for s, _ in goals]
        yield from self.wait(self.human.reaction())
        # Step forward (and a little sideways) only when the target is far.
        locals_ = [to_local @ (t - np.array([base[0], base[1], 0.0])) for _, t in goals]
        reach = max(l[0] for l in locals_)
        stance = base.copy()
        step = max(0.0, reach - COMFORT_REACH - abs(self.human.jitter(0.05)))
        lateral = float(np.mean([l[1] for l in locals_])) * 0.3 if len(goals) == 1 else 0.0
        low = min(t[2] for _, t in goals)
        crouch = max(0.0, 0.95 - low) * 0.5
        stance[:2] += yaw_matrix(base[3])[:2, :2] @ np.array([step, lateral])
        stance[2] = min(stance[2], stance[2] - crouch + self.human.jitter(0.01))
        stance[3] += self.human.jitter(self.style.stance_yaw_spread * 0.5)
        ends = []
        if step > 0.02 or crouch > 0.02:
            ends.append(self.move_base(stance, start=self.time + abs(self.human.jitter(0.08))))
        for order, (side, target) in enumerate(goals):
            start = self.time + (abs(self.human.jitter(0.12)) if order else 0.0)
            aim = target + self.human.jitter(0.015, 3)
            ends.append(
                self.move_hand(
                    side,
                    aim,
                    frame="wrist",
                    lift=abs(self.human.jitter(0.03)),
                    precision=0.05,
                    correct=True,
                    start=start,
                )
            )
        yield from self.until(max(ends))
        while True:  # stay; the env ends the episode on success
            yield

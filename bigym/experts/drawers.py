"""Drawers: open one by its handle, close one with a push, as a person does.

A drawer opens by its handle (fingers round the bar, pull, the body stepping back with
it) and closes with a push of the fist on its handle bar (a hand on the front face
below the bar would have to reach under a counter's overhang for a top drawer). A
drawer that stopped short gets another go.
"""

from __future__ import annotations

import numpy as np

from bigym.experts.doors import DONE_MARGIN, OVERSHOOT
from bigym.experts.expert import FIRM, Expert, Script


class DrawerSkills(Expert):
    """An :class:`Expert` that opens and closes the drawers of furniture props."""

    def drawer(
        self,
        side: int,
        prop: str,
        key: str,
        goal: float,
        attempts: int = 3,
        height: float = 0.27,
        relax: bool = True,
    ) -> Script:
        """Open drawer ``key`` of ``prop`` (``goal`` 1) by its handle, or close it (``goal``
        0) by pushing its handle bar with a fist, with the hand ``side``; if it stopped
        short, once more (a correction). The pelvis stands about ``height`` above the handle
        (the IK crouches further by itself while the other arm is idle; a hand that holds
        something keeps it from doing so, so such a crouch must be planned). With ``relax``
        the arm then goes back to its idle posture (its hand passes in front of the body,
        through an open drawer's space); without, the hand stays where it let go."""
        for attempt in range(attempts):
            state = self.joint_state(prop, key)
            if abs(state - goal) < DONE_MARGIN:
                return
            if attempt:
                self.note(f"correct {key} at {state:.2f}")
            centre, bar, approach = self.handle_frame(prop, f"{key}_handle", "y")
            if goal > 0.5:
                stance = self.stance(side, centre, approach, height=height)
                tilt = float(np.clip((stance[2] - 0.27 - centre[2]) * 2.0, 0.0, 0.6)) + self.human.jitter(
                    self.style.approach_spread
                )
                yield from self.grasp_bar(
                    side, centre, bar, approach, tilt=tilt, offset=self.human.jitter(0.02), base_goal=stance
                )
                yield from self.hesitate()
                yield from self.drag([side], prop, key, 1.0 + OVERSHOOT, base_follow=0.85, orientation_cost=FIRM * 0.5)
                away = None
            else:
                point = centre - approach * 0.008 + bar * self.human.jitter(0.03)
                stance = self.stance(side, point, approach, height=height)
                yield from self.press(side, point, approach, across=bar, base_goal=stance)
                yield from self.drag([side], prop, key, -OVERSHOOT, base_follow=0.85, orientation_cost=FIRM * 0.3)
                away = -approach
            done = abs(self.joint_state(prop, key) - goal) < DONE_MARGIN
            # out and up, clear of the open drawer's front, before anything else moves
            yield from self.release(side, back=0.12, up=0.06, away=away)
            if done and relax:
                relaxed = self.relax_arm(side)
                yield from self.until(self.time + 0.6 * (relaxed - self.time))


__all__ = ["DrawerSkills"]

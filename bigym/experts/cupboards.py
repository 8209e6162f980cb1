"""Kitchen-counter demonstrators: drawers and cupboard doors (scene counter_base_wall_3x1).

How a person does it, and so how these scripts do it:

* a drawer is opened and closed as :mod:`bigym.experts.drawers` does it;
* a hinged door is opened and closed as :mod:`bigym.experts.doors` does it.

Choices drawn per demo: the hand for each drawer or door (for the wall cupboard also
both hands at once, one per door), the order of the jobs (drawers are opened from the
bottom up and closed from the top down, so that an open drawer never hangs over the
hand; groups of jobs come in a random order), where the base stands, how far a door is
pulled before the hand changes grip.
"""

from __future__ import annotations

from typing import ClassVar

from bigym.experts.doors import DONE_MARGIN, DoorSkills
from bigym.experts.drawers import DrawerSkills
from bigym.experts.expert import LEFT, RIGHT, SIDE_NAMES, Script, together

DRAWERS_PROP = "cabinet_drawers"
DRAWER_ORDER = ("drawer_big_1", "drawer_small_3", "drawer_small_4")  # bottom to top
WALL_PROP = "wall_cabinet"
#: how close the pelvis may come to the counter's front (m): the feet stay in front of it
BASE_CLEARANCE = 0.3
#: how often a base-cabinet door is pushed shut with the hand away from its free edge
FAR_HAND_PROBABILITY = 0.15


class CupboardExpert(DoorSkills, DrawerSkills):
    """Opens and closes the drawers and doors of the counter scene."""

    tasks = (
        "DrawerTopOpen",
        "DrawerTopClose",
        "DrawersOpenAll",
        "DrawersCloseAll",
        "WallCupboardOpen",
        "WallCupboardClose",
        "CupboardsOpenAll",
        "CupboardsCloseAll",
    )
    pace: ClassVar[dict[str, float]] = {
        "DrawersCloseAll": 1.3,
        "WallCupboardOpen": 1.5,
        "WallCupboardClose": 1.3,
        "CupboardsOpenAll": 1.3,
        "CupboardsCloseAll": 1.2,
    }

    def plan(self) -> Script:
        env = self.env
        goal = float(env.goal)
        opening = goal > 0.5
        groups: list[list[tuple[str, str]]] = []
        for prop, keys in env.targets:
            if prop == DRAWERS_PROP:
                ordered = sorted(keys, key=DRAWER_ORDER.index, reverse=not opening)
                groups.append([(prop, key) for key in ordered])
            elif prop == WALL_PROP:
                groups.append([(prop, key) for key in keys])
            else:
                groups.extend([[(prop, key)] for key in keys])
        # doors in a random order; the drawers last when opening (an open drawer is in the
        # way of everything), first when closing
        drawers = [g for g in groups if g[0][0] == DRAWERS_PROP]
        doors = [g for g in groups if g[0][0] != DRAWERS_PROP]
        doors = [doors[i] for i in self.rng.permutation(len(doors))]
        groups = doors + drawers if opening else drawers + doors
        self.choices["order"] = [f"{p}/{k}" for g in groups for p, k in g]
        # stand in front of the counter, never inside it (its front is at the drawers' fronts)
        front = self.site(DRAWERS_PROP, "drawer_big_1_handle") + self.module_facing(DRAWERS_PROP) * 0.035
        self.keep_base_behind(front, self.module_facing(DRAWERS_PROP), BASE_CLEARANCE)
        yield from self.wait(self.human.reaction())
        for side in (LEFT, RIGHT):
            self.relax_arm(side, start=self.time + abs(self.human.jitter(0.15)), joint_space=True)
        for group in groups:
            prop = group[0][0]
            if prop == DRAWERS_PROP:
                for _, key in group:
                    yield from self.drawer(self.pick_hand(key), DRAWERS_PROP, key, goal)
            elif prop == WALL_PROP:
                yield from self.wall_doors([key for _, key in group], goal)
            else:
                key = group[0][1]
                # the hand on the door's free-edge side; closing, sometimes the other one
                side = self.door_side(prop, key)
                if not opening and self.rng.random() < FAR_HAND_PROBABILITY:
                    side = 1 - side
                self._note_hand(f"{prop}/{key}", side)
                yield from self.door(side, prop, key, goal)
            yield from self.hesitate()
        while True:
            yield

    # ------------------------------------------------------------------ helpers
    def _note_hand(self, job: str, side: int | str) -> None:
        name = side if isinstance(side, str) else SIDE_NAMES[side]
        self.choices.setdefault("hands", []).append(f"{job}:{name}")

    def pick_hand(self, job: str) -> int:
        side = LEFT if self.rng.random() < 0.5 else RIGHT
        self._note_hand(job, side)
        return side

    def wall_doors(
        self,
        keys: list[str],
        goal: float,
        margin: float = DONE_MARGIN,
        both_hands: float | None = None,
        second_after: tuple[float, float] = (1.6, 2.2),
        relax: bool = True,
    ) -> Script:
        """Both wall-cupboard doors: one hand each at once (with probability ``both_hands``;
        by default 0.4 opening, 0.5 closing), the second hand starting ``second_after`` (a
        range, s) after the first when opening; or one after the other; ``margin`` and
        ``relax`` as :meth:`door`'s."""
        if both_hands is None:
            both_hands = 0.4 if goal > 0.5 else 0.5
        both = len(keys) == 2 and self.rng.random() < both_hands
        if both:
            self._note_hand(f"{WALL_PROP}/both", "both")
            sides = {key: self.door_side(WALL_PROP, key) for key in keys}
            # the base stands centred between the doors; each hand works its own door
            centre = 0.5 * (self.site(WALL_PROP, f"{keys[0]}_handle") + self.site(WALL_PROP, f"{keys[1]}_handle"))
            _, _, approach = self.handle_frame(WALL_PROP, f"{keys[0]}_handle", "z")
            stance = self.stance(None, centre, approach, distance=0.66, height=-0.45)
            yield from self.until(self.move_base(stance))
            # opening, the second hand waits until the first door has swung aside (the two
            # handles are side by side, too close for two grippers at once)
            first = int(self.rng.integers(2))
            delay = float(self.rng.uniform(*second_after)) if goal > 0.5 else abs(self.human.jitter(0.15))
            scripts = [
                self.door(sides[key], WALL_PROP, key, goal, base=False, margin=margin, relax=relax)
                if i == first
                else self.after(
                    delay, self.door(sides[key], WALL_PROP, key, goal, base=False, margin=margin, relax=relax)
                )
                for i, key in enumerate(keys)
            ]
            yield from together(*scripts)
        else:
            order = list(keys) if self.rng.random() < 0.5 else list(reversed(keys))
            for key in order:
                # mostly the hand on the door's hinge side: the arm then never crosses
                # in front of the other, maybe open, door
                side = self.door_side(WALL_PROP, key)
                self._note_hand(f"{WALL_PROP}/{key}", side)
                yield from self.door(side, WALL_PROP, key, goal, margin=margin, relax=relax)
                yield from self.hesitate()

"""Scripted, human-like expert demonstrators for the BiGym tasks.

``make_expert(env, seed, style)`` returns a callable ``expert(obs) -> action`` for the
env's task. The env must use ``JointPositionActionMode(floating_base=True,
absolute=True)``; the demos are recorded at 500 Hz (any control rate works). An expert
reads the privileged simulator state, plans hand movements in task space as
minimum-jerk paths through randomised via-points (:mod:`bigym.experts.motion`), and
turns them into base and arm joint targets with a whole-body mink IK
(:mod:`bigym.experts.ik`). Every human-like variability is a knob of
:class:`HumanStyle` with a seeded draw; :meth:`HumanStyle.plain` turns them all off
(straight lines at constant speed) for comparisons.

Modules: :mod:`~bigym.experts.expert` (the base class, skills, actions),
:mod:`~bigym.experts.grasping` (pick, carry and place skills),
:mod:`~bigym.experts.doors` (open and close hinged doors),
:mod:`~bigym.experts.drawers` (open and close drawers),
:mod:`~bigym.experts.reach`, :mod:`~bigym.experts.cupboards`,
:mod:`~bigym.experts.dishwasher`, :mod:`~bigym.experts.stack_blocks`,
:mod:`~bigym.experts.move_plates`, :mod:`~bigym.experts.cookware`,
:mod:`~bigym.experts.boxes`, :mod:`~bigym.experts.store_box`,
:mod:`~bigym.experts.flip_cup`, :mod:`~bigym.experts.flip_cutlery`,
:mod:`~bigym.experts.groceries`, :mod:`~bigym.experts.groceries_upper`,
:mod:`~bigym.experts.sandwich`,
:mod:`~bigym.experts.dishwasher_cutlery`,
:mod:`~bigym.experts.dishwasher_load_cutlery`,
:mod:`~bigym.experts.dishwasher_unload_cutlery_long`,
:mod:`~bigym.experts.dishwasher_plates`,
:mod:`~bigym.experts.dishwasher_load_plates`,
:mod:`~bigym.experts.dishwasher_load_cups`,
:mod:`~bigym.experts.dishwasher_unload_cups`, :mod:`~bigym.experts.put_cups`,
:mod:`~bigym.experts.take_cups` (the task scripts),
:mod:`~bigym.experts.generate` (``generate_demos``: record, replay from file, keep
verified successes),
:mod:`~bigym.experts.incidents` (drops and objects pushed into surfaces reject a demo),
:mod:`~bigym.experts.stats` (``demo_stats``: diversity and human-likeness figures,
wrist-path plot).
"""

from __future__ import annotations

import importlib

from bigym.experts.motion import Human, HumanStyle

_CUPBOARDS = (
    "DrawerTopOpen",
    "DrawerTopClose",
    "DrawersOpenAll",
    "DrawersCloseAll",
    "WallCupboardOpen",
    "WallCupboardClose",
    "CupboardsOpenAll",
    "CupboardsCloseAll",
)
_DISHWASHER = ("DishwasherOpen", "DishwasherClose", "DishwasherOpenTrays", "DishwasherCloseTrays")

#: task class name -> "module:Expert class"
EXPERTS: dict[str, str] = {
    "ReachTargetSingle": "bigym.experts.reach:ReachExpert",
    "ReachTargetMultiModal": "bigym.experts.reach:ReachExpert",
    "ReachTargetDual": "bigym.experts.reach:ReachExpert",
    **{task: "bigym.experts.cupboards:CupboardExpert" for task in _CUPBOARDS},
    **{task: "bigym.experts.dishwasher:DishwasherExpert" for task in _DISHWASHER},
    "StackBlocks": "bigym.experts.stack_blocks:StackBlocksExpert",
    "MovePlate": "bigym.experts.move_plates:MovePlateExpert",
    "MoveTwoPlates": "bigym.experts.move_plates:MovePlateExpert",
    "SaucepanToHob": "bigym.experts.cookware:CookwareExpert",
    "StoreKitchenware": "bigym.experts.cookware:CookwareExpert",
    "PickBox": "bigym.experts.boxes:BoxExpert",
    "StoreBox": "bigym.experts.store_box:StoreBoxExpert",
    "FlipCup": "bigym.experts.flip_cup:FlipCupExpert",
    "FlipCutlery": "bigym.experts.flip_cutlery:FlipCutleryExpert",
    "StoreGroceriesLower": "bigym.experts.groceries:GroceriesExpert",
    "StoreGroceriesUpper": "bigym.experts.groceries_upper:UpperGroceriesExpert",
    "DishwasherUnloadCutlery": "bigym.experts.dishwasher_cutlery:CutleryUnloadExpert",
    "DishwasherLoadCutlery": "bigym.experts.dishwasher_load_cutlery:CutleryLoadExpert",
    "DishwasherUnloadCutleryLong": "bigym.experts.dishwasher_unload_cutlery_long:CutleryDrawerExpert",
    "DishwasherUnloadPlates": "bigym.experts.dishwasher_plates:PlateUnloadExpert",
    "DishwasherLoadPlates": "bigym.experts.dishwasher_load_plates:PlateLoadExpert",
    "DishwasherLoadCups": "bigym.experts.dishwasher_load_cups:CupLoadExpert",
    "DishwasherUnloadCups": "bigym.experts.dishwasher_unload_cups:CupUnloadExpert",
    "PutCups": "bigym.experts.put_cups:PutCupsExpert",
    "TakeCups": "bigym.experts.take_cups:TakeCupsExpert",
    "SandwichRemove": "bigym.experts.sandwich:SandwichRemoveExpert",
    "SandwichToast": "bigym.experts.sandwich_toast:SandwichToastExpert",
    "SandwichFlip": "bigym.experts.sandwich_flip:SandwichFlipExpert",
    "DishwasherUnloadPlatesLong": "bigym.experts.dishwasher_unload_plates_long:PlateCabinetExpert",
    "DishwasherUnloadCupsLong": "bigym.experts.dishwasher_unload_cups_long:MugCabinetExpert",
}


def expert_class(task: str):
    """The expert class of a task (class name, e.g. ``"DrawerTopOpen"``)."""
    try:
        module, name = EXPERTS[task].split(":")
    except KeyError:
        raise KeyError(f"no expert for task {task!r}; experts exist for {', '.join(EXPERTS)}") from None
    return getattr(importlib.import_module(module), name)


def make_expert(env, seed: int | None = None, style: HumanStyle | None = None, **kwargs):
    """The expert for ``env``'s task: a callable ``expert(obs) -> action``.

    ``seed`` seeds every draw of the demonstrator (hand, order, stance, timing, paths,
    tremor); ``style`` sets how much of each there is (default :class:`HumanStyle`).
    The expert restarts by itself on the first step after ``env.reset``.
    """
    return expert_class(type(env.unwrapped).__name__)(env, seed=seed, style=style, **kwargs)


def generate_demos(*args, **kwargs):
    """See :func:`bigym.experts.generate.generate_demos`."""
    from bigym.experts.generate import generate_demos as _generate

    return _generate(*args, **kwargs)


def demo_stats(*args, **kwargs):
    """See :func:`bigym.experts.stats.demo_stats`."""
    from bigym.experts.stats import demo_stats as _stats

    return _stats(*args, **kwargs)


__all__ = ["EXPERTS", "Human", "HumanStyle", "demo_stats", "expert_class", "generate_demos", "make_expert"]

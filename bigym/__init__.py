"""BiGym: demo-driven mobile bi-manual manipulation with a Unitree H1 in MuJoCo."""

from __future__ import annotations

import gymnasium as gym

# Installs the fork handler that keeps offscreen rendering working in forked workers (see
# bigym.gl_context): it must be in place before the first fork, whatever else is imported.
import bigym.gl_context  # noqa: F401

__version__ = "0.3.0"

# Registered ids: bigym/<TaskName>-v0 -> "module:Class".
TASKS: dict[str, str] = {
    "ReachTargetSingle": "bigym.envs.reach_target:ReachTargetSingle",
    "ReachTargetMultiModal": "bigym.envs.reach_target:ReachTargetMultiModal",
    "ReachTargetDual": "bigym.envs.reach_target:ReachTargetDual",
    "DishwasherOpen": "bigym.envs.dishwasher:DishwasherOpen",
    "DishwasherClose": "bigym.envs.dishwasher:DishwasherClose",
    "DishwasherOpenTrays": "bigym.envs.dishwasher:DishwasherOpenTrays",
    "DishwasherCloseTrays": "bigym.envs.dishwasher:DishwasherCloseTrays",
    "DishwasherLoadPlates": "bigym.envs.dishwasher_plates:DishwasherLoadPlates",
    "DishwasherUnloadPlates": "bigym.envs.dishwasher_plates:DishwasherUnloadPlates",
    "DishwasherUnloadPlatesLong": "bigym.envs.dishwasher_plates:DishwasherUnloadPlatesLong",
    "DishwasherLoadCups": "bigym.envs.dishwasher_cups:DishwasherLoadCups",
    "DishwasherUnloadCups": "bigym.envs.dishwasher_cups:DishwasherUnloadCups",
    "DishwasherUnloadCupsLong": "bigym.envs.dishwasher_cups:DishwasherUnloadCupsLong",
    "DishwasherLoadCutlery": "bigym.envs.dishwasher_cutlery:DishwasherLoadCutlery",
    "DishwasherUnloadCutlery": "bigym.envs.dishwasher_cutlery:DishwasherUnloadCutlery",
    "DishwasherUnloadCutleryLong": "bigym.envs.dishwasher_cutlery:DishwasherUnloadCutleryLong",
    "DrawerTopOpen": "bigym.envs.cupboards:DrawerTopOpen",
    "DrawerTopClose": "bigym.envs.cupboards:DrawerTopClose",
    "DrawersOpenAll": "bigym.envs.cupboards:DrawersOpenAll",
    "DrawersCloseAll": "bigym.envs.cupboards:DrawersCloseAll",
    "WallCupboardOpen": "bigym.envs.cupboards:WallCupboardOpen",
    "WallCupboardClose": "bigym.envs.cupboards:WallCupboardClose",
    "CupboardsOpenAll": "bigym.envs.cupboards:CupboardsOpenAll",
    "CupboardsCloseAll": "bigym.envs.cupboards:CupboardsCloseAll",
    "StackBlocks": "bigym.envs.manipulation:StackBlocks",
    "MovePlate": "bigym.envs.move_plates:MovePlate",
    "MoveTwoPlates": "bigym.envs.move_plates:MoveTwoPlates",
    "FlipCup": "bigym.envs.manipulation:FlipCup",
    "FlipCutlery": "bigym.envs.manipulation:FlipCutlery",
    "SandwichToast": "bigym.envs.sandwich:SandwichToast",
    "SandwichFlip": "bigym.envs.sandwich:SandwichFlip",
    "SandwichRemove": "bigym.envs.sandwich:SandwichRemove",
    "StoreGroceriesLower": "bigym.envs.groceries:StoreGroceriesLower",
    "StoreGroceriesUpper": "bigym.envs.groceries:StoreGroceriesUpper",
    "PutCups": "bigym.envs.pick_and_place:PutCups",
    "TakeCups": "bigym.envs.pick_and_place:TakeCups",
    "PickBox": "bigym.envs.pick_and_place:PickBox",
    "StoreBox": "bigym.envs.pick_and_place:StoreBox",
    "SaucepanToHob": "bigym.envs.pick_and_place:SaucepanToHob",
    "StoreKitchenware": "bigym.envs.pick_and_place:StoreKitchenware",
}

# Other names the paper and the original code use for the same tasks.
ALIASES: dict[str, str] = {"ReachTarget": "ReachTargetMultiModal", "reach_target": "ReachTargetMultiModal"}


def _register_all() -> None:
    for name, entry_point in TASKS.items():
        env_id = f"bigym/{name}-v0"
        if env_id not in gym.registry:
            gym.register(id=env_id, entry_point=entry_point, disable_env_checker=True)


_register_all()

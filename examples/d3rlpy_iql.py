"""Offline RL from bigym's demos with d3rlpy: IQL trained on a task's demos, evaluated by ``bigym eval``.

Needs ``pip install "bigym[rl]"`` (d3rlpy). Train on 50 demos of DrawerTopClose, observed
with proprioception and the task's object state at the protocol's 50 Hz::

    python examples/d3rlpy_iql.py DrawerTopClose --steps 20000 --out iql-DrawerTopClose

then evaluate the model on the official seeds, like any other policy::

    BIGYM_IQL_MODEL=iql-DrawerTopClose bigym eval drawer_top_close --privileged \\
        --policy examples/d3rlpy_iql.py:policy

The demos become d3rlpy's ``MDPDataset`` through :mod:`bigym.demonstrations.transitions`:
flat observations (d3rlpy rejects Dict observations) and actions scaled to [-1, 1] (its
policies are tanh-bounded), the floating base as servo targets (a policy that outputs the
env's per-step base moves adds up its errors and walks away); the same ``FlatSpaces``, saved
beside the model, map the env's observations in and the model's actions back out at
evaluation time.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import numpy as np

from bigym.demonstrations import DemoStore, Metadata
from bigym.demonstrations.player import resolve_task
from bigym.demonstrations.transitions import FlatSpaces, transitions
from bigym.evaluation.protocol import CONTROL_FREQUENCY, official_action_mode
from bigym.observations import ObservationConfig

MODEL_FILE = "model.d3"
SPACES_FILE = "spaces.json"


def make_env(task: str):
    """The env the demos are replayed in: the protocol's action mode and rate, state observations."""
    return resolve_task(task)(
        action_mode=official_action_mode(),
        observation_config=ObservationConfig(privileged_information=True),
        control_frequency=CONTROL_FREQUENCY,
    )


def train(task: str, out: Path, steps: int, demos: int = 50, store=None, seed: int = 0) -> list:
    """Fit IQL on ``demos`` demos of ``task``; write ``out/model.d3`` and ``out/spaces.json``.

    Returns d3rlpy's training history: ``(epoch, metrics)`` per epoch of 1000 steps.
    """
    import d3rlpy

    env = make_env(task)
    try:
        store = store if isinstance(store, DemoStore) else DemoStore(store)
        replayed = store.get_demos(Metadata.from_env(env), amount=demos, progress=True)
        data = transitions(replayed, env)
    finally:
        env.close()
    d3rlpy.seed(seed)
    iql = d3rlpy.algos.IQLConfig(
        observation_scaler=d3rlpy.preprocessing.StandardObservationScaler(),
        batch_size=256,
    ).create(device="cpu")
    # d3rlpy trains n_steps // n_steps_per_epoch epochs: with its default of 10,000 steps per
    # epoch, any n_steps below that trains nothing at all.
    history = iql.fit(
        data.to_d3rlpy(),
        n_steps=steps,
        n_steps_per_epoch=min(steps, 1000),
        logger_adapter=d3rlpy.logging.NoopAdapterFactory(),
        show_progress=True,
    )
    out.mkdir(parents=True, exist_ok=True)
    iql.save(str(out / MODEL_FILE))
    data.spaces.save(out / SPACES_FILE)
    return history


class IQLPolicy:
    """A saved d3rlpy model acting in a bigym env through the spaces it was trained in."""

    def __init__(self, env, folder: Path) -> None:
        import d3rlpy

        self.spaces = FlatSpaces.load(folder / SPACES_FILE)
        here = FlatSpaces.from_env(env)
        if here.keys != self.spaces.keys or here.sizes != self.spaces.sizes:
            raise ValueError(
                f"the model observes {', '.join(self.spaces.keys)}, this env gives {', '.join(here.keys)} "
                "(evaluate with --privileged)"
            )
        self.model = d3rlpy.load_learnable(str(folder / MODEL_FILE), device="cpu")

    def reset(self, seed: int) -> None:
        pass  # the actor is deterministic and keeps no history

    def __call__(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        scaled = self.model.predict(self.spaces.flatten(obs)[None])[0]
        return self.spaces.env_action(scaled, obs)


def policy(env) -> IQLPolicy:
    """Factory for ``bigym eval --policy examples/d3rlpy_iql.py:policy`` (model in ``$BIGYM_IQL_MODEL``)."""
    folder = Path(os.environ.get("BIGYM_IQL_MODEL", f"iql-{env.unwrapped.task_name}"))
    if not (folder / MODEL_FILE).is_file():
        raise FileNotFoundError(
            f"no IQL model in {folder}: train one with examples/d3rlpy_iql.py, and point BIGYM_IQL_MODEL at its folder"
        )
    return IQLPolicy(env, folder)


def main() -> None:
    parser = argparse.ArgumentParser(description="Train IQL (d3rlpy) on a task's demos.")
    parser.add_argument("task", help="task class name, e.g. DrawerTopClose")
    parser.add_argument("--steps", type=int, default=20_000, help="gradient steps")
    parser.add_argument("--demos", type=int, default=50)
    parser.add_argument("--store", help="demo store (default: the local store)")
    parser.add_argument("--out", type=Path, help="model folder (default: iql-TASK)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    out = args.out or Path(f"iql-{args.task}")
    train(args.task, out, args.steps, args.demos, args.store, args.seed)
    print(
        f"saved {out}; evaluate: BIGYM_IQL_MODEL={out} bigym eval {args.task} --privileged "
        f"--policy examples/d3rlpy_iql.py:policy"
    )


if __name__ == "__main__":
    main()

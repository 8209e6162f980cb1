"""Train a baseline on a task's demos: seeded, checkpointed, resumable to the same weights.

The demos are replayed into the chosen observations at the protocol's control rate
(cached by the store), turned into (observation, action chunk) samples, and the model is
fitted with AdamW. A run writes its checkpoint every ``checkpoint_every`` steps; started
again with the same arguments it resumes from there and ends with the weights an
uninterrupted run would have had.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any, Callable

import torch

import bigym
from bigym.action_modes import JointPositionActionMode
from bigym.baselines.checkpoint import Checkpoint
from bigym.baselines.data import ChunkDataset
from bigym.baselines.ema import WeightAverage
from bigym.baselines.methods import config_dict, make_config, make_model
from bigym.observations import CameraConfig, ObservationConfig, is_image_key

LOSS_EVERY = 50  # steps between the losses a checkpoint keeps


def observation_config(
    cameras: tuple[str, ...] = (), depth: bool = False, privileged: bool = True
) -> ObservationConfig:
    """Proprioception, optionally the task's object state and robot cameras at 84x84."""
    return ObservationConfig(
        cameras=tuple(CameraConfig(name, rgb=True, depth=depth, resolution=(84, 84)) for name in cameras),
        privileged_information=privileged,
    )


def load_demos(
    task: str, config: ObservationConfig, amount: int, frequency: float, store, workers: int, progress,
    episode_only: bool = True,
):  # fmt: skip
    """``amount`` demos of ``task`` replayed into ``config`` at ``frequency`` (absolute actions);
    ``episode_only=False``: with the recorded steps after each episode's end."""
    from bigym.demonstrations import DemoStore, Metadata
    from bigym.demonstrations.player import resolve_task

    env = resolve_task(task)(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True),
        observation_config=config,
        control_frequency=frequency,
    )
    try:
        metadata = Metadata.from_env(env)
    finally:
        env.close()
    store = store if store is not None and not isinstance(store, (str, Path)) else DemoStore(store)
    demos = store.get_demos(
        metadata, amount=amount, frequency=frequency, workers=workers, progress=progress, episode_only=episode_only
    )
    return demos, metadata


def train(
    method: str,
    task: str,
    out: str | Path,
    *,
    demos: int = 50,
    cameras: tuple[str, ...] = (),
    depth: bool = False,
    privileged: bool = True,
    frequency: float = 50.0,
    store=None,
    seed: int = 0,
    settings: dict[str, Any] | None = None,
    checkpoint_every: int = 1000,
    workers: int = 1,
    progress: Callable[[int, int, float], None] | None = None,
    replay_progress: bool = False,
    device: str = "auto",
) -> Checkpoint:
    """Train ``method`` (bc, act, dp) on ``demos`` demos of ``task`` and write ``out``.

    ``settings`` override the method's config (e.g. ``{"steps": 5000}``). ``progress`` is
    called as ``progress(step, steps, loss)`` after every step. ``device``: ``"auto"`` (CUDA
    when available, else the CPU), ``"cpu"``, ``"cuda"``, ... Random draws come from a seeded
    CPU generator on every device; a resumed run ends with the weights of an uninterrupted
    one on the CPU (CUDA kernels need not be bit-reproducible). Returns the last checkpoint.
    """
    device = resolve_device(device)
    from bigym.demonstrations.player import resolve_task

    task = resolve_task(task).__name__
    config = make_config(method, settings)
    observations = observation_config(tuple(cameras), depth, privileged)
    replayed, metadata = load_demos(
        task, observations, demos, frequency, store, workers, replay_progress, episode_only=not config.tail
    )
    image_keys = sorted(k for k in replayed[0].observations if is_image_key(k))
    out = Path(out)
    previous = Checkpoint.load(out) if out.exists() else None
    dataset = ChunkDataset(
        replayed, config.chunk, image_keys, previous.make_normalizer() if previous is not None else None,
        hold_end=config.hold_end, modes=getattr(config, "modes", 0), tail=config.tail,
    )  # fmt: skip
    image_shapes = {k: list(dataset.images[k].shape[1:]) for k in image_keys}
    for key in image_keys:
        if key.startswith("depth_"):
            image_shapes[key] = [1, *image_shapes[key]]
    checkpoint = Checkpoint(
        method=method,
        task=task,
        config=config_dict(config),
        action_mode=metadata.action_mode,
        frequency=float(metadata.frequency),
        observation_config=observations.to_dict(),
        state_keys=dataset.state_keys,
        image_shapes=image_shapes,
        state_dim=dataset.state_dim,
        action_dim=dataset.action_dim,
        base_indices=dataset.base_indices,
        normalizer=dataset.normalizer.to_dict(),
        demos=[d.uuid for d in replayed],
        demo_modes=dataset.demo_modes.tolist(),
        seed=seed,
        bigym_version=bigym.__version__,
    )
    torch.manual_seed(seed)
    generator = torch.Generator().manual_seed(seed)
    model = make_model(
        method, config, dataset.state_dim, dataset.action_dim, {k: tuple(v) for k, v in image_shapes.items()}
    ).to(device)
    optimizer = torch.optim.AdamW(model.parameters(), lr=config.lr, weight_decay=config.weight_decay)
    average = WeightAverage(model, config.ema) if config.ema != 0 else None
    if previous is not None:
        _check_resumable(previous, checkpoint, out)
        model.load_state_dict(previous.model)
        optimizer.load_state_dict(previous.optimizer)
        if average is not None:
            average.load_state_dict(previous.ema)
        generator.set_state(previous.rng["batches"])
        torch.set_rng_state(previous.rng["torch"])
        checkpoint.step, checkpoint.losses, checkpoint.loss_terms, checkpoint.train_seconds = (
            previous.step,
            previous.losses,
            previous.loss_terms,
            previous.train_seconds,
        )
    model.train()
    started, recent, recent_terms = time.perf_counter(), [], []
    for step in range(checkpoint.step, config.steps):
        batch = {k: v.to(device) for k, v in dataset.batch(config.batch_size, generator, config.state_noise).items()}
        loss, terms = model.loss(batch, generator)
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        torch.nn.utils.clip_grad_norm_(model.parameters(), 10.0)
        optimizer.step()
        if average is not None:
            average.update(model)
        recent.append(loss.item())
        recent_terms.append(terms)
        done = step + 1
        if done % LOSS_EVERY == 0 or done == config.steps:
            checkpoint.losses.append([done, sum(recent) / len(recent)])
            checkpoint.loss_terms.append({k: sum(t[k] for t in recent_terms) / len(recent_terms) for k in terms})
            recent, recent_terms = [], []
        if progress is not None:
            progress(done, config.steps, loss.item())
        if done % checkpoint_every == 0 or done == config.steps:
            _write(checkpoint, model, optimizer, average, generator, done, started, out)
            started = time.perf_counter()
    if previous is not None and previous.step >= config.steps:
        return previous
    return Checkpoint.load(out)


def resolve_device(name: str) -> torch.device:
    """``"auto"``: CUDA when torch sees a GPU, else the CPU; any other name as torch reads it."""
    if name == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    try:
        device = torch.device(name)
    except RuntimeError as error:
        raise ValueError(f"unknown device {name!r}: give auto, cpu or cuda ({error})") from error
    if device.type == "cuda" and not torch.cuda.is_available():
        raise ValueError(f"device {name!r}: torch sees no CUDA GPU here (use 'cpu' or 'auto')")
    return device


def _write(checkpoint, model, optimizer, average, generator, step, started, out) -> None:
    checkpoint.step = step
    checkpoint.train_seconds += time.perf_counter() - started
    checkpoint.model = model.state_dict()
    checkpoint.optimizer = optimizer.state_dict()
    checkpoint.ema = average.state_dict() if average is not None else {}
    checkpoint.rng = {"batches": generator.get_state(), "torch": torch.get_rng_state()}
    checkpoint.save(out)


def _check_resumable(previous: Checkpoint, new: Checkpoint, path: Path) -> None:
    """Resume only the same run: same method, task, data and settings (the step count may grow)."""
    same = ("method", "task", "action_mode", "frequency", "observation_config", "demos", "seed", "state_dim",
            "base_indices")  # fmt: skip
    differ = [name for name in same if getattr(previous, name) != getattr(new, name)]
    settings = {k: v for k, v in previous.config.items() if k != "steps"}
    if settings != {k: v for k, v in new.config.items() if k != "steps"}:
        differ.append("config")
    if differ:
        raise ValueError(
            f"{path} holds a different training run ({', '.join(differ)} differ): "
            "give another --out, or delete it to start over"
        )

"""Checkpoints: the model with everything needed to run it (normaliser, observation keys,
action mode, rate) and to resume its training bit for bit (optimiser, random states, the
weight average)."""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import torch

from bigym.baselines.data import Normalizer
from bigym.baselines.methods import make_config, make_model, method_classes

FORMAT = "bigym-baseline"
FORMAT_VERSION = 1


@dataclass
class Checkpoint:
    method: str
    task: str
    config: dict
    action_mode: dict
    frequency: float
    observation_config: dict
    state_keys: list[str]
    image_shapes: dict[str, list[int]]
    state_dim: int
    action_dim: int
    base_indices: list[int]  # action entries learned as base targets (see bigym.baselines.data)
    normalizer: dict
    demos: list[str]  # uuids of the training demos
    seed: int
    step: int = 0
    losses: list[list[float]] = field(default_factory=list)  # [step, loss] pairs
    # the loss's parts (ACT: l1 and kl; DP: mse), averaged over the same steps as each losses
    # entry: ACT's kl shows whether its latent carries anything (README, "Baselines")
    loss_terms: list[dict[str, float]] = field(default_factory=list)
    train_seconds: float = 0.0
    bigym_version: str = ""
    model: dict = field(default_factory=dict)
    optimizer: dict = field(default_factory=dict)
    rng: dict = field(default_factory=dict)
    ema: dict = field(default_factory=dict)  # the weight average's state when config["ema"] > 0
    demo_modes: list[int] = field(default_factory=list)  # each training demo's mode (config "modes")

    @property
    def acting_weights(self) -> dict:
        """The weight average when the run kept one, else the last weights."""
        return self.ema["weights"] if self.ema else self.model

    def build_model(self) -> torch.nn.Module:
        config = make_config(self.method, self.config)
        shapes = {k: tuple(v) for k, v in self.image_shapes.items()}
        model = make_model(self.method, config, self.state_dim, self.action_dim, shapes)
        if self.acting_weights:
            model.load_state_dict(self.acting_weights)
        return model

    def make_normalizer(self) -> Normalizer:
        return Normalizer.from_dict(self.normalizer)

    def save(self, path: str | Path) -> Path:
        """Write atomically: an interrupted save leaves the previous checkpoint intact."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        partial = path.with_name(path.name + ".partial")
        torch.save({"format": FORMAT, "format_version": FORMAT_VERSION, **dataclasses.asdict(self)}, partial)
        os.replace(partial, path)
        return path

    @classmethod
    def load(cls, path: str | Path) -> Checkpoint:
        path = Path(path)
        if not path.is_file():
            raise FileNotFoundError(f"no checkpoint at {path}")
        try:
            data: dict[str, Any] = torch.load(path, map_location="cpu", weights_only=True)
        except Exception as error:
            raise ValueError(f"{path} is not a readable bigym checkpoint: {error}") from error
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            raise ValueError(f"{path} is not a bigym baseline checkpoint")
        if data.get("format_version", 0) > FORMAT_VERSION:
            raise ValueError(f"{path} was written by a newer bigym (format {data['format_version']})")
        data["config"] = with_legacy_settings(data["method"], data["config"])
        fields = {f.name for f in dataclasses.fields(cls)}
        return cls(**{k: v for k, v in data.items() if k in fields})


#: Settings added after the first checkpoints, with what those checkpoints trained with (not
#: today's default, which may differ): chunk ends masked, the last weights acting, no state noise.
LEGACY_SETTINGS = {"hold_end": False, "ema": 0.0, "state_noise": 0.0, "modes": 0, "tail": False}


def with_legacy_settings(method: str, config: dict[str, Any]) -> dict[str, Any]:
    """A saved training config with the settings it predates filled in as it ran (those
    its method has: ``modes`` is ACT's alone)."""
    names = {f.name for f in dataclasses.fields(method_classes(method)[0])}
    return {**{k: v for k, v in LEGACY_SETTINGS.items() if k in names}, **config}

"""The baseline methods by name: each is a config class and a model class in its own folder."""

from __future__ import annotations

import dataclasses
from typing import Any

from bigym.baselines.act.config import ACTConfig
from bigym.baselines.act.model import ACTModel
from bigym.baselines.bc.config import BCConfig
from bigym.baselines.bc.model import BCModel
from bigym.baselines.common import TrainConfig
from bigym.baselines.dp.config import DPConfig
from bigym.baselines.dp.model import DPModel

METHODS: dict[str, tuple[type[TrainConfig], type]] = {
    "bc": (BCConfig, BCModel),
    "act": (ACTConfig, ACTModel),
    "dp": (DPConfig, DPModel),
}


def method_classes(method: str) -> tuple[type[TrainConfig], type]:
    try:
        return METHODS[method]
    except KeyError:
        raise ValueError(f"unknown method {method!r}; choose from {', '.join(METHODS)}") from None


def make_config(method: str, overrides: dict[str, Any] | None = None) -> TrainConfig:
    """The method's default config with ``overrides`` (unknown names are an error)."""
    config_class, _ = method_classes(method)
    names = {f.name for f in dataclasses.fields(config_class)}
    unknown = sorted(set(overrides or {}) - names)
    if unknown:
        raise ValueError(f"{method} has no setting {', '.join(unknown)}; its settings: {', '.join(sorted(names))}")
    types = {f.name: f.type for f in dataclasses.fields(config_class)}
    values = {name: _typed(name, value, types[name]) for name, value in (overrides or {}).items()}
    if values.get("modes", 0) < 0:
        raise ValueError(f"setting modes takes 0 (none) or a number of modes, got {values['modes']!r}")
    if values.get("state_noise", 0.0) < 0:
        raise ValueError(f"setting state_noise is a standard deviation, 0 or more, got {values['state_noise']!r}")
    return config_class(**values)


def _typed(name: str, value: Any, kind: str) -> Any:
    """A setting as its field's type (``ema=0`` is 0.0), or an error that names the type: a
    string or a bool where a number belongs would otherwise train a run nobody asked for."""
    number = isinstance(value, (int, float)) and not isinstance(value, bool)
    if kind == "float" and number:
        return float(value)
    if kind == "int" and number and float(value).is_integer():
        return int(value)
    if kind == "bool" and isinstance(value, bool):
        return value
    if kind.startswith("tuple[int") and isinstance(value, (list, tuple)) and all(
        isinstance(v, int) and not isinstance(v, bool) for v in value
    ):
        return tuple(value)
    wanted = {"float": "a number", "int": "a whole number", "bool": "true or false"}.get(kind, "a list of whole numbers")
    raise ValueError(f"setting {name} takes {wanted}, got {value!r}")


def config_dict(config: TrainConfig) -> dict[str, Any]:
    """A config as checkpoints and records store it (JSON-like: tuples as lists)."""
    return {k: list(v) if isinstance(v, tuple) else v for k, v in dataclasses.asdict(config).items()}


def make_model(method: str, config: TrainConfig, state_dim: int, action_dim: int, image_shapes: dict):
    _, model_class = method_classes(method)
    return model_class(config, state_dim, action_dim, image_shapes)

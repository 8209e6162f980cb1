"""The policy interface every evaluated policy follows, and loading a factory by name.

A policy is made per env by a factory and then driven episode by episode::

    def factory(env) -> Policy          # env: the BiGymEnv the policy will act in
    policy.reset(seed)                  # optional: called after env.reset(seed=seed)
    policy(obs) -> action               # one action per env.step

``reset(seed)`` must put the policy in the state it would be in on a fresh start for that
seed (reseed its noise, clear its history): evaluation episodes run on any worker, in any
order, and must not depend on which episodes came before. A class is a factory too
(``RandomPolicy(env)``). Factories run in worker processes, so they are passed by name,
``"package.module:function"`` or ``"path/to/file.py:function"``, or as a module-level
function (picklable by reference).

A policy that reads the simulator itself (``env.data``, as the scripted experts do) says
so with ``reads_simulator = True``: under an asynchronous vector env the simulation lives
in another process, and such a policy is refused rather than silently blind.
"""

from __future__ import annotations

import functools
import importlib
import importlib.util
import pickle
import sys
from pathlib import Path
from typing import Any, Callable, Protocol, runtime_checkable

import numpy as np


@runtime_checkable
class Policy(Protocol):
    def __call__(self, obs: dict[str, np.ndarray]) -> np.ndarray: ...


PolicyFactory = Callable[[Any], Policy]


class PolicyLoadError(ValueError):
    """A policy factory could not be found or does not fit the interface."""


def load_factory(spec: str | PolicyFactory) -> PolicyFactory:
    """The factory named by ``spec`` (``module:attribute`` or ``file.py:attribute``), or ``spec`` itself."""
    if callable(spec):
        return spec
    if not isinstance(spec, str) or ":" not in spec:
        raise PolicyLoadError(
            f"a policy factory is 'package.module:function' or 'path/to/file.py:function', got {spec!r}"
        )
    location, _, name = spec.rpartition(":")
    if location.endswith(".py"):
        module = _module_from_file(Path(location))
    else:
        try:
            module = importlib.import_module(location)
        except ImportError as error:
            raise PolicyLoadError(f"cannot import {location!r} for policy {spec!r}: {error}") from error
    factory = module
    for part in name.split("."):
        factory = getattr(factory, part, None)
        if factory is None:
            raise PolicyLoadError(f"{location!r} has no {name!r} (policy {spec!r})")
    if not callable(factory):
        raise PolicyLoadError(f"{spec!r} is not callable: a factory takes the env and returns a policy")
    return factory


def _module_from_file(path: Path):
    if not path.is_file():
        raise PolicyLoadError(f"no such policy file: {path}")
    name = f"bigym_policy_{abs(hash(str(path.resolve())))}"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except Exception as error:
        del sys.modules[name]
        raise PolicyLoadError(f"loading {path} failed: {type(error).__name__}: {error}") from error
    return module


def check_portable(spec: str | PolicyFactory) -> None:
    """Raise a clear error if worker processes cannot receive ``spec``."""
    if isinstance(spec, str):
        load_factory(spec)  # fail here, not in every worker
        return
    try:
        pickle.dumps(spec)
    except Exception as error:
        raise PolicyLoadError(
            f"the policy factory {spec!r} cannot be sent to worker processes ({error}): pass it by name, "
            "'package.module:function', or define it at module level"
        ) from error


def describe(spec: str | PolicyFactory) -> str:
    """A name for the policy in results: the spec string, or ``module:qualname`` (with the
    bound arguments of a ``functools.partial``)."""
    if isinstance(spec, str):
        return spec
    if isinstance(spec, functools.partial):
        arguments = [repr(a) for a in spec.args] + [f"{k}={v!r}" for k, v in spec.keywords.items()]
        return f"{describe(spec.func)}({', '.join(arguments)})"
    module = getattr(spec, "__module__", None) or "?"
    name = getattr(spec, "__qualname__", None) or type(spec).__name__
    return f"{module}:{name}"


def make_policy(factory: PolicyFactory, env) -> Policy:
    policy = factory(env)
    if not callable(policy):
        raise PolicyLoadError(f"the factory returned {type(policy).__name__}, which is not callable as policy(obs)")
    return policy


def reset_policy(policy: Policy, seed: int) -> None:
    reset = getattr(policy, "reset", None)
    if reset is not None:
        reset(seed)

"""Learned baselines trained from the demos: behaviour cloning with action chunks (``bc``),
ACT (``act``) and a Diffusion Policy (``dp``), compact and in-tree (torch, an optional extra).

:func:`~bigym.baselines.train.train` fits a method on a task's demos and writes a
checkpoint; :func:`~bigym.baselines.policy.checkpoint_factory` turns a checkpoint into the
policy factory that :func:`bigym.evaluation.evaluate` and ``bigym eval --policy PATH`` run.
One folder per method (config, model); :mod:`~bigym.baselines.data` makes the samples,
:mod:`~bigym.baselines.checkpoint` saves and resumes, :mod:`~bigym.baselines.policy` acts.
"""

from __future__ import annotations

from bigym.baselines.checkpoint import Checkpoint
from bigym.baselines.methods import METHODS, make_config
from bigym.baselines.policy import ChunkPolicy, checkpoint_factory, load_policy, temporal_ensemble
from bigym.baselines.train import observation_config, train

__all__ = [
    "METHODS",
    "Checkpoint",
    "ChunkPolicy",
    "checkpoint_factory",
    "load_policy",
    "make_config",
    "observation_config",
    "temporal_ensemble",
    "train",
]

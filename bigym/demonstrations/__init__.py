"""BiGym demonstrations: record, store, replay, convert and export demos.

The paper's API::

    from bigym.demonstrations import DemoStore, Metadata

    demos = DemoStore().get_demos(Metadata.from_env(env), amount=10, frequency=50)

Modules: :mod:`~bigym.demonstrations.demo` (file format), :mod:`~bigym.demonstrations.recorder`,
:mod:`~bigym.demonstrations.player`, :mod:`~bigym.demonstrations.convert`,
:mod:`~bigym.demonstrations.store`, :mod:`~bigym.demonstrations.export`,
:mod:`~bigym.demonstrations.transitions` (flat arrays for offline RL, d3rlpy). The ``bigym demos``
commands live in :mod:`bigym.cli.demos` (this package knows no demo producer). Ray is imported only when a replay
asks for ``backend="ray"``; pyarrow and h5py only when exporting.
"""

from __future__ import annotations

from bigym.demonstrations.convert import convert_demo
from bigym.demonstrations.demo import Demo, ReplayedDemo, ReplayReport
from bigym.demonstrations.errors import (
    DemoActionModeError,
    DemoBuildError,
    DemoChecksumError,
    DemoCorruptError,
    DemoDivergenceError,
    DemoError,
    DemoNotFoundError,
    DemoReplayError,
    DemoStoreBusyError,
    DemoVersionWarning,
    TooManyDemosRequestedError,
)
from bigym.demonstrations.metadata import Metadata, model_fingerprint
from bigym.demonstrations.player import ReplayPool, default_tolerance, make_env, replay, replay_many
from bigym.demonstrations.recorder import DemoRecorder, record_episode
from bigym.demonstrations.store import DATASET_VERSION, DemoStore, Manifest, ManifestEntry, ReplayCache


def export_lerobot(*args, **kwargs):
    """See :func:`bigym.demonstrations.export.export_lerobot` (imports pyarrow on use)."""
    from bigym.demonstrations.export import export_lerobot as _export

    return _export(*args, **kwargs)


def export_robomimic(*args, **kwargs):
    """See :func:`bigym.demonstrations.export.export_robomimic` (imports h5py on use)."""
    from bigym.demonstrations.export import export_robomimic as _export

    return _export(*args, **kwargs)


def export_minari(*args, **kwargs):
    """See :func:`bigym.demonstrations.export.export_minari` (imports minari on use)."""
    from bigym.demonstrations.export import export_minari as _export

    return _export(*args, **kwargs)


__all__ = [
    "DATASET_VERSION",
    "Demo",
    "DemoActionModeError",
    "DemoBuildError",
    "DemoChecksumError",
    "DemoCorruptError",
    "DemoDivergenceError",
    "DemoError",
    "DemoNotFoundError",
    "DemoRecorder",
    "DemoReplayError",
    "DemoStore",
    "DemoStoreBusyError",
    "DemoVersionWarning",
    "Manifest",
    "ManifestEntry",
    "Metadata",
    "ReplayCache",
    "ReplayPool",
    "ReplayReport",
    "ReplayedDemo",
    "TooManyDemosRequestedError",
    "convert_demo",
    "default_tolerance",
    "export_lerobot",
    "export_minari",
    "export_robomimic",
    "make_env",
    "model_fingerprint",
    "record_episode",
    "replay",
    "replay_many",
]

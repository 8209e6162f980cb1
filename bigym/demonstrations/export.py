"""Exports of replayed demos to standard dataset layouts.

* :func:`export_lerobot`: the LeRobot dataset v3.0 layout — frame tables in
  ``data/chunk-XXX/file-YYY.parquet``, one mp4 per camera in
  ``videos/<key>/chunk-XXX/file-YYY.mp4`` (episodes concatenated), and ``meta/info.json``,
  ``meta/stats.json``, ``meta/tasks.parquet``, ``meta/episodes/chunk-XXX/file-YYY.parquet``.
* :func:`export_robomimic`: one robomimic-style HDF5 file,
  ``data/demo_<k>/{actions, obs/<key>, next_obs/<key>, rewards, dones, states}``.
* :func:`export_minari`: a Minari dataset (Dict observations kept as they are).

A frame ``t`` pairs the observation before action ``t`` with that action, so an episode
of ``T`` actions gives ``T`` frames (the final observation is in ``next_obs`` only).
pyarrow, h5py, imageio-ffmpeg and minari are imported here only.
"""

from __future__ import annotations

import json
import shutil
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

import bigym
from bigym.demonstrations.atomic import atomic_write, partial_path
from bigym.demonstrations.demo import ReplayedDemo
from bigym.demonstrations.errors import DemoError
from bigym.observations import is_image_key

LEROBOT_VERSION = "v3.0"
CHUNKS_SIZE = 1000
DATA_FILE_SIZE_MB = 100
VIDEO_FILE_SIZE_MB = 200
DATA_PATH = "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
VIDEO_PATH = "videos/{video_key}/chunk-{chunk_index:03d}/file-{file_index:03d}.mp4"
EPISODES_PATH = "meta/episodes/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
TASKS_PATH = "meta/tasks.parquet"
VIDEO_CODEC = "libx264"  # "h264" in LeRobot's list of codecs
QUANTILES = (0.01, 0.10, 0.50, 0.90, 0.99)
#: robomimic's readers divide depth images by 1 and clip them to [0, 1] (``process_frame``),
#: which keeps only the first metre of metric depth (about half of the head camera's pixels).
#: Its files therefore hold depth normalised over this range, in metres, written into the
#: file: ``metres = near + value * (far - near)``; depth beyond ``far`` is stored as 1.
ROBOMIMIC_DEPTH_RANGE = (0.0, 5.0)
#: the demo metadata a Minari dataset's description carries (how to rebuild the env)
MINARI_METADATA = (
    "task",
    "task_kwargs",
    "action_mode",
    "frequency",
    "bigym_version",
    "mujoco_version",
    "model_fingerprint",
    "action_names",
)


def _check_demos(demos: Sequence[ReplayedDemo]) -> None:
    if not demos:
        raise DemoError("nothing to export: no demos given")
    first = demos[0]
    for demo in demos[1:]:
        if demo.metadata.frequency != first.metadata.frequency:
            raise DemoError("all exported demos must share one control rate")
        if set(demo.observations) != set(first.observations):
            raise DemoError("all exported demos must share one observation config")
        if demo.actions.shape[1] != first.actions.shape[1]:
            raise DemoError("all exported demos must share one action layout")


def _task_text(task: str) -> str:
    """The task's one-line description (its docstring), for LeRobot's language task table."""
    from bigym.demonstrations.player import resolve_task

    try:
        doc = (resolve_task(task).__doc__ or "").strip().splitlines()
    except DemoError:
        doc = []
    return doc[0].strip().replace("``", "") if doc and doc[0].strip() else task


def _proprioception_names(demo: ReplayedDemo) -> list[str] | None:
    from bigym.demonstrations.player import make_env
    from bigym.observations import ObservationConfig

    try:
        env = make_env(demo.metadata, ObservationConfig(), demo.metadata.frequency)
    except DemoError:
        return None
    try:
        return list(env.observation_layout.names)
    finally:
        env.close()


def _feature_name(key: str) -> str:
    if key == "proprioception":
        return "observation.state"
    if key.startswith("rgb_"):
        return f"observation.images.{key[4:]}"
    return "observation." + key.removeprefix("proprioception_")


def _stats(values: np.ndarray, axis: tuple[int, ...]) -> dict[str, list]:
    values = np.asarray(values, np.float64)
    result = {
        "min": values.min(axis=axis),
        "max": values.max(axis=axis),
        "mean": values.mean(axis=axis),
        "std": values.std(axis=axis),
        "count": np.array([values.shape[0]]),
    }
    for q in QUANTILES:
        result[f"q{round(q * 100):02d}"] = np.quantile(values, q, axis=axis)
    return {k: np.asarray(v).tolist() for k, v in result.items()}


def _merge_stats(parts: list[tuple[dict, int]]) -> dict:
    """Combine per-episode stats (min, max, count-weighted mean and pooled std; quantiles averaged)."""
    total = sum(n for _, n in parts)
    first = parts[0][0]
    mean = sum(np.asarray(s["mean"]) * n for s, n in parts) / total
    second = sum((np.asarray(s["std"]) ** 2 + np.asarray(s["mean"]) ** 2) * n for s, n in parts) / total
    merged = {
        "min": np.minimum.reduce([np.asarray(s["min"]) for s, _ in parts]),
        "max": np.maximum.reduce([np.asarray(s["max"]) for s, _ in parts]),
        "mean": mean,
        "std": np.sqrt(np.maximum(second - mean**2, 0.0)),
        "count": np.array([total]),
    }
    for key in first:
        if key.startswith("q"):
            merged[key] = sum(np.asarray(s[key]) * n for s, n in parts) / total
    return {k: np.asarray(v).tolist() for k, v in merged.items()}


class _VideoWriter:
    """One mp4 file, frames appended across episodes (h264, 2-frame GOP as LeRobot uses)."""

    def __init__(self, path: Path, height: int, width: int, fps: int) -> None:
        import imageio_ffmpeg

        path.parent.mkdir(parents=True, exist_ok=True)
        self.pix_fmt = "yuv420p" if height % 2 == 0 and width % 2 == 0 else "yuv444p"
        self.frames = 0
        self._writer = imageio_ffmpeg.write_frames(
            str(path), (width, height), fps=fps, codec=VIDEO_CODEC, pix_fmt_out=self.pix_fmt,
            macro_block_size=1, quality=None, output_params=["-crf", "18", "-g", "2"],
        )  # fmt: skip
        self._writer.send(None)

    def append(self, frames_chw: np.ndarray) -> None:
        for frame in frames_chw:
            self._writer.send(np.ascontiguousarray(frame.transpose(1, 2, 0)))
            self.frames += 1

    def close(self) -> None:
        self._writer.close()


def export_lerobot(
    demos: Sequence[ReplayedDemo],
    root: Path | str,
    *,
    task_description: str | None = None,
    robot_type: str = "unitree_h1_2f85",
    overwrite: bool = False,
    data_file_size_mb: float = DATA_FILE_SIZE_MB,
    progress: bool = False,
) -> Path:
    """Write ``demos`` as a LeRobot v3.0 dataset in the folder ``root``; return it.

    The folder is built beside ``root`` and renamed into place at the end, so an
    interrupted export leaves no half dataset. Depth images are not exported (LeRobot
    keeps cameras as videos); use :func:`export_robomimic` for depth.
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    from bigym.demonstrations.player import progress_bar

    _check_demos(demos)
    root = Path(root)
    if root.exists() and not overwrite:
        raise DemoError(f"{root} exists; pass overwrite=True (--overwrite) to replace it")
    first = demos[0]
    rate = float(first.metadata.frequency)
    if abs(rate - round(rate)) > 1e-9:
        raise DemoError(
            f"LeRobot datasets need a whole number of frames per second; these demos run at {rate:g} Hz. "
            "Replay at a rate that divides 500 Hz evenly (20, 25, 50, 100, 125, 250, 500)."
        )
    fps = round(rate)
    work = partial_path(root)
    work.mkdir(parents=True)
    try:
        # ----- features
        state_names = _proprioception_names(first)
        vector_keys = [k for k in first.observations if not is_image_key(k)]
        video_keys = [k for k in first.observations if k.startswith("rgb_")]
        features: dict[str, dict] = {}
        for key in vector_keys:
            shape = list(first.observations[key].shape[1:]) or [1]
            names = state_names if key == "proprioception" and state_names and len(state_names) == shape[0] else None
            features[_feature_name(key)] = {"dtype": "float32", "shape": shape, "names": names}
        for key in video_keys:
            _, h, w = first.observations[key].shape[1:]
            features[_feature_name(key)] = {
                "dtype": "video",
                "shape": [h, w, 3],
                "names": ["height", "width", "channels"],
                "info": {
                    "video.height": h, "video.width": w, "video.codec": "h264",
                    "video.pix_fmt": "yuv420p" if h % 2 == 0 and w % 2 == 0 else "yuv444p",
                    "video.is_depth_map": False, "video.fps": fps, "video.channels": 3, "has_audio": False,
                },
            }  # fmt: skip
        action_names = list(first.metadata.action_names) or None
        features["action"] = {"dtype": "float32", "shape": [first.actions.shape[1]], "names": action_names}
        features["next.reward"] = {"dtype": "float32", "shape": [1], "names": None}
        features["next.done"] = {"dtype": "bool", "shape": [1], "names": None}
        features["next.success"] = {"dtype": "bool", "shape": [1], "names": None}
        for name in ("timestamp", "frame_index", "episode_index", "index", "task_index"):
            features[name] = {"dtype": "float32" if name == "timestamp" else "int64", "shape": [1], "names": None}

        # ----- tasks
        texts = []
        for demo in demos:
            text = task_description or _task_text(demo.metadata.task)
            if text not in texts:
                texts.append(text)

        # ----- frames, videos, episodes
        bytes_per_frame = 4 * sum(int(np.prod(f["shape"])) for f in features.values() if f["dtype"] != "video")
        frames_per_file = max(1, int(data_file_size_mb * 2**20 / max(bytes_per_frame, 1)))
        chunk, file, file_frames = 0, 0, 0
        writers: dict[str, _VideoWriter] = {}
        tables: list = []
        stats_parts: dict[str, list] = {name: [] for name in features}
        episodes: list[dict] = []
        global_index = 0

        def flush_data() -> None:
            nonlocal tables
            if tables:
                path = work / DATA_PATH.format(chunk_index=chunk, file_index=file)
                path.parent.mkdir(parents=True, exist_ok=True)
                pq.write_table(pa.concat_tables(tables), path, compression="snappy")
            tables = []
            for writer in writers.values():
                writer.close()
            writers.clear()

        with progress_bar(progress, "exporting to LeRobot", len(demos)) as advance:
            for episode_index, demo in enumerate(demos):
                length = len(demo.actions)
                if file_frames and file_frames + length > frames_per_file:
                    flush_data()
                    file += 1
                    if file == CHUNKS_SIZE:
                        chunk, file = chunk + 1, 0
                    file_frames = 0
                task_index = texts.index(task_description or _task_text(demo.metadata.task))
                columns: dict[str, pa.Array] = {}
                per_episode: dict[str, np.ndarray] = {}
                for key in vector_keys:
                    values = np.asarray(demo.observations[key][:-1], np.float32).reshape(length, -1)
                    per_episode[_feature_name(key)] = values
                per_episode["action"] = np.asarray(demo.actions, np.float32)
                for name, values in per_episode.items():
                    flat = pa.array(values.reshape(-1), pa.float32())
                    if features[name]["shape"] == [1]:
                        columns[name] = flat
                    else:
                        columns[name] = pa.FixedSizeListArray.from_arrays(flat, values.shape[1])
                done = np.zeros(length, bool)
                done[-1] = True
                scalars = {
                    "next.reward": np.asarray(demo.rewards, np.float32),
                    "next.done": done,
                    "next.success": np.asarray(demo.success, bool),
                    "timestamp": (np.arange(length) / fps).astype(np.float32),
                    "frame_index": np.arange(length, dtype=np.int64),
                    "episode_index": np.full(length, episode_index, np.int64),
                    "index": np.arange(global_index, global_index + length, dtype=np.int64),
                    "task_index": np.full(length, task_index, np.int64),
                }
                for name, values in scalars.items():
                    columns[name] = pa.array(values)
                tables.append(pa.table(columns))

                record = {
                    "episode_index": episode_index,
                    "tasks": [texts[task_index]],
                    "length": length,
                    "data/chunk_index": chunk,
                    "data/file_index": file,
                    "dataset_from_index": global_index,
                    "dataset_to_index": global_index + length,
                }
                for key in video_keys:
                    name = _feature_name(key)
                    frames = demo.observations[key][:-1]
                    if name not in writers:
                        path = work / VIDEO_PATH.format(video_key=name, chunk_index=chunk, file_index=file)
                        writers[name] = _VideoWriter(path, frames.shape[2], frames.shape[3], fps)
                    start = writers[name].frames
                    writers[name].append(frames)
                    record[f"videos/{name}/chunk_index"] = chunk
                    record[f"videos/{name}/file_index"] = file
                    record[f"videos/{name}/from_timestamp"] = start / fps
                    record[f"videos/{name}/to_timestamp"] = (start + length) / fps
                    episode_stats = _stats(frames.astype(np.float32) / 255.0, axis=(0, 2, 3))
                    episode_stats = {
                        k: (np.asarray(v).reshape(3, 1, 1).tolist() if k != "count" else v)
                        for k, v in episode_stats.items()
                    }
                    stats_parts[name].append((episode_stats, length))
                    record.update({f"stats/{name}/{k}": v for k, v in episode_stats.items()})
                for name, values in {**per_episode, **scalars}.items():
                    values = np.asarray(values, np.float64).reshape(length, -1)
                    episode_stats = _stats(values, axis=(0,))
                    stats_parts[name].append((episode_stats, length))
                    record.update({f"stats/{name}/{k}": v for k, v in episode_stats.items()})
                record["meta/episodes/chunk_index"] = 0
                record["meta/episodes/file_index"] = 0
                episodes.append(record)
                global_index += length
                file_frames += length
                advance()
            flush_data()

        episodes_path = work / EPISODES_PATH.format(chunk_index=0, file_index=0)
        episodes_path.parent.mkdir(parents=True, exist_ok=True)
        pq.write_table(pa.Table.from_pylist(episodes), episodes_path, compression="snappy")
        _write_tasks(work / TASKS_PATH, texts)
        stats = {name: _merge_stats(parts) for name, parts in stats_parts.items() if parts}
        (work / "meta" / "stats.json").write_text(json.dumps(stats, indent=4))
        info = {
            "codebase_version": LEROBOT_VERSION,
            "robot_type": robot_type,
            "total_episodes": len(demos),
            "total_frames": global_index,
            "total_tasks": len(texts),
            "chunks_size": CHUNKS_SIZE,
            "data_files_size_in_mb": int(data_file_size_mb) if data_file_size_mb >= 1 else 1,
            "video_files_size_in_mb": VIDEO_FILE_SIZE_MB,
            "fps": fps,
            "splits": {"train": f"0:{len(demos)}"},
            "data_path": DATA_PATH,
            "video_path": VIDEO_PATH if video_keys else None,
            "features": features,
        }
        bigym_meta = {
            "bigym_version": bigym.__version__,
            "task": first.metadata.task,
            "action_mode": first.metadata.action_mode,
            "observation_config": first.metadata.observation_config,
            "demo_uuids": [d.uuid for d in demos],
            "depth_exported": False,
        }
        (work / "meta" / "bigym.json").write_text(json.dumps(bigym_meta, indent=4))
        (work / "meta" / "info.json").write_text(json.dumps(info, indent=4))
        if root.exists():
            shutil.rmtree(root)
        work.rename(root)
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise
    return root


def _write_tasks(path: Path, texts: list[str]) -> None:
    """``meta/tasks.parquet``: ``task_index`` with the task text as the (pandas) index, as LeRobot reads it."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pa.table({"task_index": pa.array(range(len(texts)), pa.int64()), "task": pa.array(texts, pa.string())})
    pandas_meta = {
        "index_columns": ["task"],
        "column_indexes": [
            {"name": None, "field_name": None, "pandas_type": "unicode", "numpy_type": "object",
             "metadata": {"encoding": "UTF-8"}}
        ],
        "columns": [
            {"name": "task_index", "field_name": "task_index", "pandas_type": "int64", "numpy_type": "int64",
             "metadata": None},
            {"name": "task", "field_name": "task", "pandas_type": "unicode", "numpy_type": "object",
             "metadata": None},
        ],
        "creator": {"library": "pyarrow", "version": pa.__version__},
        "pandas_version": "2.2.0",
    }  # fmt: skip
    table = table.replace_schema_metadata({b"pandas": json.dumps(pandas_meta).encode()})
    path.parent.mkdir(parents=True, exist_ok=True)
    pq.write_table(table, path)


def export_robomimic(
    demos: Sequence[ReplayedDemo],
    path: Path | str,
    *,
    overwrite: bool = False,
    compression: str | None = "gzip",
    progress: bool = False,
    depth_range: tuple[float, float] = ROBOMIMIC_DEPTH_RANGE,
) -> Path:
    """Write ``demos`` to one robomimic-style HDF5 file (atomically); return its path.

    ``data`` attributes: ``total`` (frames) and ``env_args`` (JSON: env_name, type, env_kwargs
    with the bigym metadata, and ``bigym``: how to rebuild the env, see
    :func:`env_from_robomimic`). Each ``data/demo_<k>`` holds ``actions (T, A)``,
    ``obs/<key>`` and ``next_obs/<key>`` (``T`` each; images channel-last ``(T, H, W, 3)``
    uint8; depth ``(T, H, W, 1)`` float32 in [0, 1], normalised over ``depth_range`` metres
    as robomimic's readers expect, with ``near``, ``far`` and ``encoding`` attributes),
    ``rewards``, ``dones``, ``states`` (MuJoCo state, spec in the ``state_spec`` attribute)
    and the attributes ``num_samples``, ``seed``, ``uuid``.
    """
    import h5py

    from bigym.demonstrations.player import progress_bar

    _check_demos(demos)
    path = Path(path)
    if path.exists() and not overwrite:
        raise DemoError(f"{path} exists; pass overwrite=True (--overwrite) to replace it")
    near, far = (float(v) for v in depth_range)
    if not (0.0 <= near < far):
        raise ValueError(f"depth_range must be (near, far) with 0 <= near < far, got {depth_range}")
    encoding = f"normalised: metres = {near:g} + value * ({far:g} - {near:g}); depth beyond {far:g} m is 1"
    first = demos[0].metadata
    env_args = {
        "env_name": first.env_id,
        "type": 2,  # robomimic's EnvType.GYM_TYPE: a gymnasium env, but see "bigym" below
        "env_kwargs": {
            "task": first.task,
            "task_kwargs": first.task_kwargs,
            "action_mode": first.action_mode,
            "observation_config": first.observation_config,
            "control_frequency": first.frequency,
            "bigym_version": bigym.__version__,
        },
        "bigym": {
            "rebuild": "from bigym.demonstrations.export import env_from_robomimic; env = env_from_robomimic(path)",
            "why": "robomimic's create_env_from_metadata builds gym (not gymnasium) envs with other kwargs",
            "depth_range": [near, far],
            "depth_encoding": encoding,
        },
    }

    def write(handle) -> None:
        with h5py.File(handle, "w") as f, progress_bar(progress, "exporting to HDF5", len(demos)) as advance:
            data = f.create_group("data")
            total = 0
            for k, demo in enumerate(demos):
                group = data.create_group(f"demo_{k}")
                length = len(demo.actions)
                group.attrs["num_samples"] = length
                group.attrs["seed"] = -1 if demo.metadata.seed is None else int(demo.metadata.seed)
                group.attrs["uuid"] = demo.uuid
                group.attrs["state_spec"] = int(demo.metadata.checkpoint_spec)
                group.attrs["metadata"] = json.dumps(demo.metadata.to_dict())
                group.create_dataset("actions", data=demo.actions)
                group.create_dataset("rewards", data=np.asarray(demo.rewards, np.float64))
                dones = np.zeros(length, np.int64)
                dones[-1] = 1
                group.create_dataset("dones", data=dones)
                group.create_dataset("states", data=demo.states[:-1])
                for prefix, part in (("obs", slice(0, -1)), ("next_obs", slice(1, None))):
                    obs_group = group.create_group(prefix)
                    for key, values in demo.observations.items():
                        values = values[part]
                        if key.startswith("rgb_"):
                            values = values.transpose(0, 2, 3, 1)
                        elif key.startswith("depth_"):
                            normalised = (np.asarray(values, np.float64) - near) / (far - near)
                            values = np.clip(normalised, 0.0, 1.0).astype(np.float32)[..., None]
                        image = values.ndim >= 3
                        dataset = obs_group.create_dataset(
                            key, data=values, compression=compression if image else None,
                            chunks=(1, *values.shape[1:]) if image and compression else None,
                        )  # fmt: skip
                        if key.startswith("depth_"):
                            dataset.attrs.update({"near": near, "far": far, "encoding": encoding})
                total += length
                advance()
            data.attrs["total"] = total
            data.attrs["env_args"] = json.dumps(env_args)
            mask = f.create_group("mask")
            mask.create_dataset("train", data=np.array([f"demo_{k}" for k in range(len(demos))], dtype="S"))

    return atomic_write(path, write)


def env_from_robomimic(source: Path | str | dict, observation_config=None, render_mode: str | None = None):
    """The bigym env a robomimic file (or its parsed ``env_args``) was recorded in: same task,
    task variant, action mode, control rate and (unless given) observation config.

    Why not robomimic's ``create_env_from_metadata``: it builds its envs through the old
    ``gym`` API and passes its own keyword arguments, which a gymnasium env rejects. Reset the
    env with a demo's ``seed`` attribute to start where that demo started.
    """
    import h5py

    from bigym.demonstrations.metadata import Metadata
    from bigym.demonstrations.player import make_env

    if isinstance(source, dict):
        env_args = source
    else:
        with h5py.File(source, "r") as f:
            if "env_args" not in f["data"].attrs:
                raise DemoError(f"{source} has no data.attrs['env_args']: not a robomimic file")
            env_args = json.loads(f["data"].attrs["env_args"])
    kwargs = env_args.get("env_kwargs") or {}
    missing = [k for k in ("task", "action_mode", "control_frequency") if k not in kwargs]
    if missing:
        raise DemoError(f"env_args lack {missing}: not written by bigym's export_robomimic")
    metadata = Metadata.from_dict(
        {
            "task": kwargs["task"],
            "task_kwargs": kwargs.get("task_kwargs") or {},
            "action_mode": kwargs["action_mode"],
            "frequency": kwargs["control_frequency"],
        }
    )
    config = observation_config if observation_config is not None else kwargs.get("observation_config")
    return make_env(metadata, config, render_mode=render_mode)


def export_minari(
    demos: Sequence[ReplayedDemo],
    dataset_id: str,
    env,
    *,
    data_format: str = "hdf5",
    author: str | None = None,
) -> Any:
    """Write ``demos`` as a Minari dataset (``namespace/name-vN``); return the ``MinariDataset``.

    Minari keeps Dict observations as they are, so the episodes hold the demos' own
    observations (all ``T + 1``), actions, rewards, terminations and truncations, and the
    seed of each. ``env`` (the env the demos were replayed in) gives the spaces; the dataset
    is written without an env spec (bigym's envs take settings a gymnasium id cannot carry):
    the demos' task, action mode, rate, versions and observation keys go into its
    description as JSON. Minari writes to its own dataset folder (``MINARI_DATASETS_PATH``).
    """
    try:
        import minari
        from minari.data_collector import EpisodeBuffer
    except ImportError as error:
        raise ImportError(f"export_minari needs minari: pip install minari ({error})") from error
    _check_demos(demos)
    space = env.observation_space
    keys = list(demos[0].observations)
    missing = [key for key in keys if key not in space.spaces]
    if missing:
        raise DemoError(f"the demos hold observations the env lacks: {', '.join(missing)}")
    buffers = []
    for index, demo in enumerate(demos):
        steps = len(demo)
        buffers.append(
            EpisodeBuffer(
                id=index,
                seed=demo.metadata.seed,
                observations={key: np.asarray(demo.observations[key][: steps + 1]) for key in keys},
                actions=np.asarray(demo.actions, np.float32),
                rewards=[float(r) for r in demo.rewards],
                terminations=[bool(t) for t in demo.terminated],
                truncations=[bool(t) for t in demo.truncated],
                # infos hold one entry per observation: the reset's first
                infos={"is_success": np.concatenate([[False], np.asarray(demo.success, bool)])},
            )
        )
    metadata = demos[0].metadata.to_dict()
    about = {key: metadata.get(key) for key in MINARI_METADATA}
    about["observations"] = keys
    description = json.dumps(about, sort_keys=True)
    with warnings.catch_warnings():
        # minari asks for an author, a code link, an eval env and an env spec; the description says why none
        warnings.filterwarnings("ignore", category=UserWarning, module=r"minari\.")
        return minari.create_dataset_from_buffers(
            dataset_id,
            buffers,
            action_space=env.action_space,
            observation_space=type(space)({key: space.spaces[key] for key in keys}),
            algorithm_name="bigym demonstrations",
            author=author,
            description=description,
            data_format=data_format,
        )

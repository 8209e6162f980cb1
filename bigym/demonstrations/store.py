"""DemoStore: versioned demo datasets behind any fsspec URL, with a local cache.

Store layout (a local folder, ``http(s)://``, ``s3://``, ``gcs://``, ``hf://`` ... any
fsspec URL; remote protocols need their fsspec package, e.g. ``s3fs``)::

    <url>/index.json                      {"format": "bigym-demo-store", "versions": [...], "latest": ...}
    <url>/<version>/manifest.json         every demo: path, sha256, size and its metadata
    <url>/<version>/<Task>/<action-mode>/<rate>hz/<uuid>.safetensors

Local cache (``$BIGYM_HOME``, default ``~/.cache/bigym``)::

    demonstrations/store/                 the default store (a local folder you can add demos to)
    demonstrations/downloads/<store-id>/<version>/...   verified copies of remote files
    demonstrations/replays/<uuid>/<key>.safetensors     replayed demos, keyed by demo content,
                                                        observation config, rate and action mode

Every file is written atomically (temporary file in the same folder, then ``os.replace``)
and every demo is checked against its manifest size and sha256 before use.

Demos on demand: a local store asked for a task it has no demos of completes that task's
slice of the shipped dataset (built here, or downloaded from a hosted copy), byte for
byte as the shipped manifest lists it (:mod:`bigym.demonstrations.provision`); a damaged
file of that slice is made again. ``on_demand=False`` (or ``BIGYM_ON_DEMAND=0``) turns
that off. Writers: local stores lock their manifest (processes wait for each other);
remote stores take a write lease and refuse a second writer with
:class:`~bigym.demonstrations.errors.DemoStoreBusyError` (:mod:`bigym.demonstrations.locks`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import os
import random
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import mujoco

import bigym
from bigym.action_modes import ActionMode
from bigym.demonstrations.atomic import atomic_open, atomic_write, is_partial, sweep_partial_files
from bigym.demonstrations.demo import DEMO_SUFFIX, Demo, ReplayedDemo, read_safetensors, sha256_bytes
from bigym.demonstrations.errors import (
    DemoActionModeError,
    DemoChecksumError,
    DemoCorruptError,
    DemoError,
    DemoNotFoundError,
    DemoStoreBusyError,
    TooManyDemosRequestedError,
)
from bigym.demonstrations.locks import file_lock, remote_lease
from bigym.demonstrations.metadata import (
    FORMAT_VERSION,
    Metadata,
    action_mode_slug,
    describe_action_mode,
    frequency_slug,
    normalise_action_mode,
)
from bigym.observations import ObservationConfig
from bigym.paths import bigym_home

#: the dataset version a store serves by default: the one this bigym ships a manifest for
DATASET_VERSION = "v2"
MANIFEST_NAME = "manifest.json"
INDEX_NAME = "index.json"
STORE_FORMAT = "bigym-demo-store"


def demonstrations_home() -> Path:
    return bigym_home() / "demonstrations"


def default_store_url() -> str:
    """``$BIGYM_DEMO_STORE`` if set, else the local folder ``$BIGYM_HOME/demonstrations/store``."""
    return os.environ.get("BIGYM_DEMO_STORE") or str(demonstrations_home() / "store")


def canonical_task(name: str) -> str:
    """The registered class name of a task given any of its names."""
    from bigym.demonstrations.player import resolve_task

    return resolve_task(name).__name__


def task_variant(task: str, task_kwargs: dict | None) -> dict:
    """``task_kwargs`` completed with the task's own defaults (e.g. ``hand="left"``).

    A query that leaves a variant argument out means the task's default variant, so
    ``{}`` and ``{"hand": "left"}`` select the same ReachTargetSingle demos.
    """
    import inspect

    from bigym.demonstrations.player import resolve_task

    defaults = {
        name: parameter.default
        for name, parameter in inspect.signature(resolve_task(task).__init__).parameters.items()
        if parameter.kind is inspect.Parameter.KEYWORD_ONLY and parameter.default is not inspect.Parameter.empty
    }
    return {**defaults, **(task_kwargs or {})}


# ---------------------------------------------------------------------- manifest
@dataclass
class ManifestEntry:
    """One demo file of a store and the metadata needed to choose it without opening it."""

    path: str  # relative to the version folder, with forward slashes
    sha256: str
    size: int
    uuid: str
    task: str
    action_mode: dict
    frequency: float
    num_steps: int
    success: bool | None = None
    source: str = "unknown"
    seed: int | None = None
    task_kwargs: dict = field(default_factory=dict)
    bigym_version: str = ""
    mujoco_version: str = ""
    model_fingerprint: str | None = None
    date: str | None = None

    @classmethod
    def for_demo(cls, demo: Demo, path: str, data: bytes) -> ManifestEntry:
        meta = demo.metadata
        return cls(
            path=path,
            sha256=sha256_bytes(data),
            size=len(data),
            uuid=meta.uuid,
            task=meta.task,
            action_mode=normalise_action_mode(meta.action_mode),
            frequency=float(meta.frequency),
            num_steps=int(meta.num_steps or len(demo.actions)),
            success=meta.success,
            source=meta.source,
            seed=meta.seed,
            task_kwargs=dict(meta.task_kwargs),
            bigym_version=meta.bigym_version,
            mujoco_version=meta.mujoco_version,
            model_fingerprint=meta.model_fingerprint,
            date=meta.date,
        )

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> ManifestEntry:
        known = {f.name for f in dataclasses.fields(cls)}
        return cls(**{k: v for k, v in data.items() if k in known})

    def describe(self) -> str:
        return f"{self.task} {describe_action_mode(self.action_mode)} {self.frequency:g} Hz ({self.uuid})"


@dataclass
class Manifest:
    version: str
    entries: list[ManifestEntry] = field(default_factory=list)

    def to_json(self) -> str:
        entries = sorted(self.entries, key=lambda e: e.path)
        payload = {
            "format": STORE_FORMAT,
            "format_version": FORMAT_VERSION,
            "version": self.version,
            "demos": [e.to_dict() for e in entries],
        }
        return json.dumps(payload, indent=1, sort_keys=True)

    @classmethod
    def from_json(cls, text: bytes | str, source: str) -> Manifest:
        try:
            payload = json.loads(text)
        except (UnicodeDecodeError, json.JSONDecodeError) as error:
            raise DemoCorruptError(f"the manifest {source} is not valid JSON: {error}", source=source) from error
        if not isinstance(payload, dict) or payload.get("format") != STORE_FORMAT:
            raise DemoCorruptError(f"{source} is not a bigym demo-store manifest", source=source)
        try:
            entries = [ManifestEntry.from_dict(item) for item in payload.get("demos", [])]
        except TypeError as error:
            raise DemoCorruptError(f"the manifest {source} has a malformed entry: {error}", source=source) from error
        return cls(str(payload.get("version", "")), entries)

    def by_uuid(self, prefix: str) -> ManifestEntry:
        matches = [e for e in self.entries if e.uuid.startswith(prefix)]
        if not matches:
            raise DemoNotFoundError(f"no demo with uuid {prefix!r} in this store")
        if len(matches) > 1:
            raise DemoNotFoundError(f"uuid prefix {prefix!r} is ambiguous: {len(matches)} demos match")
        return matches[0]


# ---------------------------------------------------------------------- replay cache
class ReplayCache:
    """Replayed demos on disk, keyed by demo content, observation config, rate and action mode."""

    def __init__(self, root: Path | str | None = None) -> None:
        self.root = Path(root) if root is not None else demonstrations_home() / "replays"

    @staticmethod
    def key(
        demo_sha256: str,
        observation_config: ObservationConfig | dict | None,
        frequency: float,
        action_mode: dict | ActionMode,
        episode_only: bool = True,
    ) -> str:
        if isinstance(observation_config, ObservationConfig) or observation_config is None:
            observation_config = (observation_config or ObservationConfig()).to_dict()
        substeps = max(1, round(500.0 / float(frequency)))
        payload = [
            FORMAT_VERSION,
            "episode-ends-at-first-terminal-step",  # replays cached before that rule are not served
            "floor-placed-by-each-frame's-own-camera",  # nor images rendered before that fix
            demo_sha256,
            observation_config,
            substeps,
            normalise_action_mode(action_mode),
            bigym.__version__,
            mujoco.__version__,
        ]
        if not episode_only:  # (the keys of episode replays stay as they were)
            payload.append("whole-recording")
        return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()[:32]

    def path(self, uuid: str, key: str) -> Path:
        return self.root / uuid / f"{key}{DEMO_SUFFIX}"

    def get(self, uuid: str, key: str) -> ReplayedDemo | None:
        path = self.path(uuid, key)
        if not path.is_file():
            return None
        try:
            return ReplayedDemo.load(path)
        except (DemoCorruptError, FileNotFoundError):
            with contextlib.suppress(FileNotFoundError):
                path.unlink()  # a damaged entry is a miss, and is rebuilt
            return None

    def put(self, uuid: str, key: str, replayed: ReplayedDemo) -> Path:
        return replayed.save(self.path(uuid, key))

    def entries(self) -> list[Path]:
        if not self.root.is_dir():
            return []
        return sorted(p for p in self.root.rglob(f"*{DEMO_SUFFIX}") if not is_partial(p))

    def clear(self, uuids: Iterable[str] | None = None) -> int:
        """Delete the cached replays of ``uuids`` (all when None); return how many files."""
        removed = 0
        folders = [self.root / u for u in uuids] if uuids is not None else (
            [p for p in self.root.iterdir() if p.is_dir()] if self.root.is_dir() else []
        )  # fmt: skip
        for folder in folders:
            if folder.is_dir():
                for path in folder.iterdir():
                    path.unlink()
                    removed += 1
                folder.rmdir()
        return removed


# ---------------------------------------------------------------------- the store
class DemoStore:
    """Demos of every task under one URL; see the module docstring for the layout.

    ``DemoStore().get_demos(Metadata.from_env(env), amount=10, frequency=50)`` returns ten
    replayed demos with ``env``'s observations at 50 Hz, downloading, verifying, replaying
    and caching as needed.
    """

    def __init__(
        self,
        url: str | os.PathLike | None = None,
        version: str = DATASET_VERSION,
        cache_dir: str | os.PathLike | None = None,
        storage_options: dict | None = None,
        *,
        on_demand: bool | None = None,
        mirror: str | None = None,
        build_workers: int | None = None,
    ) -> None:
        """``on_demand``: complete a missing task from the shipped dataset (default: on,
        unless ``BIGYM_ON_DEMAND=0``); ``mirror``: a hosted copy of the shipped dataset to
        download such slices from (default ``$BIGYM_DATASET_MIRROR``, else they are built
        here with ``build_workers`` processes, default the CPU count up to 8)."""
        import fsspec

        self.url = str(url if url is not None else default_store_url()).rstrip("/")
        try:
            self.fs, self._root = fsspec.core.url_to_fs(self.url, **(storage_options or {}))
        except (ImportError, ValueError) as error:
            raise DemoError(f"cannot open the demo store {self.url}: {error}") from error
        self.is_local = "file" in _protocols(self.fs)
        self._cache_root = Path(cache_dir) if cache_dir is not None else demonstrations_home()
        self.replays = ReplayCache(self._cache_root / "replays")
        self._requested_version = version
        self._version: str | None = None
        self._manifest: Manifest | None = None
        self.on_demand = on_demand if on_demand is not None else os.environ.get("BIGYM_ON_DEMAND", "1") != "0"
        self.mirror = mirror
        self.build_workers = build_workers

    def __repr__(self) -> str:
        return f"DemoStore({self.url!r}, version={self._requested_version!r})"

    # ------------------------------------------------------------------ paths
    @property
    def version(self) -> str:
        if self._version is None:
            self._version = self._resolve_version(self._requested_version)
        return self._version

    def _remote(self, *parts: str) -> str:
        return "/".join([self._root.rstrip("/"), *parts])

    @property
    def store_id(self) -> str:
        digest = hashlib.sha256(self.url.encode()).hexdigest()[:12]
        tail = "".join(c if c.isalnum() else "_" for c in self.url.split("://")[-1])[-40:].strip("_")
        return f"{tail}-{digest}"

    @property
    def download_dir(self) -> Path:
        return self._cache_root / "downloads" / self.store_id / self.version

    @property
    def version_folder(self) -> Path:
        """The version's folder of a local store."""
        if not self.is_local:
            raise DemoError(f"{self.url} is not a local store")
        return Path(self._remote(self.version))

    def local_path(self, entry: ManifestEntry) -> Path:
        """Where the verified file lives on this machine (in the store, or the download cache)."""
        if self.is_local:
            return Path(self._remote(self.version, entry.path))
        return self.download_dir / entry.path

    def _resolve_version(self, version: str) -> str:
        if version != "latest":
            return version
        index = self._read_index()
        if not index.get("latest"):
            raise DemoNotFoundError(f"the store {self.url} has no {INDEX_NAME} naming its latest version")
        return str(index["latest"])

    def _read_index(self) -> dict:
        try:
            return json.loads(self.fs.cat_file(self._remote(INDEX_NAME)))
        except FileNotFoundError:
            return {}
        except (UnicodeDecodeError, json.JSONDecodeError) as error:
            raise DemoCorruptError(f"{self.url}/{INDEX_NAME} is not valid JSON: {error}") from error

    def versions(self) -> list[str]:
        """Dataset versions listed in the store's index."""
        return list(self._read_index().get("versions", []))

    # ------------------------------------------------------------------ manifest
    def manifest(self, refresh: bool = False) -> Manifest:
        """The version's manifest; for remote stores fetched once and cached (versions are immutable)."""
        if self._manifest is not None and not refresh:
            return self._manifest
        remote = self._remote(self.version, MANIFEST_NAME)
        if self.is_local:
            try:
                text = self.fs.cat_file(remote)
            except FileNotFoundError:
                self._manifest = Manifest(self.version)
                return self._manifest
        else:
            cached = self.download_dir / MANIFEST_NAME
            if cached.is_file() and not refresh:
                text = cached.read_bytes()
            else:
                try:
                    text = self.fs.cat_file(remote)
                except FileNotFoundError as error:
                    raise DemoNotFoundError(
                        f"the store {self.url} has no dataset version {self.version!r} ({remote} not found)"
                    ) from error
                except Exception as error:  # network errors of every fsspec backend
                    raise DemoError(f"cannot fetch {remote}: {error}") from error
                Manifest.from_json(text, remote)  # validate before caching
                atomic_write(cached, text)
        self._manifest = Manifest.from_json(text, remote)
        return self._manifest

    def entries(
        self,
        task: str | None = None,
        action_mode: dict | ActionMode | None = None,
        frequency: float | None = None,
        success: bool | None = None,
    ) -> list[ManifestEntry]:
        """Manifest entries, optionally filtered; sorted by path."""
        task = canonical_task(task) if task else None
        mode = normalise_action_mode(action_mode) if action_mode is not None else None
        found = []
        for entry in self.manifest().entries:
            if task is not None and entry.task != task:
                continue
            if mode is not None and normalise_action_mode(entry.action_mode) != mode:
                continue
            if frequency is not None and abs(entry.frequency - float(frequency)) > 1e-9:
                continue
            if success is not None and bool(entry.success) != success:
                continue
            found.append(entry)
        return sorted(found, key=lambda e: e.path)

    # ------------------------------------------------------------------ files
    def fetch(self, entry: ManifestEntry) -> Path:
        """A verified local copy of ``entry`` (downloaded once for remote stores)."""
        path = self.local_path(entry)
        if self.is_local:
            if not path.is_file():
                raise DemoNotFoundError(f"{path} is listed in the manifest but missing from the store")
            verify_bytes(path.read_bytes(), entry, str(path))
            return path
        if path.is_file():
            try:
                verify_bytes(path.read_bytes(), entry, str(path))
                return path  # cache hit: no request
            except DemoChecksumError:
                path.unlink()  # damaged in the cache: fetch it again
        remote = self._remote(self.version, entry.path)
        try:
            data = self.fs.cat_file(remote)
        except FileNotFoundError as error:
            raise DemoNotFoundError(f"{remote} is listed in the manifest but missing from the store") from error
        except Exception as error:
            raise DemoError(f"cannot download {remote}: {error}") from error
        verify_bytes(data, entry, remote)
        self._check_against_shipped(entry, remote)
        with atomic_open(path) as handle:
            handle.write(data)
        return path

    def download(self, entries: Sequence[ManifestEntry] | None = None, progress: bool = False) -> list[Path]:
        """Fetch and verify ``entries`` (default: every demo of this version)."""
        from bigym.demonstrations.player import progress_bar

        entries = list(self.manifest().entries if entries is None else entries)
        sweep_partial_files(self.download_dir)
        paths = []
        with progress_bar(progress, "downloading demos", len(entries)) as advance:
            for entry in entries:
                paths.append(self.fetch(entry))
                advance()
        return paths

    def _shipped_entry(self, entry: ManifestEntry) -> ManifestEntry | None:
        """The shipped dataset's entry at ``entry``'s path, if the version ships one."""
        from bigym.demonstrations.provision import shipped_entries

        return next((e for e in shipped_entries(self.version, entry.task) if e.path == entry.path), None)

    def _check_against_shipped(self, entry: ManifestEntry, source: str) -> None:
        """A hosted copy of a shipped dataset must serve the shipped bytes, whatever its own manifest says."""
        shipped = self._shipped_entry(entry)
        if shipped is not None and (shipped.sha256, shipped.size) != (entry.sha256, entry.size):
            raise DemoChecksumError(
                f"{source} differs from the dataset {self.version} this bigym ships (sha256 {entry.sha256[:16]}... "
                f"where the shipped manifest says {shipped.sha256[:16]}...); it was not used",
                source=source, expected=shipped.sha256, actual=entry.sha256,
            )  # fmt: skip

    # ------------------------------------------------------------------ demos on demand
    def provide(self, task: str, progress: bool = True, rebuild: Sequence[str] = ()):
        """Complete ``task``'s slice of the shipped dataset in this (local) store.

        Returns a :class:`~bigym.demonstrations.provision.ProvisionReport`, or None when no
        shipped dataset covers the task or the store is remote.
        """
        from bigym.demonstrations.provision import provide_task

        return provide_task(
            self, canonical_task(task), mirror=self.mirror, workers=self.build_workers, progress=progress,
            rebuild=rebuild,
        )  # fmt: skip

    def _can_provide(self, task: str, task_kwargs: dict | None = None) -> bool:
        from bigym.demonstrations.provision import shipped_entries

        return self.on_demand and self.is_local and bool(shipped_entries(self.version, task, task_kwargs))

    def load(self, entry: ManifestEntry | str) -> Demo:
        """The lightweight demo of a manifest entry (or uuid prefix), verified.

        A missing or damaged file of the shipped dataset is made again (demos on demand);
        any other is reported.
        """
        if isinstance(entry, str):
            entry = self.manifest().by_uuid(entry)
        try:
            path = self.fetch(entry)
        except (DemoChecksumError, DemoCorruptError, DemoNotFoundError) as error:
            shipped = self._shipped_entry(entry)
            if not (self.on_demand and self.is_local and shipped is not None and shipped.sha256 == entry.sha256):
                raise
            from bigym.demonstrations.provision import notify

            notify(f"{error}; making it again from the shipped dataset")
            self.provide(entry.task, rebuild=[entry.path])
            path = self.fetch(entry)
        demo = Demo.load(path)
        if demo.uuid != entry.uuid:
            raise DemoCorruptError(f"{path} holds demo {demo.uuid}, the manifest says {entry.uuid}")
        return demo

    # ------------------------------------------------------------------ selection
    def find(
        self, metadata: Metadata, include_failed: bool = False, convert: bool = False
    ) -> tuple[list[ManifestEntry], bool]:
        """Entries usable for ``metadata``, and whether they need an action-mode conversion.

        Raises :class:`DemoNotFoundError` when the store has no demo of the task, and
        :class:`DemoActionModeError` (with the conversion to run) when it has them only for
        another action mode.
        """
        from bigym.demonstrations.convert import check_convertible

        task = canonical_task(metadata.task)
        wanted = normalise_action_mode(metadata.action_mode)
        variant = task_variant(task, metadata.task_kwargs)
        of_task = [e for e in self.entries(task=task) if include_failed or e.success]
        same_task = [e for e in of_task if task_variant(task, e.task_kwargs) == variant]
        if not same_task:
            tasks = sorted({e.task for e in self.manifest().entries})
            known = f"it has demos of {', '.join(tasks)}" if tasks else "it is empty"
            if of_task:
                variants = sorted({json.dumps(task_variant(task, e.task_kwargs), sort_keys=True) for e in of_task})
                known = f"it has {task} demos only for the variants {', '.join(variants)}"
            raise DemoNotFoundError(
                f"no {'' if include_failed else 'successful '}demos of {task} in {self.url} (version "
                f"{self.version}); {known}",
                task=task,
            )
        exact = [e for e in same_task if normalise_action_mode(e.action_mode) == wanted]
        if exact:
            return exact, False
        modes = sorted({json.dumps(normalise_action_mode(e.action_mode), sort_keys=True) for e in same_task})
        recorded = [json.loads(m) for m in modes]
        convertible = []
        for mode in recorded:
            try:
                check_convertible(mode, wanted)
                convertible.append(mode)
            except DemoActionModeError:
                pass
        if convertible and convert:
            usable = [e for e in same_task if normalise_action_mode(e.action_mode) in convertible]
            return usable, True
        listing = "; ".join(
            f"{sum(normalise_action_mode(e.action_mode) == m for e in same_task)} with {describe_action_mode(m)}"
            for m in recorded
        )
        if convertible:
            source = convertible[0]
            kind = "absolute" if source["absolute"] else "delta"
            to = "absolute" if wanted["absolute"] else "delta"
            message = (
                f"{task} demos in {self.url} were recorded with {kind} actions ({listing}), none with "
                f"{describe_action_mode(wanted)}; convert with `bigym demos convert --task {task} --to {to}`, "
                "or pass convert=True to get_demos"
            )
        else:
            message = (
                f"{task} demos in {self.url} exist only for other action modes ({listing}); none can be converted "
                f"to {describe_action_mode(wanted)}"
            )
        raise DemoActionModeError(message, recorded=recorded, requested=wanted)

    def select(
        self, metadata: Metadata, amount: int | None = -1, include_failed: bool = False, convert: bool = False,
        shuffle_seed: int | None = None,
    ) -> tuple[list[ManifestEntry], bool]:  # fmt: skip
        """The first ``amount`` usable entries (sorted by path, or shuffled with ``shuffle_seed``)."""
        if amount == 0:
            return [], False
        try:
            entries, converting = self.find(metadata, include_failed, convert)
        except DemoNotFoundError as error:
            task = canonical_task(metadata.task)
            if isinstance(error, TooManyDemosRequestedError) or not self._can_provide(task, metadata.task_kwargs):
                raise
            self.provide(task)  # demos on demand: the shipped dataset's slice of the task
            entries, converting = self.find(metadata, include_failed, convert)
        if shuffle_seed is not None:
            random.Random(shuffle_seed).shuffle(entries)
        if amount is not None and amount > 0:
            if amount > len(entries):
                raise TooManyDemosRequestedError(
                    f"{amount} demos of {canonical_task(metadata.task)} requested, the store has {len(entries)} "
                    f"for {describe_action_mode(metadata.action_mode)}",
                    available=len(entries),
                )
            entries = entries[:amount]
        return entries, converting

    # ------------------------------------------------------------------ the paper's API
    def get_demos(
        self,
        metadata: Metadata,
        amount: int | None = -1,
        frequency: float | None = None,
        *,
        observation_config: ObservationConfig | dict | None = None,
        convert: bool = False,
        include_failed: bool = False,
        workers: int = 1,
        backend: str = "process",
        progress: bool = False,
        use_cache: bool = True,
        tolerance: float | None = None,
        shuffle_seed: int | None = None,
        episode_only: bool = True,
    ) -> list[ReplayedDemo]:
        """``amount`` demos (all with -1) replayed with ``metadata``'s observations at ``frequency`` Hz.

        ``metadata`` is usually ``Metadata.from_env(env)``: its task, action mode and
        observation config are used, and its control rate when ``frequency`` is None.
        ``convert``: accept demos recorded with the other joint-position mode (absolute /
        delta) and convert them while replaying. Replays are verified (checkpoints, success)
        and cached; ``workers`` > 1 replays cache misses in parallel. ``episode_only=False``:
        each replay holds the whole recording, the steps after its episode's end too
        (``report.episode_steps`` says where the episode ends).
        """
        from bigym.demonstrations.player import replay_many

        entries, converting = self.select(metadata, amount, include_failed, convert, shuffle_seed)
        if not entries:
            return []
        frequency = float(frequency if frequency is not None else metadata.frequency)
        config = observation_config if observation_config is not None else metadata.observation_config
        config = _config_dict(config)
        mode = normalise_action_mode(metadata.action_mode)
        results: list[ReplayedDemo | None] = [None] * len(entries)
        keys = [ReplayCache.key(e.sha256, config, frequency, mode, episode_only) for e in entries]
        if use_cache:
            for index, (entry, key) in enumerate(zip(entries, keys)):
                results[index] = self.replays.get(entry.uuid, key)
        missing = [i for i, r in enumerate(results) if r is None]
        if missing:
            demos = [self.load(entries[i]) for i in missing]

            def store_result(position: int, replayed) -> None:
                index = missing[position]
                results[index] = replayed
                if use_cache and isinstance(replayed, ReplayedDemo):
                    self.replays.put(entries[index].uuid, keys[index], replayed)

            replay_many(
                demos, config, frequency, action_mode=metadata.action_mode if converting else None,
                workers=workers, backend=backend, tolerance=tolerance, progress=progress,
                on_result=store_result, description=f"replaying {canonical_task(metadata.task)}",
                episode_only=episode_only,
            )  # fmt: skip
        return results  # type: ignore[return-value]

    def get_lightweight_demos(
        self, metadata: Metadata, amount: int | None = -1, include_failed: bool = False
    ) -> list[Demo]:
        """``amount`` lightweight demos for ``metadata``'s task and action mode (no replay)."""
        entries, _ = self.select(metadata, amount, include_failed)
        return [self.load(e) for e in entries]

    # ------------------------------------------------------------------ writing
    def add(self, demo: Demo, overwrite: bool = False) -> ManifestEntry:
        """Put ``demo`` into this store (version folder) and its manifest."""
        return self.add_many([demo], overwrite)[0]

    def add_many(self, demos: Iterable[Demo], overwrite: bool = False) -> list[ManifestEntry]:
        """Put several demos into this store, rewriting the manifest once.

        Every demo is checked before anything is written: a duplicate uuid (without
        ``overwrite``) adds nothing at all.
        """
        files: list[tuple[ManifestEntry, bytes]] = []
        for demo in demos:
            meta = demo.metadata
            folder = [canonical_task(meta.task), action_mode_slug(meta.action_mode), frequency_slug(meta.frequency)]
            relative = "/".join([*folder, demo.filename])
            data = demo.to_bytes()
            files.append((ManifestEntry.for_demo(demo, relative, data), data))
        uuids = [entry.uuid for entry, _ in files]
        if len(set(uuids)) != len(uuids):
            raise DemoError("the demos to add repeat a uuid")
        with self._writing() as manifest:
            clashes = {e.uuid for e in manifest.entries} & set(uuids)
            if clashes and not overwrite:
                raise DemoError(
                    f"demo {sorted(clashes)[0]} is already in {self.url}; pass overwrite=True to replace it"
                )
            for entry, data in files:
                self._write(self._remote(self.version, entry.path), data)
            manifest.entries = [e for e in manifest.entries if e.uuid not in set(uuids)] + [e for e, _ in files]
        return [entry for entry, _ in files]

    def remove(self, uuids: Iterable[str]) -> list[ManifestEntry]:
        """Delete demos (by uuid prefix) from this store and its manifest."""
        removed = []
        with self._writing() as manifest:
            for prefix in uuids:
                entry = manifest.by_uuid(prefix)
                with contextlib.suppress(FileNotFoundError):
                    self.fs.rm_file(self._remote(self.version, entry.path))
                manifest.entries = [e for e in manifest.entries if e.uuid != entry.uuid]
                removed.append(entry)
        self.replays.clear([e.uuid for e in removed])
        return removed

    def rebuild_manifest(self) -> Manifest:
        """Scan the version folder and write a manifest of every demo file found."""
        base = self._remote(self.version)
        entries = []
        for remote in sorted(self.fs.find(base)):
            if not remote.endswith(DEMO_SUFFIX) or is_partial(remote):
                continue
            data = self.fs.cat_file(remote)
            demo = Demo.from_bytes(data, remote)
            entries.append(ManifestEntry.for_demo(demo, remote[len(base.rstrip("/")) + 1 :], data))
        with self._writing() as manifest:
            manifest.entries = entries
        return self.manifest()

    @contextlib.contextmanager
    def _writing(self):
        """Read-modify-write the manifest under the store's lock (local) or lease (remote), then the index."""
        with self._lock():
            try:
                manifest = self.manifest(refresh=True)
            except DemoNotFoundError:  # a new remote store: its first demo creates the manifest
                manifest = Manifest(self.version)
            yield manifest
            text = manifest.to_json().encode()
            self._write(self._remote(self.version, MANIFEST_NAME), text)
            if not self.is_local and self.fs.cat_file(self._remote(self.version, MANIFEST_NAME)) != text:
                raise DemoStoreBusyError(
                    f"another writer replaced the manifest of {self.url} while this one wrote it (a writer that "
                    "ignores the write lease?); add the demos again"
                )
            index = self._read_index()
            versions = sorted(set(index.get("versions", [])) | {self.version})
            payload = {"format": STORE_FORMAT, "versions": versions, "latest": max(versions, key=_version_key)}
            self._write(self._remote(INDEX_NAME), json.dumps(payload, indent=1).encode())
            self._manifest = manifest

    @contextlib.contextmanager
    def _lock(self):
        if self.is_local:
            with file_lock(self.version_folder / ".lock"):
                yield
        else:
            with remote_lease(self.fs, self._remote(self.version, ".write-lease"), self.url):
                yield

    def _write(self, remote: str, data: bytes) -> None:
        if self.is_local:
            atomic_write(Path(remote), data)
        else:
            try:
                self.fs.pipe_file(remote, data)
            except Exception as error:
                raise DemoError(f"cannot write {remote}: {error}") from error

    # ------------------------------------------------------------------ cache
    def clear_downloads(self) -> int:
        """Delete this store's download cache; return how many files."""
        removed = 0
        root = self._cache_root / "downloads" / self.store_id
        if root.is_dir():
            for path in sorted(root.rglob("*"), reverse=True):
                if path.is_file():
                    path.unlink()
                    removed += 1
                else:
                    path.rmdir()
            root.rmdir()
        self._manifest = None
        return removed


def _version_key(version: str) -> tuple:
    """Natural order: v2 < v10."""
    import re

    return tuple(int(p) if p.isdigit() else p for p in re.split(r"(\d+)", version))


def _protocols(fs) -> tuple[str, ...]:
    protocol = fs.protocol
    return (protocol,) if isinstance(protocol, str) else tuple(protocol)


def _config_dict(config) -> dict:
    if config is None:
        return ObservationConfig().to_dict()
    if isinstance(config, ObservationConfig):
        return config.to_dict()
    return ObservationConfig.from_dict(config).to_dict()


def verify_bytes(data: bytes, entry: ManifestEntry, source: str) -> None:
    """Size and sha256 against the manifest; then that the bytes parse as safetensors."""
    if len(data) != entry.size:
        kind = "truncated" if len(data) < entry.size else "longer than expected"
        raise DemoChecksumError(
            f"{source} is {kind}: {len(data)} bytes where the manifest says {entry.size} "
            "(an interrupted download or a damaged file; it was not kept)",
            source=source,
            expected=entry.size,
            actual=len(data),
        )
    digest = sha256_bytes(data)
    if digest != entry.sha256:
        raise DemoChecksumError(
            f"checksum mismatch for {source}: sha256 {digest[:16]}... where the manifest says "
            f"{entry.sha256[:16]}... (the file was modified or corrupted; it was not kept)",
            source=source,
            expected=entry.sha256,
            actual=digest,
        )
    read_safetensors(data, source)

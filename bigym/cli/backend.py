"""``--backend`` and ``--ray-address``: the options every command with parallel work shares."""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated

import typer

RayAddressOption = Annotated[
    str | None, typer.Option(help="With --backend ray: a Ray cluster's address (default: $RAY_ADDRESS, else local).")
]


def start_backend(
    backend: str, address: str | None, workers: int | None, fail: Callable[[str], None],
    allowed: tuple[str, ...] = ("process", "ray"),
) -> None:  # fmt: skip
    """Check the options (``fail`` with a message otherwise); for Ray, connect to ``address``
    (or start a local instance with ``workers`` CPUs) now, before any work starts."""
    if backend not in allowed:
        fail(f"--backend must be {' or '.join(repr(b) for b in allowed)}, got {backend!r}")
    if address and backend != "ray":
        fail("--ray-address needs --backend ray")
    if backend == "ray":
        from bigym.scale_out import ensure_ray

        ensure_ray(address, num_cpus=workers)

"""How closely a trained baseline fits its own training samples, as it acts.

Run: ``python benchmarks/baseline_fit.py CHECKPOINT [CHECKPOINT ...] [--store STORE]``.
For each checkpoint it replays the demos it trained on (same task, observations and rate),
builds the acting model (the weight average when the run kept one, dropout off, z = 0, the
demo's own mode when the run has modes; dp samples each chunk from a generator seeded 0, so
the figure repeats) and prints the masked L1 between its chunks and the demos' on every
training sample, in the normalised units of the training loss. The training loss alone
cannot say this: it is measured with dropout and state noise on.
"""

from __future__ import annotations

import argparse
import os

os.environ.setdefault("MUJOCO_GL", "egl")

import torch  # noqa: E402

from bigym.baselines import Checkpoint  # noqa: E402
from bigym.baselines.common import masked_l1  # noqa: E402
from bigym.baselines.data import ChunkDataset  # noqa: E402
from bigym.baselines.train import load_demos  # noqa: E402
from bigym.observations import ObservationConfig  # noqa: E402


def acting_fit(checkpoint: Checkpoint, store=None) -> float:
    """The acting model's masked L1 over all samples of its training demos."""
    config = ObservationConfig.from_dict(checkpoint.observation_config)
    demos, _ = load_demos(checkpoint.task, config, len(checkpoint.demos), checkpoint.frequency, store, 1, False)
    if [demo.uuid for demo in demos] != checkpoint.demos:
        raise ValueError(f"the store's first {len(checkpoint.demos)} {checkpoint.task} demos are not the ones it trained on")
    dataset = ChunkDataset(
        demos, checkpoint.config["chunk"], sorted(checkpoint.image_shapes), checkpoint.make_normalizer(),
        hold_end=checkpoint.config["hold_end"], modes=checkpoint.config.get("modes", 0),
    )  # fmt: skip
    model = checkpoint.build_model().eval()
    total, weight, generator = 0.0, 0, torch.Generator().manual_seed(0)
    with torch.no_grad():
        for start in range(0, len(dataset), 1024):
            batch = dataset.samples(torch.arange(start, min(start + 1024, len(dataset))))
            error = masked_l1(model.predict(batch, generator), batch["actions"], batch["pad"])
            kept = int((~batch["pad"]).sum())
            total, weight = total + error.item() * kept, weight + kept
    return total / weight


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("checkpoints", nargs="+")
    parser.add_argument("--store", default=None, help="demo store (default: the local store)")
    args = parser.parse_args()
    for path in args.checkpoints:
        checkpoint = Checkpoint.load(path)
        print(f"{path}: {checkpoint.method} on {checkpoint.task}, step {checkpoint.step}, "
              f"acting L1 on its training samples {acting_fit(checkpoint, args.store):.4f}")  # fmt: skip


if __name__ == "__main__":
    main()

"""``gmr positions FILE -o OUT.npz``: world positions of every joint for every frame."""

from __future__ import annotations

import argparse
import io

import numpy as np

from gmr_studio.core.atomic import atomic_write_bytes
from gmr_studio.core.cli.reading import add_reading_options, read_with_args
from gmr_studio.core.kinematics.fk import world_positions


def register(parser: argparse.ArgumentParser) -> None:
    parser.description = (
        "Writes positions (F, J, 3) in the file's units and axes, names (J,) in the file's "
        "joint order, and frame_time (seconds)."
    )
    parser.add_argument("file", help="any motion file the project reads")
    parser.add_argument("-o", "--output", required=True, help="the .npz file to write")
    add_reading_options(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    motion = read_with_args(args.file, args)
    buffer = io.BytesIO()
    np.savez(
        buffer,
        positions=world_positions(motion),
        names=np.array(motion.names),
        frame_time=np.float64(motion.frame_time),
    )
    atomic_write_bytes(args.output, buffer.getvalue())
    print(f"{args.output}: {motion.n_frames} frames x {motion.n_joints} joints")
    return 0

"""``gmr curves FILE --joints J1[,J2...] --quantity Q [--frames A:B] -o OUT.csv|OUT.png``.

The quantities of :mod:`core.analysis.curves` (and foot ``contacts``, :mod:`core.analysis.contacts`) for some
joints, over all frames or ``A:B`` (0-based, ``B`` excluded, either end may be left out).
CSV (:mod:`core.analysis.curves_table`): a header row, then one row per frame: ``frame`` (0-based,
in the file), ``time`` (s, :mod:`core.timebase.clock`), then one column per ``JOINT.QUANTITY.AXIS``
(``JOINT.channels.Zrotation``, ``lradius.channels.rx``; ``JOINT.speed``, ``JOINT.contact``
for scalars).
PNG: the same columns plotted against time (matplotlib, from the ``bench`` extra).
"""

from __future__ import annotations

import argparse
import io
from pathlib import Path

import numpy as np

from gmr_studio.core.analysis.contacts import DEFAULT_HEIGHT, DEFAULT_SPEED, foot_contacts, foot_joints
from gmr_studio.core.analysis.curves import ALIASES, QUANTITIES, UNITS, Curves, joint_curves, quantity_name
from gmr_studio.core.analysis.curves_table import curves_csv_text
from gmr_studio.core.atomic import atomic_write_bytes, atomic_write_text
from gmr_studio.core.cli.reading import add_gltf_options, reader_options
from gmr_studio.core.edits.clip import frame_range
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import read_motion_with_channels
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.model.channels import FileChannels
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.timebase.clock import frame_seconds

CLI_QUANTITIES = (*QUANTITIES, *ALIASES, "contacts")


def parse_frames(text: str) -> tuple[int | None, int | None]:
    """``"A:B"``, ``"A:"``, ``":B"`` -> (start, stop) for argparse; B is excluded."""
    start, colon, stop = text.partition(":")
    if not colon:
        raise argparse.ArgumentTypeError(f"expected A:B (0-based, B excluded), not {text!r}")
    try:
        return (int(start) if start.strip() else None, int(stop) if stop.strip() else None)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected whole frame numbers in A:B, not {text!r}") from None


def register(parser: argparse.ArgumentParser) -> None:
    parser.description = (
        "The file's own rotation channels (channels: BVH channels, AMC dofs; alias euler), the GMR "
        "rotation as Euler angles (gmr-euler), its angle and quaternion, local translation GMR-style (local-pre, "
        "R t) or BVH-style (local-post, t), world position, speed, acceleration, or foot contacts (1 planted, "
        "0 not), one row per frame (docs/curves.md says what each means)."
    )
    parser.add_argument("file", help="any motion file the project reads")
    parser.add_argument("--joints", help="comma-separated joint names (default for contacts: the foot joints)")
    parser.add_argument("--quantity", required=True, choices=CLI_QUANTITIES)
    parser.add_argument("--frames", type=parse_frames, metavar="A:B", help="0-based frame range, B excluded")
    parser.add_argument("--height", type=float, default=DEFAULT_HEIGHT, help="contacts: height, fraction of size")
    parser.add_argument("--speed", type=float, default=DEFAULT_SPEED, help="contacts: speed, fraction of size/s")
    parser.add_argument("-o", "--output", required=True, help="a .csv or .png file")
    add_gltf_options(parser)
    parser.set_defaults(run=run)


def curves_for(
    motion: Motion,
    joints: list[str],
    quantity: str,
    *,
    height: float = DEFAULT_HEIGHT,
    speed: float = DEFAULT_SPEED,
    file_channels: FileChannels | None = None,
) -> Curves:
    """The columns ``gmr curves`` writes, over every frame of the motion (``file_channels``:
    the file's own channels, for ``channels``)."""
    needs_positions = quantity in ("world", "speed", "acceleration", "contacts")
    positions = world_positions(motion) if needs_positions else None
    if quantity == "contacts":
        indices = [motion.joint_index(j) for j in joints] if joints else foot_joints(motion)
        if not indices:
            raise OperationError("no foot joints (names with foot, toe, ankle or heel): name them with --joints")
        contacts = foot_contacts(motion, positions, indices, height=height, speed=speed)
        return Curves(tuple(f"{n}.contact" for n in contacts.names), contacts.planted.astype(np.float64), "")
    if not joints:
        raise OperationError(f"--joints is required for {quantity}")
    quantity_name(quantity)
    return Curves.concatenate([joint_curves(motion, j, quantity, positions, file_channels) for j in joints])


def png_bytes(curves: Curves, times: np.ndarray, title: str) -> bytes:
    """The columns plotted against time as a PNG (matplotlib, Agg backend)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        from matplotlib import pyplot
    except ImportError:  # pragma: no cover - matplotlib ships with the bench extra
        raise OperationError(
            "PNG output needs matplotlib (pip install 'gmr-studio[bench]'); write .csv instead"
        ) from None
    figure, axes = pyplot.subplots(figsize=(10, 4.5), dpi=100)
    for column, values in zip(curves.columns, curves.values.T):
        axes.plot(times, values, label=column, linewidth=1.0)
    axes.set_xlabel("time (s)")
    axes.set_ylabel(curves.unit or "value")
    axes.set_title(title)
    axes.grid(alpha=0.3)
    axes.legend(fontsize="small", loc="best")
    figure.tight_layout()
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png")
    pyplot.close(figure)
    return buffer.getvalue()


def run(args: argparse.Namespace) -> int:
    output = Path(args.output)
    if output.suffix.lower() not in (".csv", ".png"):
        raise OperationError(f"the output must be a .csv or .png file, not {output.name!r}")
    motion, channels = read_motion_with_channels(
        args.file, **reader_options(args.file, animation=args.animation, skin=args.skin)
    )
    joints = [j.strip() for j in args.joints.split(",") if j.strip()] if args.joints else []
    curves = curves_for(motion, joints, args.quantity, height=args.height, speed=args.speed, file_channels=channels)
    start, stop = frame_range(motion.n_frames, *(args.frames or (None, None)))
    frames = np.arange(start, stop)
    kept = Curves(curves.columns, curves.values[start:stop], curves.unit)
    if output.suffix.lower() == ".csv":
        atomic_write_text(output, curves_csv_text(kept, frames, motion.frame_time))
    else:
        unit = UNITS.get(ALIASES.get(args.quantity, args.quantity), "")
        title = f"{Path(args.file).name}: {args.quantity}" + (f" ({unit})" if unit else "")
        atomic_write_bytes(output, png_bytes(kept, frame_seconds(frames, motion.frame_time), title))
    print(f"{output}: {len(kept.columns)} columns x {frames.size} frames")
    return 0

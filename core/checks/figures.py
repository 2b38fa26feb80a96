"""The pictures of docs/checks.md: real takes where a check finds something, the quantity it
measures plotted over the frames around it, the frames it reports shaded.

``python -m gmr_studio.core.checks.figures [OUT_DIR]`` (default ``docs/images``) writes
``checks-<kind>.png`` for each of :data:`EXAMPLES` from the shared data (matplotlib, from
the ``bench`` extra).
"""

from __future__ import annotations

import dataclasses
import io
import sys
from pathlib import Path

import numpy as np

from gmr_studio.core.atomic import atomic_write_bytes
from gmr_studio.core.checks import CheckSettings, run_checks
from gmr_studio.core.checks.context import CheckData
from gmr_studio.core.checks.feet import depths
from gmr_studio.core.checks.frames import rest_fractions
from gmr_studio.core.checks.run import check_data
from gmr_studio.core.formats import read_motion
from gmr_studio.core.shared_data import PROJECT_ROOT, shared_file


@dataclasses.dataclass(frozen=True)
class Example:
    """A file of the shared data, a kind, a joint (None: the whole pose), frames to plot."""

    file: str
    kind: str
    joint: str | None
    first: int
    last: int


EXAMPLES = (
    Example("cmu/subject01/01_01.bvh", "foot-skate", "RightToeBase", 2008, 2133),
    Example("cmu/subject01/01_01.bvh", "pop", "LeftToeBase_End", 824, 884),
    Example("bvh/assimp_Boxing_Toes.bvh", "jitter", "Head", 2360, 2440),
    Example("cmu/subject01/01_01.bvh", "penetration", "LeftToeBase", 1990, 2060),
    Example("cmu/subject01/01_01.bvh", "rest-pose", None, 0, 30),
)


def measured(
    example: Example, whole: CheckData, inner: CheckData, settings: CheckSettings, start: int
) -> tuple[np.ndarray, str]:
    """(F,) the quantity the example's check measures at every frame of the file (NaN where
    it does not apply), and its label; ``start``: the first frame reported (a slide is
    measured from there)."""
    values = np.full(whole.n_frames, np.nan)
    inside = slice(inner.first, inner.first + inner.n_frames)
    j = whole.motion.joint_index(example.joint) if example.joint else -1
    units = inner.units
    if example.kind == "foot-skate":
        up = inner.up
        across = [a for a in range(3) if a != up]
        path = inner.positions[:, j][:, across]
        values[inside] = np.linalg.norm(path - path[start - inner.first], axis=-1)
        return values, f"horizontal distance from frame {start} ({units})"
    if example.kind in ("pop", "jitter"):
        values[inner.first + 1 : inner.first + inner.n_frames - 1] = inner.deviations[:, j]
        return values, f"deviation from the neighbours' midpoint ({units})"
    if example.kind == "penetration":
        joints, depth = depths(inner, settings)
        values[inside] = depth[:, list(joints).index(j)]
        return values, f"depth below its contact level ({units})"
    if example.kind == "rest-pose":
        return rest_fractions(whole.motion, settings), "fraction of the moving joints at rest"
    raise ValueError(f"no picture for {example.kind!r}")


def figure(example: Example) -> bytes:
    """The example's picture as PNG bytes."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot

    settings = CheckSettings()
    motion = read_motion(shared_file(example.file))
    whole, inner = check_data(motion, settings)
    shown = [
        f
        for f in run_checks(motion, settings, whole.positions)
        if f.kind == example.kind
        and (example.joint is None or example.joint in f.names)
        and f.end >= example.first
        and f.start <= example.last
    ]
    values, label = measured(example, whole, inner, settings, shown[0].start if shown else example.first)
    frames = np.arange(example.first, example.last + 1)
    figure, axes = pyplot.subplots(figsize=(9, 3.4), dpi=100)
    axes.plot(frames, values[frames], linewidth=1.2, marker=".", markersize=3)
    axes.set_xlim(example.first - 0.5, example.last + 0.5)
    for finding in shown:
        axes.axvspan(finding.start - 0.5, finding.end + 0.5, color="tab:orange", alpha=0.25)
        axes.annotate(
            f"{finding.severity}: {finding.value:.3g} {finding.units}",
            (finding.start, 1.0),
            xycoords=("data", "axes fraction"),
            va="top",
            fontsize="small",
        )
    name = Path(example.file).name
    axes.set_title(f"{name}: {example.kind}" + (f", {example.joint}" if example.joint else ""))
    axes.set_xlabel("frame")
    axes.set_ylabel(label, fontsize="small")
    axes.grid(alpha=0.3)
    figure.tight_layout()
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png")
    pyplot.close(figure)
    return buffer.getvalue()


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    folder = Path(args[0]) if args else PROJECT_ROOT / "docs" / "images"
    for example in EXAMPLES:
        target = folder / f"checks-{example.kind}.png"
        atomic_write_bytes(target, figure(example))
        print(target)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

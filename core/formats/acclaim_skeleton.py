"""The Acclaim skeleton as data: what an ASF file says (:mod:`core.formats.asf` reads it).

Angles are radians inside (files in degrees are converted); lengths are in the file's
units (``:units length`` is kept as data, never applied). How the axes and dofs turn into
rotations: ``docs/formats.md`` ("Acclaim ASF/AMC").
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.rotations.euler import matrix_from_euler

#: the joint name of the Acclaim root, in AMC files and in the GMR motion
ROOT_NAME = "root"
ROTATION_DOFS = ("rx", "ry", "rz")
TRANSLATION_DOFS = ("tx", "ty", "tz")
#: every dof a bone may have; ``l`` stretches the bone along its direction
BONE_DOFS = (*ROTATION_DOFS, *TRANSLATION_DOFS, "l")


@dataclasses.dataclass(frozen=True)
class AcclaimUnits:
    """``:units``: ``mass`` and ``length`` multipliers (kept as data) and the angle unit."""

    mass: float = 1.0
    length: float = 1.0
    angle: str = "deg"  # "deg" or "rad": the unit of every angle in the ASF and, by default, the AMC


@dataclasses.dataclass(frozen=True, eq=False)
class AcclaimBone:
    """One ``begin ... end`` block of ``:bonedata``.

    Attributes
    ----------
    name : str, unique; the AMC names the bone so.
    direction : (3,) float64, unit vector of the bone in the skeleton's (world) axes at rest
        (the file's vector, normalised; zero when the file gives zero).
    length : float, in the file's length units.
    axis : (3,) float64, radians, the angles about x, y and z of the bone's local frame.
    axis_order : str, e.g. ``"XYZ"``: the sequence in which those rotations are applied,
        about fixed axes (so ``C = Rz Ry Rx`` for ``"XYZ"``).
    dof : tuple of str, the degrees of freedom in AMC value order, each one of
        ``rx ry rz tx ty tz l`` (lower case); rotations are applied in this order about
        the axes of the bone's local frame (so ``R = Rz Ry Rx`` for ``rx ry rz``).
    limits : (len(dof), 2) float64, (min, max) per dof as data (radians for rotations,
        length units otherwise; +-inf allowed); NaN where the file gives no limits.
    parent : int, index of the parent bone in :attr:`AcclaimSkeleton.bones`, -1 for the root.
    id : int or None, the file's ``id``.
    bodymass, cofmass : float or None, as written.
    line : int, line of the block's ``begin`` (for messages).
    """

    name: str
    direction: np.ndarray
    length: float
    axis: np.ndarray
    axis_order: str
    dof: tuple[str, ...]
    limits: np.ndarray
    parent: int
    id: int | None = None
    bodymass: float | None = None
    cofmass: float | None = None
    line: int = 0

    @property
    def rotation_dofs(self) -> tuple[str, ...]:
        return tuple(d for d in self.dof if d in ROTATION_DOFS)

    @property
    def axis_rotation(self) -> np.ndarray:
        """(3, 3) ``C``: the bone's local frame in the skeleton's axes."""
        return axis_rotation(self.axis, self.axis_order)


@dataclasses.dataclass(frozen=True, eq=False)
class AcclaimSkeleton:
    """An ASF file. ``bones`` are in ``:bonedata`` order; :attr:`parents` gives the tree.

    Attributes
    ----------
    path : str, the file read.
    name, version, documentation : str, as written ('' when absent).
    units : AcclaimUnits.
    root_order : tuple of str, the root's AMC values in order, from ``tx ty tz rx ry rz``
        (lower case); the rotations apply in this order about fixed axes.
    root_axis : str, the order of ``root_orientation`` (e.g. ``"XYZ"``).
    root_position : (3,) float64, length units.
    root_orientation : (3,) float64, radians, about x, y, z.
    bones : tuple of AcclaimBone.
    """

    path: str
    name: str
    version: str
    units: AcclaimUnits
    documentation: str
    root_order: tuple[str, ...]
    root_axis: str
    root_position: np.ndarray
    root_orientation: np.ndarray
    bones: tuple[AcclaimBone, ...]

    @property
    def names(self) -> tuple[str, ...]:
        """Bone names in ``:bonedata`` order."""
        return tuple(b.name for b in self.bones)

    @property
    def parents(self) -> np.ndarray:
        """(B,) int64: parent bone index per bone, -1 for children of the root."""
        return np.array([b.parent for b in self.bones], dtype=np.int64)

    def bone_index(self, name: str) -> int:
        """Index of a bone in :attr:`bones`; KeyError if there is none."""
        return self.names.index(name)

    @property
    def root_axis_rotation(self) -> np.ndarray:
        """(3, 3) ``C`` of the root, from ``orientation`` and ``axis``."""
        return axis_rotation(self.root_orientation, self.root_axis)


def axis_rotation(angles: np.ndarray, order: str) -> np.ndarray:
    """(3, 3) rotation from angles (3,) radians about x, y, z, applied in ``order`` about
    fixed axes: order ``"XYZ"`` gives ``Rz(z) @ Ry(y) @ Rx(x)``."""
    intrinsic = order[::-1]
    return matrix_from_euler(np.array([angles["XYZ".index(a)] for a in intrinsic]), intrinsic)

"""A file's own rotation channels, as written: what ``channels`` means in curves and the inspector.

A motion file stores each joint's rotation as angles about axes of its own choosing:

- **BVH**: the joint's ``CHANNELS`` rotations (``Zrotation Xrotation Yrotation``), intrinsic
  in file order, about the parent's axes; the rotation turns the bones *leaving* the joint
  (post-rotation). End Sites have none.
- **AMC** (with its ASF): the bone's rotation dofs (``rx ry rz``, maybe only ``rx``), applied
  in file order about the axes of the bone's ASF frame ``C`` (its ``axis``): the rotation of
  the bone *ending* at the joint (GMR's joint, pre-rotation) is ``C R C^T`` with
  ``R = R_last ... R_first``. A one-axis elbow has one column.

:class:`FileChannels` keeps those values (degrees; an AMC in radians is converted), the
channel labels, and how to turn them back into the motion's rotation
(:meth:`FileChannels.rotations`), so that a reader can tell whether the values still
describe a motion (an edit may have changed it). :func:`core.formats.read_motion_with_channels`
returns them with the motion.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.rotations.euler import matrix_from_euler

#: a file's channel values still describe a motion when the rotation they make is within this
#: (max abs matrix entry) of the motion's: exact reads differ by ~1e-15, edits by far more
FILE_MATCH_TOLERANCE = 1e-9


@dataclasses.dataclass(frozen=True, eq=False)
class FileChannels:
    """The rotation channel values of a motion file as written.

    Attributes
    ----------
    orders : joint name -> the axes of its rotation channels in file order (``"ZXY"``,
        ``"X"``); joints without rotation channels (End Sites) are absent.
    angles : joint name -> (F, k) float64 read-only degrees, columns in file order (BVH
        values unwrapped as the file has them: 370 stays 370).
    labels : joint name -> k column labels as the file names them (``Zrotation``, ``rx``);
        by default ``<axis>rotation``.
    kind : ``"bvh"`` (intrinsic in file order, post-rotation: the rotation of the bones
        leaving the joint) or ``"amc"`` (applied in file order about the ASF frame, the
        rotation of the bone ending at the joint).
    axes : joint name -> (3, 3) ASF frame ``C`` of an AMC joint (absent: the identity).
    """

    orders: dict[str, str]
    angles: dict[str, np.ndarray]
    labels: dict[str, tuple[str, ...]] = dataclasses.field(default_factory=dict)
    kind: str = "bvh"
    axes: dict[str, np.ndarray] = dataclasses.field(default_factory=dict)

    @property
    def convention(self) -> str:
        """``"post"`` when a joint's channels turn its children (BVH), ``"pre"`` when they
        turn the bone ending at it (AMC)."""
        return "post" if self.kind == "bvh" else "pre"

    def label_of(self, name: str) -> tuple[str, ...]:
        """The column labels of a joint's channels (``()`` when it has none)."""
        if name not in self.orders:
            return ()
        return self.labels.get(name) or tuple(f"{axis}rotation" for axis in self.orders[name])

    def intrinsic_order(self, name: str) -> str:
        """The Euler order (:mod:`core.rotations.euler`) whose angles are the columns read right to
        left (AMC: applied in file order about fixed axes) or left to right (BVH)."""
        order = self.orders[name]
        return order if self.kind == "bvh" else order[::-1]

    def rotations(self, name: str, frame: int | None = None) -> np.ndarray:
        """(F, 3, 3) the rotation the file's values of ``name`` make, in the motion's axes:
        BVH ``R(channels)``; AMC ``C R C^T``; (3, 3) at one ``frame``."""
        if frame is not None:
            return self._rotations(np.radians(self.angles[name][frame : frame + 1]), name)[0]
        return self._rotations(np.radians(self.angles[name]), name)

    def still_make(self, name: str, rotations: np.ndarray, frame: int | None = None) -> bool:
        """Whether the file's values of ``name`` still make ``rotations``: (F, 3, 3) over every
        frame, or (3, 3) at ``frame`` (an edit may have changed the motion), within
        :data:`FILE_MATCH_TOLERANCE`. The curves and the inspector both ask this."""
        made = self.rotations(name, frame)
        return bool(made.shape == np.shape(rotations) and np.abs(made - rotations).max() <= FILE_MATCH_TOLERANCE)

    def _rotations(self, radians: np.ndarray, name: str) -> np.ndarray:
        if self.kind != "bvh":
            radians = radians[:, ::-1]
        rotation = matrix_from_euler(radians, self.intrinsic_order(name))
        c = self.axes.get(name)
        return rotation if c is None else c @ rotation @ c.T

    def angles_from(self, name: str, rotations: np.ndarray, euler) -> np.ndarray:
        """(F, k) degrees in this joint's channel columns of other rotations (F, 3, 3) (the
        motion's after an edit), by ``euler(rotations, order)`` (continuous degrees)."""
        c = self.axes.get(name)
        local = rotations if c is None else c.T @ rotations @ c
        degrees = euler(local, self.intrinsic_order(name))
        return degrees if self.kind == "bvh" else degrees[:, ::-1]

    def of(self, name: str, frame: int) -> tuple[str, np.ndarray] | None:
        """BVH: (order, (k,) degrees) of a joint at a frame, or None if it has no rotation
        channels (or the file is not a BVH, whose values need :meth:`rotations`)."""
        if name not in self.orders or self.kind != "bvh":
            return None
        return self.orders[name], self.angles[name][frame]

"""Edits of the whole world of a motion: its length unit (``scale_lengths``) and its up axis
(``change_up_axis``), for ``gmr convert --scale --up``, the app's Scale and Up axis edits,
and the readers' options.

Both are changes of the world frame applied consistently to every joint, in either
convention, so that the rest pose, the offsets and the motion all move together:

- scale ``s``: every offset and translation times ``s`` (rotations unchanged); the motion's
  stated unit (:attr:`~core.model.facts.FileFacts.unit`) becomes the unit ``1 / s`` as long;
- up axis: a rotation ``Q`` of the world (:func:`core.space.up_axis.up_turn`).
  ``R'_j = Q R_j Q^T`` for every joint, ``t'_j = Q t_j`` for every offset and translation.
  Then every world position is ``Q P_j`` and every world rotation ``Q W_j Q^T`` (FK of either
  convention commutes with the change of basis), and the rest pose turns with the world.
  Rotation orders swap their Y and Z letters (``ZYX`` -> ``YZX``: ``Q Ry Q^T = Rz`` and
  ``Q Rz Q^T = Ry^-1``), so each joint keeps an equivalent decomposition. The motion's
  stated up axis becomes the target.

Data converted to metres from other units (a glTF export read back) goes back to the unit it
came from with :func:`in_source_unit`, which the writers of formats that cannot state a unit
(BVH) call, so a chain of conversions keeps its first unit.

A note of each edit is added to the motion's comments (provenance, never read back).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.edits.edited import Edited
from gmr_studio.core.kinematics.engine import turned_joints
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.units import unit_factor
from gmr_studio.core.space.up_axis import check_up_axis, up_axis_of, up_turn


def scale_lengths(motion: Motion, factor: float) -> Motion:
    """Every offset and translation times ``factor`` (> 0); the stated unit follows."""
    return scale_lengths_edit(motion, factor).motion


def scale_lengths_edit(motion: Motion, factor: float) -> Edited:
    """:func:`scale_lengths`; every world position is ``factor`` times the input's, every
    world rotation the input's."""
    if not np.isfinite(factor) or factor <= 0:
        raise ValueError(f"the scale must be a positive number, not {factor}")
    if factor == 1:
        return Edited.same_joints(motion)
    facts = motion.facts
    unit = None if facts.unit is None else facts.unit.scaled(factor)
    result = motion.replace(
        offsets=motion.offsets * factor,
        translations=motion.translations * factor,
        comments=(*motion.comments, f"lengths scaled by {factor:.15g}"),
        facts=facts.replace(unit=unit),
    )
    return Edited.same_joints(result, scale=float(factor))


def change_up_axis(motion: Motion, target: str, source: str | None = None) -> Motion:
    """The motion with its world turned so that ``target`` ('y' or 'z') is up.

    ``source``: the motion's up axis (default: :func:`core.space.up_axis.up_axis_of`).
    Nothing turns when they agree (the stated up axis becomes ``target`` either way). Every
    world position ``P`` becomes ``Q P``; see the module docstring.
    """
    return change_up_axis_edit(motion, target, source).motion


def change_up_axis_edit(
    motion: Motion, target: str, source: str | None = None, *, threads: int | None = None
) -> Edited:
    """:func:`change_up_axis`; every world position ``P`` becomes ``Q P`` and every world
    rotation ``W`` becomes ``Q W Q^T`` (``threads``: as for :func:`turned_world`)."""
    source = check_up_axis(source or up_axis_of(motion))
    target = check_up_axis(target)
    if source == target:
        same = motion if motion.facts.up_axis == target else motion.replace(facts=motion.facts.replace(up_axis=target))
        return Edited.same_joints(same)
    swap = str.maketrans("YZ", "ZY")
    mapping = "(x, y, z) -> (x, -z, y)" if target == "z" else "(x, y, z) -> (x, z, -y)"
    turn = up_turn(source, target)
    result = turned_world(motion, turn, threads=threads).replace(
        rotation_orders=tuple(order.translate(swap) for order in motion.rotation_orders),
        comments=(*motion.comments, f"world turned from {source} up to {target} up: {mapping}"),
        facts=motion.facts.replace(up_axis=target),
    )
    return Edited.same_joints(result, turn=turn)


def turned_world(motion: Motion, turn: np.ndarray, *, threads: int | None = None) -> Motion:
    """The motion with its world turned by ``turn`` (3, 3), a rotation or axis permutation:
    every joint's frame conjugated (``R' = Q R Q^T``), every offset and translation turned, so
    every world position is ``Q P``. The stated up axis is left to the caller. An axis
    permutation is one compiled pass over the frames (on ``threads``, None, the default: one per core;
    :func:`core.kinematics.engine.turned_joints`)."""
    turn = np.asarray(turn, dtype=np.float64)
    if np.array_equal(turn, np.eye(3)):
        return motion
    return motion.replace(
        rotations=turned_joints(motion.rotations, turn=turn, threads=threads),
        offsets=motion.offsets @ turn.T,
        translations=turned_joints(motion.translations, turn=turn, threads=threads),
    )


def in_source_unit(motion: Motion) -> Motion:
    """The motion in the unit its data came from (:attr:`~core.model.facts.FileFacts.source_unit`)
    when its facts know both units; else the motion itself."""
    facts = motion.facts
    if facts.source_unit is None or facts.unit is None:
        return motion
    scaled = scale_lengths(motion, unit_factor(facts.unit, facts.source_unit))
    return scaled.replace(facts=facts.replace(unit=facts.source_unit, source_unit=None))

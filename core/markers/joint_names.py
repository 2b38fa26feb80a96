"""Marker maps on skeletons whose joints are named otherwise, through joint-name maps.

A marker map names the joints of the skeleton it was calibrated on (``cmu``: CMU's ASF,
``root``, ``lhipjoint``...). The same capture's BVH names the joint at the same place
otherwise (``Hips``, ``LeftUpLeg``...). :func:`through_joint_map` renames the map's virtual
markers, their ``@NAME`` inputs and its pelvis triple through a joint-name map
(:mod:`core.jointmap`: ``resources/jointmaps/cmu.toml``), so that the map places the other
skeleton's joints; virtual markers the joint map does not pair keep their names and place
nothing. When no joint map pairs the pelvis, :class:`~core.errors.OperationError` says why.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

from gmr_studio.core.errors import OperationError
from gmr_studio.core.markers.markermap import MarkerMap


def through_joint_map(marker_map: MarkerMap, skeleton_names: Sequence[str], joint_map=None) -> MarkerMap:
    """The marker map with its joint names renamed to ``skeleton_names`` (see the module
    docstring); the map itself when it already names the skeleton's joints.

    Parameters
    ----------
    marker_map : a loaded marker map.
    skeleton_names : the joints of the skeleton it is to place.
    joint_map : a joint-name map (name, path or :class:`~core.jointmap.JointMap`); None tries
        every shipped map and takes the one that pairs the pelvis and the most virtual markers.

    Raises
    ------
    OperationError : the map's pelvis joints are not the skeleton's and no joint map pairs them.
    """
    from gmr_studio.core.jointmap import available_joint_maps, match_joints

    names = set(skeleton_names)
    pelvis = marker_map.pelvis or ()
    if not pelvis or all(p in names for p in pelvis):
        return marker_map
    if marker_map.pelvis_home is None and all(v.kind != "cluster" for v in marker_map.virtual):
        return marker_map  # a pelvis-only map (plug-in-gait...): its virtual markers are no joints
    tried = [joint_map] if joint_map is not None else available_joint_maps()
    best, best_count, best_name = None, -1, ""
    for candidate in tried:
        match = match_joints(marker_map.names, list(skeleton_names), candidate)
        renames = {marker_map.names[a]: skeleton_names[b] for a, b in match.pairs}
        if all(p in renames for p in pelvis) and len(renames) > best_count:
            best, best_count = renames, len(renames)
            best_name = getattr(candidate, "name", str(candidate))
    if best is None:
        via = f"joint map {tried[0]!r}" if joint_map is not None else f"any joint map ({', '.join(tried) or 'none'})"
        raise OperationError(
            f"marker map {marker_map.name!r} places the joints of another skeleton ({', '.join(pelvis)} are not "
            f"joints of this one), and {via} does not pair them with this skeleton's joints"
        )
    return rename_joints(marker_map, best, f"joint names through joint map {best_name!r}")


def rename_joints(marker_map: MarkerMap, renames: dict[str, str], how: str) -> MarkerMap:
    """The map with its virtual markers (and ``@NAME`` inputs, pelvis triple) renamed;
    names not in ``renames`` stay; ``how`` is added to the description."""

    def rename(label: str) -> str:
        return "@" + renames.get(label[1:], label[1:]) if label.startswith("@") else label

    taken = set(renames.values())
    clashes = [v.name for v in marker_map.virtual if v.name not in renames and v.name in taken]
    if clashes:
        raise OperationError(f"renaming map {marker_map.name!r}: {', '.join(clashes)} would name two joints")
    virtual = tuple(
        dataclasses.replace(v, name=renames.get(v.name, v.name), markers=tuple(rename(m) for m in v.markers))
        for v in marker_map.virtual
    )
    pelvis = tuple(renames.get(p, p) for p in marker_map.pelvis) if marker_map.pelvis else None
    unpaired = [v.name for v in marker_map.virtual if v.name not in renames]
    note = f"{how}" + (f"; {', '.join(unpaired)} unpaired: they place no joint" if unpaired else "")
    starts = {renames.get(k, k): renames.get(s, s) for k, s in marker_map.bone_starts.items()}
    return marker_map.replace(virtual=virtual, pelvis=pelvis, renamed=note, bone_starts=starts)

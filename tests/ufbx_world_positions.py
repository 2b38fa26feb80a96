"""Runs in a child process: ufbx's own evaluation of an FBX file, the oracle of the FBX tests.

Usage: ``python tests/ufbx_world_positions.py FILE OUT.npz TAKE FRAMES`` writes, for every
node of the file (by name), its world position (the translation of ufbx's ``node_to_world``
after ``evaluate_scene``) at each of the first FRAMES frames of take TAKE (an index), the
frames at the file's frame rate from the take's start, as the reader samples them; and
``keyed``: the frames on which every curve of the take that changes has a key.

ufbx's Python bindings do not count the references of the elements they return (see
core/formats/fbx_in/worker.py), so every element is taken through ``owned``, every scene is
kept, and the process ends with ``os._exit`` once the output is written.
"""

from __future__ import annotations

import os
import sys

import numpy as np
import ufbx

from gmr_studio.core.formats.fbx_in.worker import elements, owned


def keyed_frames(stack, times: np.ndarray, rate: float) -> np.ndarray:
    """(K,) int: the frames (of ``times``) holding a key of every curve of the take whose
    keys do not all hold one value."""
    keyed = np.ones(times.size, bool)
    for layer in elements(stack.layers):
        for value in elements(layer.anim_values):
            for curve in (owned(c) for c in value.curves):
                if curve is None:
                    continue
                keyframes = list(curve.keyframes)
                if len({key.value for key in keyframes}) < 2:
                    continue
                keys = np.array([key.time for key in keyframes])
                at = (keys - times[0]) * rate
                on = np.round(at[np.abs(at - np.round(at)) < 1e-4]).astype(int)
                mask = np.zeros(times.size, bool)
                mask[on[(on >= 0) & (on < times.size)]] = True
                keyed &= mask
    return np.flatnonzero(keyed)


def main(argv: list[str]) -> None:
    source, output, take, n_frames = argv[0], argv[1], int(argv[2]), int(argv[3])
    scenes = [ufbx.load_file(source)]
    stack = owned(elements(scenes[0].anim_stacks)[take])
    rate = scenes[0].settings.frames_per_second
    times = stack.time_begin + np.arange(n_frames) / rate
    names = [node.name for node in elements(scenes[0].nodes) if not node.is_root]
    positions = np.empty((n_frames, len(names), 3))
    for f, time in enumerate(times.tolist()):
        scenes.append(ufbx.evaluate_scene(scenes[0], stack.anim, time))
        nodes = [node for node in elements(scenes[-1].nodes) if not node.is_root]
        for k, node in enumerate(nodes):
            positions[f, k] = node.node_to_world[3]
    np.savez(output, names=np.array(names), positions=positions, times=times, keyed=keyed_frames(stack, times, rate))
    sys.stdout.flush()
    os._exit(0)


if __name__ == "__main__":
    main(sys.argv[1:])

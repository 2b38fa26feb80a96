"""FBX in: the skeleton of an FBX file and one of its takes as a post-rotation motion.

``read_fbx(path, animation=None)``: binary and ASCII FBX (6.1 to 7.7) through ufbx, in a
child process (:mod:`.worker` says why). The joints are the bones, the nodes between them
and the animated nodes above them (a root null that carries the motion); without bones,
every node is a joint (node animation, as glTF's). The take (``animation``: name or
index, default the first) is sampled at the file's frame rate over its time span, layers
blended as the file blends them; FBX's transform stack (pre- and post-rotation, pivots and
offsets, rotation order, inherit type) is ufbx's. Units and axes are the file's
(:func:`.skeleton.file_facts`). Meshes, cameras and lights are left out (a note says so).

:func:`fbx_contents` lists the takes and what the file holds, for ``gmr info``.
Errors: :class:`~core.errors.MotionFileError` naming the file and what was wrong.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from gmr_studio.core.array_transfer import read_arrays
from gmr_studio.core.errors import MotionFileError, input_size, read_input
from gmr_studio.core.formats.fbx_in.skeleton import counted, motion_from_nodes
from gmr_studio.core.model.motion import Motion

WORKER = Path(__file__).with_name("worker.py")
#: exit status of the worker when it refused the file (worker.REJECTED)
REJECTED = 3
#: seconds the child may take: this plus one per MB of file
TIMEOUT_SECONDS = 60.0


def read_fbx(path: str | Path, *, animation: str | int | None = None, data: bytes | None = None) -> Motion:
    """Read an ``.fbx`` file as a post-rotation motion (see the module docstring)."""
    header, arrays = _run(path, data, {"mode": "motion", "animation": None if animation is None else str(animation)})
    try:
        return motion_from_nodes(header["meta"], arrays)
    except ValueError as exc:  # limits of the motion model
        raise MotionFileError(path, str(exc)) from None


def fbx_contents(path: str | Path, data: bytes | None = None) -> dict:
    """``{"takes": [{"index", "name", "begin", "end", "layers"}], "frame_rate", "unit_meters",
    "axes", "nodes", "bones", "meshes", "cameras", "lights", "version", "ascii"}`` (JSON-ready)."""
    return _run(path, data, {"mode": "contents"})[0]["contents"]


def contents_text(contents: dict) -> list[str]:
    """Lines for ``gmr info``: one per take, and what the file holds besides the skeleton."""
    lines = [
        f"take:       {take['index']} '{take['name']}', {take['begin']:.6g} to {take['end']:.6g} s"
        + (f", {len(take['layers'])} layers" if len(take["layers"]) > 1 else "")
        + " (--animation)"
        for take in contents["takes"]
    ]
    if not contents["takes"]:
        lines.append("take:       none (the nodes' pose)")
    held = ", ".join(counted(contents[key], key) for key in ("meshes", "cameras", "lights") if contents[key])
    nodes = f"nodes:      {contents['nodes']} ({contents['bones']} bones)"
    lines.append(nodes + (f"; left out: {held}" if held else ""))
    return lines


# ---------------------------------------------------------------------------- the child
def _run(path: str | Path, data: bytes | None, options: dict) -> tuple[dict, dict[str, np.ndarray]]:
    """The worker's header and arrays for the file (given by its path, or ``data`` through
    the child's stdin), or MotionFileError."""
    source, size, payload = _source(path, data)
    if size == 0:
        raise MotionFileError(path, "the file is empty: expected an FBX file")
    limit = TIMEOUT_SECONDS + size / 1e6
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = env["OPENBLAS_NUM_THREADS"] = "1"
    with tempfile.TemporaryDirectory(prefix="gmr-fbx-") as folder:
        output = Path(folder) / "result.arrays"
        command = [sys.executable, str(WORKER), source, json.dumps({**options, "output": str(output)})]
        try:
            done = subprocess.run(
                command,
                input=payload,
                stdin=subprocess.DEVNULL if payload is None else None,
                capture_output=True,
                timeout=limit,
                env=env,
            )
        except subprocess.TimeoutExpired:
            raise MotionFileError(path, f"ufbx did not finish reading the file in {limit:.0f} s") from None
        message = _last_line(done.stderr.decode("utf-8", "replace"))
        if done.returncode == REJECTED:
            raise MotionFileError(path, message)
        if done.returncode != 0:
            cause = f"signal {-done.returncode}" if done.returncode < 0 else f"exit status {done.returncode}"
            detail = f" ({message})" if done.stderr.strip() else ""
            raise MotionFileError(path, f"ufbx crashed reading the file ({cause}){detail}: the file is corrupt")
        try:
            return read_arrays(output)
        except (OSError, ValueError) as exc:
            raise MotionFileError(path, f"the reader's child process left no result ({exc})") from None


def _source(path: str | Path, data: bytes | None) -> tuple[str, int, bytes | None]:
    """(the worker's FILE argument, the file's size, the bytes for its stdin): the path, which
    ufbx reads itself, or ``-`` and the bytes (given, or a path ufbx cannot take as text)."""
    if data is None:
        size = input_size(path)
        name = os.path.abspath(os.fsdecode(path))  # never "-" or an option
        try:
            name.encode("utf-8")
            return name, size, None
        except UnicodeEncodeError:
            data = read_input(path)
    return "-", len(data), data


def _last_line(text: str) -> str:
    lines = [line.strip() for line in text.strip().splitlines() if line.strip()]
    return lines[-1] if lines else "no reason given"

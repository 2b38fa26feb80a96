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

import contextlib
import json
import os
import subprocess
import sys
import tempfile
import threading
from collections.abc import Iterator
from pathlib import Path

from gmr_studio.core.array_transfer import read_arrays
from gmr_studio.core.errors import MotionFileError, input_size, read_input
from gmr_studio.core.formats.fbx_in.compiled_pose import warm_up
from gmr_studio.core.formats.fbx_in.skeleton import counted, motion_from_nodes
from gmr_studio.core.model.motion import Motion

WORKER = Path(__file__).with_name("worker.py")
#: exit status of the worker when it refused the file (worker.REJECTED)
REJECTED = 3
#: seconds the child may take: this plus one per MB of file
TIMEOUT_SECONDS = 60.0


def read_fbx(path: str | Path, *, animation: str | int | None = None, data: bytes | None = None) -> Motion:
    """Read an ``.fbx`` file as a post-rotation motion (see the module docstring)."""
    options = {"mode": "motion", "animation": None if animation is None else str(animation)}
    warming = threading.Thread(target=_warm_up, daemon=True)  # while the child loads the file
    warming.start()
    with _worker_result(path, data, options) as (header, arrays):
        warming.join()
        try:
            return motion_from_nodes(header["meta"], arrays)
        except ValueError as exc:  # limits of the motion model
            raise MotionFileError(path, str(exc)) from None


def fbx_contents(path: str | Path, data: bytes | None = None) -> dict:
    """``{"takes": [{"index", "name", "begin", "end", "layers"}], "frame_rate", "unit_meters",
    "axes", "nodes", "bones", "meshes", "cameras", "lights", "version", "ascii"}`` (JSON-ready)."""
    with _worker_result(path, data, {"mode": "contents"}) as (header, _):
        return header["contents"]


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
@contextlib.contextmanager
def _worker_result(path: str | Path, data: bytes | None, options: dict) -> Iterator[tuple[dict, dict]]:
    """The worker's header and arrays for the file (its path, or ``data`` written to a
    temporary file), or MotionFileError. The child says it is done by closing its stderr
    once its result is in place; it is waited for on leaving, having released ufbx's
    memory meanwhile (on a long take, gigabytes the system takes a while to reclaim)."""
    with tempfile.TemporaryDirectory(prefix="gmr-fbx-") as folder:
        source, size = _source(path, data, Path(folder))
        if size == 0:
            raise MotionFileError(path, "the file is empty: expected an FBX file")
        limit = TIMEOUT_SECONDS + size / 1e6
        output = Path(folder) / "result.arrays"
        env = dict(os.environ)
        env["OMP_NUM_THREADS"] = env["OPENBLAS_NUM_THREADS"] = "1"
        command = [sys.executable, str(WORKER), source, json.dumps({**options, "output": str(output)})]
        quiet = subprocess.DEVNULL
        child = subprocess.Popen(command, stdin=quiet, stdout=quiet, stderr=subprocess.PIPE, env=env)
        timed_out = threading.Event()
        timer = threading.Timer(limit, lambda: (timed_out.set(), child.kill()))
        try:
            timer.start()
            try:
                stderr = child.stderr.read()  # to its end: the child closes it when done, or exits
            finally:
                timer.cancel()
            if not output.exists():
                _refused_or_crashed(path, child.wait(), stderr.decode("utf-8", "replace"), timed_out.is_set(), limit)
            try:
                result = read_arrays(output)
            except (OSError, ValueError) as exc:
                raise MotionFileError(path, f"the reader's child process left no usable result ({exc})") from None
            yield result
        finally:
            child.stderr.close()
            if child.poll() is None and not output.exists():
                child.kill()  # stopped early (an interrupt): nothing is waiting for its result
            child.wait()


def _warm_up() -> None:
    """The compiled kernels loaded (:func:`.compiled_pose.warm_up`); a failure here is left
    for the reading itself to meet."""
    try:
        warm_up()
    except Exception:  # the read that follows calls the same code and reports what fails
        pass


def _refused_or_crashed(path: str | Path, status: int, stderr: str, timed_out: bool, limit: float) -> None:
    """The MotionFileError of a child that ended without a result."""
    message = _last_line(stderr)
    if timed_out:
        raise MotionFileError(path, f"ufbx did not finish reading the file in {limit:.0f} s")
    if status == REJECTED:
        raise MotionFileError(path, message)
    cause = f"signal {-status}" if status < 0 else f"exit status {status}"
    detail = f" ({message})" if stderr.strip() else ""
    raise MotionFileError(path, f"ufbx crashed reading the file ({cause}){detail}: the file is corrupt")


def _source(path: str | Path, data: bytes | None, folder: Path) -> tuple[str, int]:
    """(the path the worker reads, the file's size): the file itself, or a copy of its
    bytes in ``folder`` (``data`` given, or a path ufbx cannot take as text)."""
    if data is None:
        size = input_size(path)
        name = os.path.abspath(os.fsdecode(path))
        try:
            name.encode("utf-8")
            return name, size
        except UnicodeEncodeError:
            data = read_input(path)
    copy = folder / "input.fbx"
    copy.write_bytes(data)
    return str(copy), len(data)


def _last_line(text: str) -> str:
    lines = [line.strip() for line in text.strip().splitlines() if line.strip()]
    return lines[-1] if lines else "no reason given"

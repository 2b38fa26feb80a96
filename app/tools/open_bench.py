"""``python -m gmr_studio.app.tools.open_bench``: opening a long take (CMU 01_01 tiled to
100,000 frames) of every format in the window, to its first drawn frame, against the floor
of a reader of that format.

The takes: BVH, 01_01's frame lines repeated (:func:`core.benchmark.data.tile_bvh`); AMC,
01_01's frames repeated under its header and renumbered, beside ``01.asf``
(:func:`core.benchmark.data.tile_amc`); glTF, the tiled BVH exported as ``.glb`` by this
project's writer; FBX, the tiled BVH imported and exported by Blender
(:func:`core.benchmark.fbx_speed.made_files`: it needs Blender's Python, ``--bpy``, else the
FBX rows are left out and the reason printed). ``--keep DIR`` keeps the FBX and glb there
and reuses them (Blender's export of 100,000 frames takes minutes); the rest is written to a
temporary folder.

Floors (what no reader of the format can take less than):

- BVH: ``numpy.loadtxt`` of the file's frame lines, as ``gmr bench`` times it;
- AMC: ``numpy.loadtxt`` of the same numbers, each frame's on one line (the bone names and
  frame numbers stripped beforehand: loadtxt needs rows of equal length, and the names are
  the file's framing, as the BVH's header is), so the text parsed is the BVH yardstick's kind;
- glTF: reading the file, parsing its JSON and decoding every animation sampler's input and
  output accessor with ``numpy.frombuffer`` to float64 (the numbers a reader works on;
  without the conversion ``frombuffer`` is a view that reads nothing);
- FBX: ufbx loading the file in a new process and doing nothing else
  (:data:`core.benchmark.fbx_speed.UFBX_LOAD_ONLY`), the floor of any reader on ufbx.

Each format is timed in its own rounds, interleaved (the floor, then each row once), best
round kept (:class:`app.tools.take_bench.Rounds`). Rows: the floor; the read
(``core.formats.read_motion_with_channels``), the conversion to GMR, the FK cache; opening
in the window to its first drawn frame, x floor (goal 2); what starts after that frame (the
checks, the foot contacts) is let finish untimed before the next call. CPU times are this
process's: the FBX reader's and the floor's ufbx run in child processes, not counted. Prints
figures only.
"""

from __future__ import annotations

import argparse
import io
import json
import shutil
import struct
import subprocess
import sys
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gmr_studio.app.tools.take_bench import BVH, MB, Rounds, _load, _row
from gmr_studio.core.shared_data import shared_data_dir

AMC, ASF = "cmu/subject01/01_01.amc", "cmu/subject01/01.asf"
FORMATS = ("BVH", "AMC", "glTF", "FBX")


@dataclass
class Take:
    """One format's long take: its file, its floor (a call) and what the floor is."""

    name: str
    path: Path
    floor: Callable[[], object]
    floor_label: str


def bvh_take(folder: Path, n_frames: int) -> Take:
    from gmr_studio.core.benchmark.data import tile_bvh

    text = tile_bvh(shared_data_dir() / BVH, n_frames)
    block = text.split(b"\nFrame Time:", 1)[1].split(b"\n", 1)[1]  # the frame lines
    path = folder / "take.bvh"
    path.write_bytes(text)
    return Take("BVH", path, lambda: _loadtxt(block), "numpy.loadtxt of the frame lines")


def amc_take(folder: Path, n_frames: int) -> Take:
    from gmr_studio.core.benchmark.data import tile_amc

    text = tile_amc(shared_data_dir() / AMC, n_frames)
    (folder / "amc").mkdir()
    path = folder / "amc" / "01_01.amc"
    path.write_bytes(text)
    shutil.copyfile(shared_data_dir() / ASF, folder / "amc" / "01.asf")
    lines = amc_number_lines(text)
    return Take("AMC", path, lambda: _loadtxt(lines), "numpy.loadtxt of its numbers, a frame a line")


def amc_number_lines(text: bytes) -> bytes:
    """The numbers of an AMC file's frames, each frame's on one line in file order: the
    header, frame numbers and bone names left out."""
    lines = text.replace(b"\r\n", b"\n").split(b"\n")
    frames: list[list[bytes]] = []
    for line in lines:
        words = line.split()
        if not words or words[0].startswith((b":", b"#")):
            continue
        if len(words) == 1 and words[0].isdigit():
            frames.append([])
        elif frames:
            frames[-1].extend(words[1:])
    return b"\n".join(b" ".join(words) for words in frames) + b"\n"


def gltf_take(path: Path) -> Take:
    return Take("glTF", path, lambda: gltf_keys(path), "its animation accessors by numpy.frombuffer")


def gltf_keys(path: Path) -> list[np.ndarray]:
    """Every animation sampler's input and output of a ``.glb`` file as float64 arrays
    (count, components), read with ``json`` and ``numpy.frombuffer`` and nothing else."""
    from gmr_studio.core.formats.gltf_in.container import COMPONENTS, TYPE_SIZES

    data = path.read_bytes()
    json_length = struct.unpack_from("<I", data, 12)[0]
    document = json.loads(data[20 : 20 + json_length])
    binary = memoryview(data)[20 + json_length + 8 :]
    keys = []
    for animation in document.get("animations", []):
        for sampler in animation["samplers"]:
            for index in (sampler["input"], sampler["output"]):
                accessor = document["accessors"][index]
                view = document["bufferViews"][accessor["bufferView"]]
                size = TYPE_SIZES[accessor["type"]]
                offset = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
                dtype = COMPONENTS[accessor["componentType"]][0]
                values = np.frombuffer(binary, dtype, accessor["count"] * size, offset)
                keys.append(values.astype(np.float64).reshape(-1, size))
    return keys


def fbx_take(path: Path) -> Take:
    from gmr_studio.core.benchmark.fbx_speed import UFBX_LOAD_ONLY

    command = [sys.executable, "-c", UFBX_LOAD_ONLY, str(path)]
    return Take("FBX", path, lambda: subprocess.run(command, check=True), "ufbx's load alone, a new process")


def _loadtxt(text: bytes) -> np.ndarray:
    return np.loadtxt(io.BytesIO(text), dtype=np.float64, comments=None, ndmin=2)


def exported_takes(folder: Path, n_frames: int, bpy: Path, keep: Path | None, log) -> tuple[list[Take], str]:
    """The glTF and FBX takes (in ``keep`` when given, else ``folder``), and why the FBX is
    missing ('' when it is not)."""
    from gmr_studio.core.benchmark.fbx_speed import made_files
    from gmr_studio.core.formats.bvh import read_bvh
    from gmr_studio.core.formats.gltf import export_gltf

    where = keep or folder
    where.mkdir(parents=True, exist_ok=True)
    missing = f"no Python with Blender's bpy at {bpy} (--bpy): no FBX take to open"
    if bpy.exists():
        log(f"the FBX and glb takes in {where} (Blender's export takes minutes when they are not there) ...")
        try:
            fbx, glb, seconds = made_files(n_frames, where, bpy)
        except subprocess.CalledProcessError as exc:
            lines = (exc.stderr or b"").decode("utf-8", "replace").strip().splitlines() or ["no message"]
            missing = f"Blender's export failed ({lines[-1]}): no FBX take to open"
        else:
            log("  reused" if seconds is None else f"  Blender exported the FBX in {seconds:.0f} s")
            return [gltf_take(glb), fbx_take(fbx)], ""
    source = read_bvh(shared_data_dir() / BVH)
    glb = folder / "take.glb"
    export_gltf(source.frame_slice(np.arange(n_frames) % source.n_frames), glb)
    return [gltf_take(glb)], missing


def bench_format(take: Take, rounds: int, window_parts, log: Callable[[str], None] = print) -> None:
    """One format's rows: its floor, read, conversion, cache and opening in the window."""
    from gmr_studio.app.model.state import Snapshot
    from gmr_studio.core.formats import read_motion_with_channels
    from gmr_studio.core.kinematics.convention import pre_from_post

    app, window = window_parts
    size = take.path.stat().st_size
    log(f"{take.name}: opening a {size / MB:.0f} MB file, {_load()}")
    post, channels = read_motion_with_channels(take.path)
    gmr = pre_from_post(post)

    def open_to_first_frame() -> None:
        window.files.open_path(str(take.path), ask=False, wait=True)
        window.view.scene.render()
        app.processEvents()

    def deferred_work_done() -> None:  # the checks and contacts that start after the first frame
        while not window.state.shown:
            app.processEvents()
        window.problems.wait()
        app.processEvents()

    timed = Rounds()
    timed.add("floor", take.floor)
    timed.add("read", lambda: read_motion_with_channels(take.path))
    timed.add("convert", lambda: pre_from_post(post))
    timed.add("cache", lambda: Snapshot.of(gmr, file_channels=channels))
    timed.add("open", open_to_first_frame, settle=deferred_work_done)
    timed.run(rounds, log)
    floor = timed.best("floor")[0]
    frames = f"{window.state.snapshot.motion.n_frames} frames x {window.state.snapshot.motion.n_joints} joints"
    print(f"\n{take.name}, {size / MB:.0f} MB, {frames} (best of {rounds} rounds; x floor):")
    print(f"  {take.floor_label + ' (floor)':<58} {timed.line('floor')}")
    for name, label in (
        ("read", f"read the file (core.formats, {take.name} as written)"),
        ("convert", "convert to GMR (pre_from_post)"),
        ("cache", "FK cache (Snapshot.of)"),
    ):
        print(f"  {label:<58} {timed.line(name)}  {timed.best(name)[0] / floor:5.2f} x floor")
    _row(timed, "open", "open in the window to its first drawn frame", floor, "floor", 2.0)


def bench_open(
    n_frames: int,
    rounds: int,
    *,
    formats: Sequence[str] = FORMATS,
    bpy: Path | None = None,
    keep: Path | None = None,
    log: Callable[[str], None] = print,
) -> None:
    """Opening the take of each of ``formats`` (see the module docstring)."""
    from gmr_studio.app.model.loading import load_snapshot
    from gmr_studio.app.tools.bench import bench_window, close_bench_window
    from gmr_studio.core.benchmark.fbx_speed import default_bpy

    with tempfile.TemporaryDirectory(prefix="gmr-open-") as scratch:
        folder = Path(scratch)
        takes, missing = [], ""
        if "BVH" in formats:
            takes.append(bvh_take(folder, n_frames))
        if "AMC" in formats:
            takes.append(amc_take(folder, n_frames))
        if "glTF" in formats or "FBX" in formats:
            exported, missing = exported_takes(folder, n_frames, bpy or default_bpy(), keep, log)
            takes += [take for take in exported if take.name in formats]
        for take in takes:
            load_snapshot(take.path)  # compiled kernels loaded before timing
        app, window, settings = bench_window(1280, 800)
        try:
            for take in takes:
                bench_format(take, rounds, (app, window), log)
        finally:
            close_bench_window(window, settings)
    if missing and "FBX" in formats:
        print(f"\nFBX: left out: {missing}")


def main(argv: Sequence[str] | None = None) -> int:
    prog = "python -m gmr_studio.app.tools.open_bench"
    parser = argparse.ArgumentParser(prog=prog, description=__doc__.split("\n\n")[0].replace("\n", " "))
    parser.add_argument("--frames", type=int, default=100_000, help="frames of the take (100000)")
    parser.add_argument("--rounds", type=int, default=5, help="rounds; each figure keeps its best (5)")
    parser.add_argument("--formats", default=",".join(FORMATS), help="which, comma-separated (BVH,AMC,glTF,FBX)")
    parser.add_argument("--bpy", type=Path, default=None, help="a Python with Blender's bpy module")
    parser.add_argument("--keep", type=Path, default=None, metavar="DIR", help="keep the FBX and glb there, reuse them")
    args = parser.parse_args(argv)
    formats = [name.strip() for name in args.formats.split(",") if name.strip()]
    unknown = [name for name in formats if name not in FORMATS]
    if unknown:
        parser.error(f"unknown format {unknown[0]!r}: expected some of {', '.join(FORMATS)}")
    if not (shared_data_dir() / BVH).exists():
        print(f"the CMU files are not in {shared_data_dir()}: nothing to measure", file=sys.stderr)
        return 2
    from gmr_studio.app.tools.bench import application

    application()  # the window needs the process's QApplication
    bench_open(args.frames, args.rounds, formats=formats, bpy=args.bpy, keep=args.keep)
    print(f"\n{_load()}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

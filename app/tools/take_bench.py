"""``python -m gmr_studio.app.tools.take_bench``: a long take (CMU 01_01 tiled to 100,000
frames, 38 joints) edited, cached, opened and checked, each figure beside its yardstick.

Every row is timed in the same rounds as its yardstick, interleaved (round after round:
the yardsticks, then each row twice in a row), and keeps its best call: the load of other
jobs on the machine then falls on both sides alike, and each side's second call gets
memory freed a moment before, as a copy in a loop does (a virtual machine that hands freed
memory back to its host makes the first touch of memory freed seconds ago several times
slower: the first call meets that, the second the program's own cost). Wall time and the
process's CPU time (every thread, and of it the system's: page faults of new arrays,
mostly) are both given; the ratio of the best wall times is the one the goals speak of.

Yardsticks:
- ``copy R``: one copy of the motion's rotation array (F, J, 3, 3), allocation included;
- ``copy P``: one copy of the FK output (F, J, 3), as ``gmr bench`` times it;
- ``FK 1``: the single-root FK of every frame on one thread, as ``gmr bench`` times it;
- ``parse``: ``numpy.loadtxt`` of the file's frame lines, as ``gmr bench`` times it;
and, beside the FK, one read of what it reads (the largest rotation and translation
number: no FK can take less).

Rows: the FK itself; the cache a document holds (``Snapshot.of``); every edit as the core
operation alone (as a caller of the library gets it: on every core) and as the app's
undoable edit (with the cache of its result), with the undo, and the edit's allocation peak
(tracemalloc) beside what the new motion and its cache take; ``gmr check``; the undo
history after more edits than it keeps; then opening the take of every format in a window
(:mod:`app.tools.open_bench`). Prints figures only.
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import time
from collections.abc import Callable, Sequence

import numpy as np

from gmr_studio.core.shared_data import shared_data_dir

BVH = "cmu/subject01/01_01.bvh"
MB = 1e6


class Rounds:
    """Named calls timed round after round; the best wall seconds of each, and the CPU
    seconds (every thread; of which in the system: page faults, mostly) of that call."""

    def __init__(self) -> None:
        self.calls: dict[str, Callable[[], object]] = {}
        self.settles: dict[str, Callable[[], object] | None] = {}
        self.times: dict[str, list[tuple[float, float, float]]] = {}

    def add(self, name: str, call: Callable[[], object], settle: Callable[[], object] | None = None) -> None:
        """Time ``call``; ``settle`` runs after each call, untimed: it waits for what the
        call left running (so that it is counted in no other call)."""
        self.calls[name] = call
        self.settles[name] = settle
        self.times[name] = []

    def run(self, rounds: int, log: Callable[[str], None], repeats: int = 2) -> None:
        """``rounds`` rounds, each calling every call ``repeats`` times in a row."""
        for round_ in range(rounds):
            for name, call in self.calls.items():
                for _ in range(repeats):
                    start, before = time.perf_counter(), resource.getrusage(resource.RUSAGE_SELF)
                    call()
                    wall, after = time.perf_counter() - start, resource.getrusage(resource.RUSAGE_SELF)
                    system = after.ru_stime - before.ru_stime
                    self.times[name].append((wall, after.ru_utime - before.ru_utime + system, system))
                    if self.settles[name] is not None:
                        self.settles[name]()
            log(f"  round {round_ + 1} of {rounds} done ({_load()})")

    def best(self, name: str) -> tuple[float, float, float]:
        """(wall, CPU, system) seconds of the call with the least wall time."""
        return min(self.times[name])

    def line(self, name: str) -> str:
        wall, cpu, system = self.best(name)
        return f"{wall:7.3f} s  cpu {cpu:6.3f} s (sys {system:5.3f})"


def _load() -> str:
    return "load average " + " ".join(f"{x:.1f}" for x in os.getloadavg())


def tiled_motion(n_frames: int):
    """01_01 as GMR, its frames repeated to ``n_frames`` (an index copy: contiguous arrays)."""
    from gmr_studio.core.formats import load_gmr

    base = load_gmr(shared_data_dir() / BVH)
    index = np.tile(np.arange(base.n_frames), -(-n_frames // base.n_frames))[:n_frames]
    return base.frame_slice(index)


def edits(motion) -> list[tuple[str, str, Callable, Callable]]:
    """(name, source, core operation, app command) of every edit timed: ``source`` names
    the document it starts from ('take', 'split', 'all': split at RightForeArm, split all)."""
    from gmr_studio.app.model import commands
    from gmr_studio.core.edits.clip import resample, trim
    from gmr_studio.core.edits.dummies import remove_dummies
    from gmr_studio.core.edits.mirror import mirror
    from gmr_studio.core.edits.operations import join, join_all, shift_root, split, split_all
    from gmr_studio.core.edits.world import change_up_axis, scale_lengths

    foot, forearm = motion.joint_index("LeftFoot"), motion.joint_index("RightForeArm")
    half = (motion.n_frames // 4, 3 * motion.n_frames // 4)
    return [
        ("shift root to LeftFoot", "take", lambda m: shift_root(m, foot), lambda s: commands.shift_root_to(s, foot)),
        ("split at RightForeArm", "take", lambda m: split(m, forearm), lambda s: commands.split_here(s, forearm)),
        ("join RightForeArm", "split", lambda m: join(m, forearm), lambda s: commands.join_to_parent(s, forearm)),
        ("split all", "take", split_all, commands.split_everything),
        ("join all", "all", join_all, commands.join_everything),
        ("remove dummies", "take", remove_dummies, commands.remove_dummy_joints),
        ("trim to the middle half", "take", lambda m: trim(m, *half), lambda s: commands.trim_to_range(s, *half)),
        ("resample to 60 Hz", "take", lambda m: resample(m, 60.0), lambda s: commands.resample_to(s, 60.0)),
        ("mirror", "take", mirror, commands.mirror_left_right),
        (
            "up axis to Z",
            "take",
            lambda m: change_up_axis(m, "z"),
            lambda s: commands.up_axis_to(s, "z"),
        ),
        (
            "scale by 0.01",
            "take",
            lambda m: scale_lengths(m, 0.01),
            lambda s: commands.scale_by(s, 0.01),
        ),
    ]


def _app_edit(state, command) -> Callable[[], None]:
    """The undoable edit, then its undo (so that every round starts from the same document)."""

    def edit() -> None:
        assert command(state), "the edit was refused"
        state.undo_stack.undo()

    return edit


def bench_take(n_frames: int, rounds: int, log: Callable[[str], None] = print, only: str = "") -> None:
    """Everything but opening (see the module docstring); ``only``: the edits whose name
    holds this text (the yardsticks, FK, cache and check are always timed)."""
    from gmr_studio.app.model.state import Snapshot, StudioState, history_bytes
    from gmr_studio.core.benchmark.timing import peak_memory
    from gmr_studio.core.checks import run_checks
    from gmr_studio.core.edits.operations import split, split_all
    from gmr_studio.core.kinematics import engine as fk_engine

    motion = tiled_motion(n_frames)
    log(f"a take of {motion.n_frames} frames x {motion.n_joints} joints (01_01 tiled), {_load()}")
    sources = {"take": motion, "split": split(motion, "RightForeArm"), "all": split_all(motion)}
    states = {}
    for name, source in sources.items():
        states[name] = StudioState()
        states[name].open_document(Snapshot.of(source), None)
    positions = fk_engine.world_positions(motion)
    timed = Rounds()
    timed.add("copy R", motion.rotations.copy)
    timed.add("copy P", positions.copy)
    timed.add("read", lambda: (motion.rotations.max(), motion.translations.max()))
    timed.add("FK 1", lambda: fk_engine.world_positions(motion))
    timed.add("FK cache", lambda: Snapshot.of(motion))
    timed.add("gmr check", lambda: run_checks(motion))
    rows = [row for row in edits(motion) if only in row[0]]
    for name, source, core, command in rows:
        core(sources[source])  # compiled kernels loaded before timing
        timed.add(f"{name}: core", lambda core=core, m=sources[source]: core(m))
        timed.add(f"{name}: app", _app_edit(states[source], command))
    log(f"timing in {rounds} rounds ...")
    timed.run(rounds, log)
    copy_r, copy_p, fk = (timed.best(name)[0] for name in ("copy R", "copy P", "FK 1"))
    print(f"\nyardsticks (best of {rounds} rounds of two calls in a row; wall s, CPU s of every thread):")
    for name, what in (
        ("copy R", f"one copy of the rotations (F, J, 3, 3), {motion.rotations.nbytes / MB:.0f} MB"),
        ("copy P", f"one copy of the FK output (F, J, 3), {positions.nbytes / MB:.0f} MB"),
    ):
        print(f"  {what:<58} {timed.line(name)}")
    read = f"reading what FK reads once (max of R and of T), {(motion.rotations.nbytes + positions.nbytes) / MB:.0f} MB"
    print(f"  {read:<58} {timed.line('read')}  {timed.best('read')[0] / copy_p:5.2f} x copy P")
    _row(timed, "FK 1", "single-root FK, 1 thread (gmr bench's)", copy_p, "copy P", 2.0)
    _row(timed, "FK cache", "FK cache of a document (Snapshot.of, every core)", fk, "FK 1", 1.5)
    _row(timed, "gmr check", "gmr check (core.checks.run_checks)", fk, "FK 1", 3.0)
    print(
        "\nedits (x copy R; core: the library's operation with its defaults, on every core; "
        "goals: core 1.5, app edit with the cache of its result 2.0):"
    )
    for name, *_ in rows:
        _row(timed, f"{name}: core", f"{name}: core", copy_r, "copy R", 1.5)
        _row(timed, f"{name}: app", f"{name}: app edit + undo", copy_r, "copy R", 2.0)
    print(
        "\nmemory of one app edit (tracemalloc peak: the new arrays it writes, also as copies of R, "
        "which bound its time from below; allowed: the new motion and its cache):"
    )
    for name, source, _core, command in rows:
        state = states[source]
        peak = peak_memory(lambda state=state, command=command: command(state))
        after = state.snapshot
        allowed = after.nbytes
        state.undo_stack.undo()
        start = time.perf_counter()
        state.undo_stack.redo()
        state.undo_stack.undo()
        swap = (time.perf_counter() - start) / 2
        verdict = "within" if peak <= allowed + MB else "over"  # a megabyte for the small arrays
        print(
            f"  {name:<32} peak {peak / MB:5.0f} MB ({peak / motion.rotations.nbytes:4.2f} x R) of "
            f"{allowed / MB:4.0f} MB allowed ({verdict}); "
            f"undo/redo {1000 * swap:.2f} ms"
        )
    _history(states["take"], history_bytes, motion, log)


def _row(timed: Rounds, name: str, label: str, yardstick: float, against: str, goal: float) -> None:
    ratio = timed.best(name)[0] / yardstick
    verdict = "met" if ratio <= goal else "NOT met"
    print(f"  {label:<58} {timed.line(name)}  {ratio:5.2f} x {against:<7} (goal {goal}: {verdict})")


def _history(state, history_bytes, motion, log) -> None:
    """More edits than the history keeps, alternating kinds; what it then holds."""
    from gmr_studio.app.model import commands

    limit = state.undo_stack.undoLimit()
    foot, forearm = motion.joint_index("LeftFoot"), motion.joint_index("RightForeArm")
    steps = [
        lambda: commands.shift_root_to(state, foot),
        lambda: commands.split_here(state, forearm),
        lambda: commands.join_to_parent(state, forearm),
        lambda: commands.mirror_left_right(state),  # a whole new snapshot
    ]
    most = 0
    for k in range(limit + 3):
        steps[k % len(steps)]()
        most = max(most, history_bytes(state))
    held = state.undo_stack.count()
    print(
        f"\nundo history: keeps {limit} edit(s) for this take; after {limit + 3} edits it holds {held}, "
        f"at most {most / 2**30:.2f} GiB with the document (budget 2 GiB)"
    )


def main(argv: Sequence[str] | None = None) -> int:
    prog = "python -m gmr_studio.app.tools.take_bench"
    parser = argparse.ArgumentParser(prog=prog, description=__doc__.split("\n\n")[0].replace("\n", " "))
    parser.add_argument("--frames", type=int, default=100_000, help="frames of the take (100000)")
    parser.add_argument("--rounds", type=int, default=5, help="rounds; each figure keeps its best (5)")
    parser.add_argument("--no-open", action="store_true", help="leave out opening the file in a window")
    parser.add_argument("--only", default="", metavar="TEXT", help="only the edits whose name holds TEXT")
    args = parser.parse_args(argv)
    if not (shared_data_dir() / BVH).exists():
        print(f"the CMU files are not in {shared_data_dir()}: nothing to measure", file=sys.stderr)
        return 2
    from gmr_studio.app.tools import open_bench
    from gmr_studio.app.tools.bench import application

    application()  # the undo stacks and the window need the process's QApplication
    bench_take(args.frames, args.rounds, only=args.only)
    if not args.no_open:
        open_bench.bench_open(args.frames, args.rounds)
    print(f"\n{_load()}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

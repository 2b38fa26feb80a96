"""The benchmark's results as tables, a JSON document and a Figure-4-style plot."""

from __future__ import annotations

import io
import json
from collections.abc import Callable
from pathlib import Path

from gmr_studio.core.atomic import atomic_write_bytes, atomic_write_text

#: what the ratios in the JSON mean
DEFINITIONS = {
    "us_per_frame": "microseconds per frame for the world positions of every joint (best of N runs, "
    "mean over the instances of a configuration)",
    "ratio_to_bvh": "BVH time / this time: how many times faster than the BVH baseline",
    "ratio_to_yardstick": "this time / the time to copy the (F, J, 3) output: 1 is the memory-bound limit",
    "euler_*": "the same, starting from Euler angles as stored instead of rotation matrices cached at load",
    "noise": "(median - best) / best over the repeated runs",
    "relative_error": "largest distance from our positions / the skeleton's size (largest extent at frame 0)",
}


def summary_lines(result: dict) -> list[str]:
    """The closing tables: targets and where they stand, peers, parsing, operations."""
    frames, yard = result["frames"], result["yardstick_us_per_frame"]
    configs = result["configs"]
    full, single = configs[-1], configs[0]
    bvh, bvh_euler = result["bvh_us_per_frame"], result["bvh_euler_us_per_frame"]
    lines = [
        "",
        f"{frames} frames x {result['joints']} joints; best of {result['repeat']} runs, baselines best of "
        f"{result['baseline_runs']['bvh']} spread over the run "
        f"(noise: copy {result['noise']['yardstick']:.0%}, BVH {result['noise']['bvh']:.0%})",
        f"{'path':<52}{'us/frame':>10}{'vs BVH':>10}{'vs copy':>10}",
    ]

    def row(label: str, us: float, base: float | None) -> str:
        faster = f"{base / us:9.2f}x" if base else f"{'':10}"
        return f"{label:<52}{us:10.3f}{faster}{us / yard:9.2f}x"

    lines += [
        row("copy of the (F, J, 3) output (yardstick)", yard, None),
        row("BVH, rotations cached at load", bvh, bvh),
        row("BVH, from Euler angles as stored", bvh_euler, bvh_euler),
        row("BVH, reference core.kinematics.fk (before)", result["reference_bvh_us_per_frame"], bvh),
        row("GMR C_1 single root, cached (mean of instances)", single["us_per_frame"], bvh),
        row("GMR single root (the file's), cached", result["single_root_us_per_frame"], bvh),
        row(
            f"GMR single root (the file's), {result['threads']} threads",
            result["single_root_threads_us_per_frame"],
            bvh,
        ),
        row(f"GMR C_{full['k']} full translational, cached", full["us_per_frame"], bvh),
        row("GMR C_1 single root, from Euler angles", single["euler_us_per_frame"], bvh_euler),
        row(f"GMR C_{full['k']} full translational, from Euler angles", full["euler_us_per_frame"], bvh_euler),
        "",
        "targets:",
        f"  full translational >= 10x faster than BVH: cached {bvh / full['us_per_frame']:.1f}x, "
        f"from Euler angles {bvh_euler / full['euler_us_per_frame']:.1f}x",
        f"  full translational within 2x of the copy: {full['us_per_frame'] / yard:.2f}x",
        f"  single-root GMR within 5x of the copy: {single['us_per_frame'] / yard:.2f}x (C_1 mean), "
        f"{result['single_root_us_per_frame'] / yard:.2f}x (the file's root), "
        f"{result['single_root_threads_us_per_frame'] / yard:.2f}x (the file's root, {result['threads']} threads)",
        f"  parsing >= half of numpy: {result['parse_mb_per_s']:.1f} MB/s vs numpy.loadtxt "
        f"{result['numpy_parse_mb_per_s']:.1f} MB/s ({result['parse_mb_per_s'] / result['numpy_parse_mb_per_s']:.2f}x)",
    ]
    peers = result["peers"]
    if peers:
        lines += ["", f"{'peer':<46}{'frames':>8}{'us/frame':>10}{'ours BVH':>10}{'GMR C_1':>9}{'error/size':>12}"]
        for p in peers:
            if p.get("failure"):
                lines.append(f"{p['name'] + ' ' + p['version']:<46.46}  FAILED: {p['failure']}")
                continue
            ours = bvh_euler if "Euler" in p["starts_from"] else bvh
            us = p["us_per_frame"]
            lines.append(
                f"{p['name'] + ' ' + p['version'] + ', ' + p['starts_from']:<46.46}{p['frames']:>8}"
                f"{us:10.2f}{us / ours:9.1f}x{us / single['us_per_frame']:8.1f}x"
                f"{p['relative_error']:12.1e}{'' if p['agrees'] else '  DISAGREES'}"
            )
        ran = [p for p in peers if not p.get("failure")]
        fastest = min(ran or peers, key=lambda p: p["us_per_frame"])
        lines.append(
            f"  fastest peer {fastest['name']} ({fastest['starts_from']}): ours is "
            f"{fastest['us_per_frame'] / single['us_per_frame']:.1f}x faster with one root, "
            f"{fastest['us_per_frame'] / full['us_per_frame']:.0f}x fully translational"
        )
    ops = result["operations"]
    memory = result["memory"]
    lines += [
        "",
        f"operations on {frames} frames: shift root to {ops['shift_root']['joint']} "
        f"{ops['shift_root']['seconds'] * 1e3:.0f} ms, split {ops['split']['joint']} "
        f"{ops['split']['seconds'] * 1e3:.0f} ms, join it back {ops['join']['seconds'] * 1e3:.0f} ms",
        f"memory: one (F, J, 3, 3) array is {memory['rotations_array_mb']:.0f} MB; FK peak above the input: "
        f"positions {memory['positions_peak_mb']:.0f} MB, with rotations "
        f"{memory['positions_and_rotations_peak_mb']:.0f} MB, "
        f"from Euler {memory['positions_from_euler_peak_mb']:.0f} MB; process max RSS {result['max_rss_mb']:.0f} MB",
    ]
    return lines


def write_json(result: dict, path: Path) -> None:
    document = dict(result, definitions=DEFINITIONS)
    atomic_write_text(path, json.dumps(document, indent=2) + "\n")


def write_plot(result: dict, path: Path, log: Callable[[str], None] = print) -> bool:
    """Time per frame against the number of roots, BVH as lines (Figure 4 of the paper)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        log("no plot: matplotlib is not installed (pip install '.[bench]')")
        return False
    configs = result["configs"]
    ks = [c["k"] for c in configs]
    figure, axes = plt.subplots(figsize=(8, 6), dpi=120)
    low = [c["us_per_frame"] - c["min_us_per_frame"] for c in configs]
    high = [c["max_us_per_frame"] - c["us_per_frame"] for c in configs]
    axes.errorbar(ks, [c["us_per_frame"] for c in configs], yerr=[low, high], fmt="o-", ms=3, capsize=2,
                  color="tab:blue", label="GMR $C_k$, rotations cached (mean, min-max of instances)")  # fmt: skip
    axes.plot(ks, [c["euler_us_per_frame"] for c in configs], "s-", ms=3, color="tab:orange",
              label="GMR $C_k$, from Euler angles as stored")  # fmt: skip
    axes.axhline(result["bvh_us_per_frame"], color="tab:blue", ls="--", label="BVH, rotations cached")
    axes.axhline(result["bvh_euler_us_per_frame"], color="tab:orange", ls="--", label="BVH, from Euler angles")
    axes.axhline(result["yardstick_us_per_frame"], color="gray", ls=":", label="copy of the output (yardstick)")
    axes.set_yscale("log")
    axes.set_xlabel("number of roots k")
    axes.set_ylabel("microseconds per frame (log scale)")
    axes.set_title(f"World positions of {result['joints']} joints, {result['frames']:,} frames")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2, frameon=False)
    figure.tight_layout()
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png")
    plt.close(figure)
    atomic_write_bytes(path, buffer.getvalue())
    return True


def markdown_tables(result: dict) -> str:
    """The run as Markdown tables (what docs/benchmark.md shows)."""
    m, frames, yard = result["machine"], result["frames"], result["yardstick_us_per_frame"]
    bvh, bvh_euler = result["bvh_us_per_frame"], result["bvh_euler_us_per_frame"]
    configs = result["configs"]
    single, full = configs[0], configs[-1]
    out = [
        f"Machine: {m['cpu']}, {m['cores']} cores, Python {m['python']}, numpy {m['numpy']}, "
        f"numba {m.get('numba', 'absent')} (FK backend: {m['fk_backend']}). {frames:,} frames x {result['joints']} "
        f"joints. Best of {result['repeat']} runs for parsing, at most 3 per configuration instance, and "
        f"{result['baseline_runs']['bvh']} for the baselines (copy, BVH, one root), timed in alternation at the "
        "start and again after each k so that bursts of load from other jobs hit every side; noise (median/best - 1): "
        + ", ".join(f"{k} {v:.0%}" for k, v in result["noise"].items())
        + ".",
        "",
        "| path | us/frame | x faster than BVH (same start) | x the copy |",
        "|---|---:|---:|---:|",
        f"| copy of the (F, J, 3) output (yardstick) | {yard:.3f} | | 1.00 |",
        f"| BVH, rotations cached at load | {bvh:.3f} | 1.00 | {bvh / yard:.2f} |",
        f"| BVH, from Euler angles as stored | {bvh_euler:.3f} | 1.00 | {bvh_euler / yard:.2f} |",
        f"| BVH, reference `core.kinematics.fk` (before this work) | {result['reference_bvh_us_per_frame']:.3f} | "
        f"{bvh / result['reference_bvh_us_per_frame']:.2f} | {result['reference_bvh_us_per_frame'] / yard:.2f} |",
        f"| GMR single root (Hips), cached | {result['single_root_us_per_frame']:.3f} | "
        f"{bvh / result['single_root_us_per_frame']:.2f} | {result['single_root_us_per_frame'] / yard:.2f} |",
        f"| GMR single root (Hips), cached, {result['threads']} threads | "
        f"{result['single_root_threads_us_per_frame']:.3f} | {bvh / result['single_root_threads_us_per_frame']:.2f} | "
        f"{result['single_root_threads_us_per_frame'] / yard:.2f} |",
        f"| GMR C_1 (random single root, mean), cached | {single['us_per_frame']:.3f} | {single['ratio_to_bvh']:.2f} "
        f"| {single['ratio_to_yardstick']:.2f} |",
        f"| GMR C_{full['k']} fully translational, cached | {full['us_per_frame']:.3f} | {full['ratio_to_bvh']:.2f} | "
        f"{full['ratio_to_yardstick']:.2f} |",
        f"| GMR C_1, from Euler angles | {single['euler_us_per_frame']:.3f} | {single['euler_ratio_to_bvh']:.2f} | "
        f"{single['euler_us_per_frame'] / yard:.2f} |",
        f"| GMR C_{full['k']}, from Euler angles | {full['euler_us_per_frame']:.3f} | "
        f"{full['euler_ratio_to_bvh']:.2f} | {full['euler_us_per_frame'] / yard:.2f} |",
        "",
        "| k | us/frame (cached) | min-max of instances | x faster than BVH | x the copy | us/frame (Euler) "
        "| x faster than BVH (Euler) |",
        "|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for c in configs:
        out.append(
            f"| {c['k']} | {c['us_per_frame']:.3f} | {c['min_us_per_frame']:.3f}-{c['max_us_per_frame']:.3f} | "
            f"{c['ratio_to_bvh']:.2f} | {c['ratio_to_yardstick']:.2f} | {c['euler_us_per_frame']:.3f} | "
            f"{c['euler_ratio_to_bvh']:.2f} |"
        )
    if result["peers"]:
        out += [
            "",
            "| peer | starts from | frames timed | us/frame | x ours, BVH same start | x ours, GMR C_1 | "
            "x ours, GMR C_J | max error / size |",
            "|---|---|---:|---:|---:|---:|---:|---:|",
        ]
        for p in result["peers"]:
            if p.get("failure"):
                out.append(f"| {p['name']} {p['version']} | FAILED: {p['failure']} | | | | | | |")
                continue
            ours = bvh_euler if "Euler" in p["starts_from"] else bvh
            us = p["us_per_frame"]
            out.append(
                f"| {p['name']} {p['version']} | {p['starts_from']} | {p['frames']:,} | {us:.2f} | {us / ours:.1f} | "
                f"{us / single['us_per_frame']:.1f} | {us / full['us_per_frame']:.0f} | {p['relative_error']:.1e} |"
            )
    ops, mem = result["operations"], result["memory"]
    out += [
        "",
        f"Parsing: `read_bvh` {result['parse_mb_per_s']:.1f} MB/s ({result['parse_ms']:.0f} ms), `numpy.loadtxt` of "
        f"the frame lines {result['numpy_parse_mb_per_s']:.1f} MB/s ({result['numpy_parse_ms']:.0f} ms): "
        f"{result['parse_mb_per_s'] / result['numpy_parse_mb_per_s']:.2f}x.",
        "",
        f"Operations on {frames:,} frames: shift root to {ops['shift_root']['joint']} "
        f"{ops['shift_root']['seconds'] * 1e3:.0f} ms; split {ops['split']['joint']} "
        f"{ops['split']['seconds'] * 1e3:.0f} ms; join it back {ops['join']['seconds'] * 1e3:.0f} ms.",
        "",
        f"Memory: one (F, J, 3, 3) float64 array is {mem['rotations_array_mb']:.0f} MB. Peak allocated by FK above its "
        f"input (tracemalloc): positions {mem['positions_peak_mb']:.0f} MB, positions and rotations "
        f"{mem['positions_and_rotations_peak_mb']:.0f} MB, positions from Euler angles "
        f"{mem['positions_from_euler_peak_mb']:.0f} MB. Whole benchmark process: max RSS "
        f"{result['max_rss_mb']:.0f} MB.",
        "",
        f"Agreement: engine vs reference {result['engine_vs_reference_error']:.1e} of the size; every configuration's "
        f"positions vs the one-root motion at most {max(c['max_position_error'] for c in configs):.1e} of the size.",
    ]
    return "\n".join(out) + "\n"

"""``gmr audit FILE``: the round-trip auditor (core/compare/audit.py, docs/compare.md).

Runs FILE through every path the project offers and prints, per path, the worst position
error relative to the skeleton's size against the documented tolerance. Exit 1 when a path
exceeds it (or fails, or loses joints), 0 otherwise, 2 for an unreadable file.
"""

from __future__ import annotations

import argparse
import json

from gmr_studio.core.atomic import atomic_write_text
from gmr_studio.core.cli.reading import add_gltf_options, reader_options
from gmr_studio.core.compare.audit import audit_motion
from gmr_studio.core.formats import read_motion


def register(parser: argparse.ArgumentParser) -> None:
    parser.description = (
        "GMR in memory, GMR file, BVH file, forest export after split all, glTF file (also of "
        "the forest), dummy removal and "
        "back, shift root to every k-th joint, split all / join all, and the ASF rest pose for an AMC: the "
        "worst position error of each, relative to the skeleton's size, against its documented tolerance."
    )
    parser.add_argument("file", help="any motion file the project reads")
    parser.add_argument("--asf", help="the .asf skeleton of an .amc (default: the one beside it)")
    add_gltf_options(parser)
    parser.add_argument("--every", type=int, default=5, help="shift the root to every K-th joint (default 5)")
    parser.add_argument("--json", metavar="OUT", help="write the paths as JSON")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    motion = read_motion(args.file, **reader_options(args.file, args.asf, animation=args.animation, skin=args.skin))
    paths = audit_motion(motion, args.file, every=args.every)
    width = max(len(p.name) for p in paths)
    print(f"{args.file}: {motion.n_frames} frames, {motion.n_joints} joints, size {motion.size:.6g}")
    print(f"{'path':<{width}}  {'max error':>10}  {'relative':>9}  {'tolerance':>9}  result  worst joint")
    for p in paths:
        verdict = "ok" if p.ok else "FAIL"
        line = f"{p.name:<{width}}  {p.max_error:>10.3g}  {p.relative_error:>9.2e}  {p.tolerance:>9.0e}  {verdict:<6}  "
        line += f"{p.worst_joint} (frame {p.worst_frame})" if p.worst_joint else "-"
        if p.lost_joints:
            line += f"; lost {', '.join(p.lost_joints)}"
        if p.error:
            line += f"; {p.error}"
        print(line)
    failed = [p for p in paths if not p.ok]
    print(f"{len(paths) - len(failed)} of {len(paths)} paths within tolerance")
    if args.json:
        document = {"file": args.file, "size": motion.size, "paths": [p.to_json() for p in paths]}
        atomic_write_text(args.json, json.dumps(document, indent=1) + "\n")
        print(f"wrote {args.json}")
    return 1 if failed else 0

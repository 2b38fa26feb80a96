"""Fuzz targets for ASF skeletons and AMC motions (an AMC is read against the unmutated
ASF beside its seed file)."""

from __future__ import annotations

import re
from functools import cache
from pathlib import Path

from gmr_studio.core.formats.acclaim import asf_beside, read_asf_file
from gmr_studio.core.formats.amc import read_amc
from gmr_studio.core.formats.asf import read_asf
from gmr_studio.core.fuzz.mutations import line_starts
from gmr_studio.core.fuzz.targets import SEED_FRAMES, Target, _shared
from gmr_studio.core.shared_data import shared_data_dir


@cache
def asf_seeds() -> list[tuple[str, bytes]]:
    return [(path.name, path.read_bytes()) for path in _shared("**/*.asf")]


@cache
def amc_seeds() -> list[tuple[str, bytes]]:
    seeds = []
    for path in _shared("**/*.amc"):
        data = path.read_bytes()
        # the header and SEED_FRAMES frames (a frame starts with a line holding only its number)
        starts = [m.start() for m in re.finditer(rb"(?m)^\d+[ \t]*\r?$", data)]
        end = starts[SEED_FRAMES] if len(starts) > SEED_FRAMES else len(data)
        seeds.append((str(path.relative_to(shared_data_dir())), data[:end]))
    return seeds


@cache
def _skeleton_beside(amc_label: str):
    return read_asf(asf_beside(shared_data_dir() / amc_label))


def _read_asf(path: Path, data: bytes, seed: str):
    return read_asf_file(path, data)


def _read_amc(path: Path, data: bytes, seed: str):
    return read_amc(path, _skeleton_beside(seed), data=data)


def targets(mutations, check_motion) -> dict[str, Target]:
    return {
        "asf": Target("asf", ".asf", asf_seeds, _read_asf, check_motion, mutations, structure=line_starts),
        "amc": Target("amc", ".amc", amc_seeds, _read_amc, check_motion, mutations),
    }

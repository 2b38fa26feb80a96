"""Shared fixtures: the real data folder, small synthetic motions, tolerances, and the
hypothesis profiles.

Hypothesis runs under one of two profiles: ``ci`` (derandomised: the examples are derived
from each test's source, so a red run is red again on replay, and no example database) when
the environment sets ``CI`` or ``GMR_REQUIRE_GUI`` (as the README's test command does), else
``dev`` (random examples every run, to keep finding new cases locally). ``HYPOTHESIS_PROFILE``
picks one explicitly.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pytest
from hypothesis import settings

from gmr_studio.core.model.motion import Motion, build_translations
from gmr_studio.core.rotations.euler import matrix_from_euler
from gmr_studio.core.shared_data import shared_data_dir

settings.register_profile("ci", derandomize=True, database=None, print_blob=True)
settings.register_profile("dev", derandomize=False)


def hypothesis_profile(environ: Mapping[str, str] = os.environ) -> str:
    """The hypothesis profile for an environment (see the module docstring)."""
    if environ.get("HYPOTHESIS_PROFILE"):
        return environ["HYPOTHESIS_PROFILE"]
    return "ci" if environ.get("CI") or environ.get("GMR_REQUIRE_GUI") else "dev"


settings.load_profile(hypothesis_profile())

DATA = shared_data_dir()
MISSING_DATA = f"the real data folder {DATA} is absent (it ships with CI, not with a fresh clone)"


def shared_files(pattern: str) -> list:
    """pytest params for the shared files matching ``pattern``: one skipping param when the
    data folder is absent; when it is present but nothing matches, one param naming the
    missing pattern, so that the test fails (a missing file is a failure, not a skip)."""
    if not DATA.is_dir():
        return [pytest.param(None, marks=pytest.mark.skip(reason=MISSING_DATA), id="no-data")]
    files = sorted(DATA.glob(pattern))
    if not files:
        return [pytest.param(DATA / f"MISSING {pattern}", id=f"missing:{pattern}")]
    return [pytest.param(f, id=str(f.relative_to(DATA))) for f in files]


def shared_path(relative: str) -> Path:
    """A file of the shared data. Skips the test when the data folder is absent; fails it
    when the folder is present but the file is not."""
    path = DATA / relative
    if not DATA.is_dir():
        pytest.skip(MISSING_DATA)
    if not path.exists():
        pytest.fail(f"{path} is missing, though the data folder {DATA} is present")
    return path


def random_motion(
    rng: np.random.Generator,
    parents: list[int],
    n_frames: int = 3,
    convention: str = "pre",
    translation_joints: tuple[int, ...] = (),
    angle: float = np.pi,
) -> Motion:
    """A motion with random offsets and rotations on the given tree (roots translate)."""
    n = len(parents)
    offsets = rng.normal(size=(n, 3))
    channels = {j: rng.normal(size=(n_frames, 3)) * 5 for j in range(n) if parents[j] < 0 or j in translation_joints}
    orders = [str(rng.choice(["XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"])) for _ in range(n)]
    rotations = np.stack(
        [matrix_from_euler(rng.uniform(-angle, angle, (n_frames, 3)), orders[j]) for j in range(n)], axis=1
    )
    flags = np.zeros(n, bool)
    flags[list(channels)] = True
    return Motion(
        names=[f"j{j}" for j in range(n)],
        parents=parents,
        offsets=offsets,
        rotation_orders=orders,
        has_translation=flags,
        rotations=rotations,
        translations=build_translations(n_frames, offsets, channels),
        frame_time=1 / 30,
        convention=convention,
    )


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261121)


def _have_display() -> bool:
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY") or os.environ.get("QT_QPA_PLATFORM"))


def pytest_collection_modifyitems(config, items):
    """GUI tests need a display. Without one they are skipped, saying how to run them,
    unless GMR_REQUIRE_GUI=1 (as CI sets): then they fail, never skip."""
    if _have_display():
        return
    if os.environ.get("GMR_REQUIRE_GUI") == "1":
        raise pytest.UsageError("GMR_REQUIRE_GUI=1 but there is no display: run the tests under xvfb-run")
    skip = pytest.mark.skip(reason="no display: run under xvfb-run (the README's test command does)")
    for item in items:
        if "gui" in item.keywords:
            item.add_marker(skip)

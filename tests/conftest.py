"""Shared fixtures: the real data folder, small synthetic motions, tolerances."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gmr_studio.core.motion import Motion, build_translations
from gmr_studio.core.rotations import matrix_from_euler
from gmr_studio.core.shared_data import shared_data_dir

DATA = shared_data_dir()
MISSING_DATA = f"the real data folder {DATA} is absent (it ships with CI, not with a fresh clone)"


def shared_files(pattern: str) -> list:
    """pytest params for the shared files matching ``pattern``; one skipping param if none."""
    files = sorted(DATA.glob(pattern)) if DATA.is_dir() else []
    if not files:
        return [pytest.param(None, marks=pytest.mark.skip(reason=MISSING_DATA), id="no-data")]
    return [pytest.param(f, id=str(f.relative_to(DATA))) for f in files]


def shared_path(relative: str) -> Path:
    """A file of the shared data; skips the test when the folder is absent."""
    path = DATA / relative
    if not path.exists():
        pytest.skip(MISSING_DATA if not DATA.is_dir() else f"{path} is missing")
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
    import os

    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY") or os.environ.get("QT_QPA_PLATFORM"))


def pytest_collection_modifyitems(config, items):
    """GUI tests need a display. Without one they are skipped, saying how to run them,
    unless GMR_REQUIRE_GUI=1 (as CI sets): then they fail, never skip."""
    import os

    if _have_display():
        return
    if os.environ.get("GMR_REQUIRE_GUI") == "1":
        raise pytest.UsageError("GMR_REQUIRE_GUI=1 but there is no display: run the tests under xvfb-run")
    skip = pytest.mark.skip(reason="no display: run under xvfb-run (the README's test command does)")
    for item in items:
        if "gui" in item.keywords:
            item.add_marker(skip)

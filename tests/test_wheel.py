"""The installed package: build the wheel, install it into a fresh virtual environment outside
the checkout, and run the command line and the app from there (issue 15, part 1).

Offline and quick: the wheel is built without build isolation (setuptools comes with the
``test`` extra) from a copy of the sources, and installed with ``--no-deps`` into a venv whose
only other path is the test environment's site-packages (for numpy, PyQt6, ...). That path is
added by a ``.pth`` line, so the test environment's own ``.pth`` files, among them the editable
install of the checkout, are not processed: ``gmr_studio`` can only come from the wheel, and
the test checks that it does.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import shared_path

ROOT = Path(__file__).resolve().parent.parent
SOURCES = ("pyproject.toml", "README.md", "core", "app", "resources")


def run(command: list[str], cwd: Path, **kwargs) -> subprocess.CompletedProcess:
    environment = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    return subprocess.run(command, cwd=cwd, env=environment, capture_output=True, text=True, timeout=180, **kwargs)


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> tuple[Path, Path, Path]:
    """(the wheel, the fresh venv's bin folder, a working folder outside the checkout)."""
    base = tmp_path_factory.mktemp("wheel")
    source = base / "source"
    for name in SOURCES:
        path = ROOT / name
        if path.is_dir():
            shutil.copytree(path, source / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        else:
            source.mkdir(exist_ok=True)
            shutil.copy2(path, source / name)
    wheels = base / "dist"
    built = run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            str(source),
            "--no-deps",
            "--no-build-isolation",
            "-q",
            "-w",
            str(wheels),
        ],
        cwd=base,
    )
    assert built.returncode == 0, built.stderr
    (wheel,) = wheels.glob("*.whl")
    venv = base / "venv"
    made = run([sys.executable, "-m", "venv", "--without-pip", str(venv)], cwd=base)
    assert made.returncode == 0, made.stderr
    fresh_python = venv / "bin" / "python"
    site = run([str(fresh_python), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"], cwd=base)
    (Path(site.stdout.strip()) / "test_dependencies.pth").write_text(sysconfig.get_path("purelib") + "\n")
    pip = [sys.executable, "-m", "pip", "--python", str(fresh_python), "install", "--no-deps", "--no-index", "-q"]
    done = run([*pip, str(wheel)], cwd=base)
    assert done.returncode == 0, done.stderr
    work = base / "work"
    work.mkdir()
    return wheel, venv / "bin", work


def test_wheel_holds_only_gmr_studio(installed):
    wheel, _, _ = installed
    with zipfile.ZipFile(wheel) as archive:
        names = archive.namelist()
    top = {name.split("/", 1)[0] for name in names}
    assert top == {"gmr_studio", "gmr_studio-0.1.0.dist-info"}
    for resource in ("resources/demo/", "resources/icons/", "resources/markermaps/", "resources/styles/"):
        assert any(name.startswith(f"gmr_studio/{resource}") for name in names), resource


def test_the_package_comes_from_the_wheel(installed):
    _, bin_folder, work = installed
    where = run(
        [str(bin_folder / "python"), "-c", "import gmr_studio.core, sys; print(gmr_studio.core.__file__)"], work
    )
    assert where.returncode == 0, where.stderr
    assert Path(where.stdout.strip()).is_relative_to(bin_folder.parent)
    assert not Path(where.stdout.strip()).is_relative_to(ROOT)


def test_gmr_info_and_convert_from_the_wheel(installed):
    _, bin_folder, work = installed
    source = shared_path("cmu/subject01/01_01.bvh")
    info = run([str(bin_folder / "gmr"), "info", str(source), "--json"], work)
    assert info.returncode == 0, info.stderr
    assert json.loads(info.stdout)["frames"] == 2752
    converted = run([str(bin_folder / "gmr"), "convert", str(source), "walk.gmr"], work)
    assert converted.returncode == 0, converted.stderr
    from gmr_studio.core.formats import read_motion
    from gmr_studio.core.kinematics.fk import world_positions

    written = read_motion(work / "walk.gmr")
    assert written.convention == "pre" and written.n_frames == 2752
    np.testing.assert_allclose(world_positions(written), world_positions(read_motion(source)), atol=1e-9)


@pytest.mark.gui
def test_gmr_studio_screenshot_of_the_demo_from_the_wheel(installed):
    _, bin_folder, work = installed
    shot = work / "demo.png"
    made = run([str(bin_folder / "gmr-studio"), "--screenshot", str(shot), "--size", "640x400"], work)
    assert made.returncode == 0, made.stderr
    from PyQt6.QtGui import QImage

    from gmr_studio.app.media.video import image_pixels

    image = QImage(str(shot))
    assert (image.width(), image.height()) == (640, 400)
    pixels = image_pixels(image)
    assert np.unique(pixels.reshape(-1, 3), axis=0).shape[0] > 50  # a drawn scene, not a blank image


def test_the_readme_library_example_runs_from_the_wheel(installed):
    """The README's library example (its imports name gmr_studio) runs as written."""
    _, bin_folder, work = installed
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("## The library", 1)[1]
    example = section.split("```python\n", 1)[1].split("```", 1)[0]
    assert "from gmr_studio.core" in example and "from core" not in example
    shutil.copy(shared_path("cmu/subject01/01_01.bvh"), work / "01_01.bvh")
    ran = run([str(bin_folder / "python"), "-c", example], work)
    assert ran.returncode == 0, ran.stderr
    assert (work / "feet.gmr").exists()

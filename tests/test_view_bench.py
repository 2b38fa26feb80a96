"""The view bench runs and prints its figures side by side (not a timing test: no figure is
asserted, only that every one is measured)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from tests.conftest import shared_path

pytestmark = pytest.mark.gui


def test_the_view_bench_prints_every_figure():
    shared_path("cmu/subject01/01_01.bvh")  # skips, saying why, without the shared data
    command = [sys.executable, "-m", "gmr_studio.app.tools.view_bench", "--size", "800x500", "--frames", "6"]
    command += ["--rounds", "2"]
    result = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    out = result.stdout
    figures = ("bare VTK widget", "x bare", "+ axes, trail, labels", "+ one comparison layer", "inspector text")
    for text in (*figures, "renders a frame (default figure): "):
        assert text in out, out
    assert "native widget" in out and "framebuffer widget" in out and "failed" not in out, out
    # every figure with the Curves tab in front (adding a layer raises the Error tab over it)
    assert out.count("docks shown: Curves, Forest, Inspector, Timeline; with the layer: Curves,") == 2, out

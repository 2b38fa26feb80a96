"""Every ``gmr`` command that reads a motion takes the same reading options (core.cli.reading)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gmr_studio.core.cli import build_parser, main
from gmr_studio.core.formats import load_gmr, read_motion
from gmr_studio.core.kinematics.fk import world_positions
from tests.conftest import shared_path

#: subcommand -> arguments that make a complete command line with a motion file FILE
MOTION_COMMANDS = {
    "info": ["FILE"],
    "positions": ["FILE", "-o", "OUT.npz"],
    "edit": ["FILE", "-o", "OUT.gmr"],
    "convert": ["FILE", "OUT.gmr"],
    "check": ["FILE"],
    "markers": ["M.c3d", "--skeleton", "S.asf", "--reference", "FILE", "-o", "OUT.gmr"],
}


@pytest.fixture
def amc_apart(tmp_path):
    """CMU 01_01.amc linked into a folder without its .asf, and the .asf elsewhere."""
    amc = shared_path("cmu/subject01/01_01.amc")
    asf = shared_path("cmu/subject01/01.asf")
    (tmp_path / "motion").mkdir()
    (tmp_path / "skeleton").mkdir()
    (tmp_path / "motion" / "walk.amc").symlink_to(amc)
    (tmp_path / "skeleton" / "subject.asf").symlink_to(asf)
    return tmp_path / "motion" / "walk.amc", tmp_path / "skeleton" / "subject.asf"


@pytest.mark.parametrize("command", sorted(MOTION_COMMANDS))
def test_every_motion_command_takes_the_reading_options(command):
    argv = [command, *MOTION_COMMANDS[command], "--asf", "S.asf", "--frame-rate", "60"]
    if command != "markers":  # its --scale is marker units to skeleton units
        argv += ["--scale", "2.54", "--up", "z", "--from-up", "y"]
    args = build_parser().parse_args(argv)
    assert args.asf == "S.asf"
    assert args.frame_rate == 60.0
    if command != "markers":
        assert (args.scale, args.up, args.from_up) == (2.54, "z", "y")


def test_positions_scaled_and_turned_like_convert(capsys, tmp_path):
    bvh = shared_path("cmu/subject01/01_01.bvh")
    out = tmp_path / "positions.npz"
    assert main(["positions", str(bvh), "-o", str(out), "--scale", "0.0254", "--up", "z"]) == 0
    converted = tmp_path / "walk.gmr"
    assert main(["convert", str(bvh), str(converted), "--scale", "0.0254", "--up", "z"]) == 0
    expected = world_positions(read_motion(converted))
    original = world_positions(read_motion(bvh))
    positions = np.load(out)["positions"]
    np.testing.assert_allclose(positions, expected, rtol=0, atol=1e-12)
    # Y up in inches -> Z up in metres: z' = 0.0254 y, and lengths scale alike
    np.testing.assert_allclose(positions[..., 2], 0.0254 * original[..., 1], rtol=0, atol=1e-12)


def test_positions_of_an_amc_with_its_asf_elsewhere(capsys, amc_apart, tmp_path):
    amc, asf = amc_apart
    out = tmp_path / "positions.npz"
    # without --asf there is no skeleton beside the file: a one-line error, exit code 2
    assert main(["positions", str(amc), "-o", str(out)]) == 2
    assert "asf" in capsys.readouterr().err.lower()
    assert main(["positions", str(amc), "-o", str(out), "--asf", str(asf), "--frame-rate", "60"]) == 0
    saved = np.load(out)
    expected = read_motion(shared_path("cmu/subject01/01_01.amc"))
    np.testing.assert_array_equal(saved["positions"], world_positions(expected))
    assert tuple(saved["names"]) == expected.names
    assert float(saved["frame_time"]) == 1 / 60


def test_info_edit_and_convert_read_the_same_amc(capsys, amc_apart, tmp_path):
    amc, asf = amc_apart
    assert main(["info", str(amc), "--asf", str(asf), "--json"]) == 0
    expected = load_gmr(shared_path("cmu/subject01/01_01.amc"))
    info = json.loads(capsys.readouterr().out)
    assert (info["frames"], len(info["joints"])) == (expected.n_frames, expected.n_joints)
    for argv in (["edit", str(amc), "-o", str(tmp_path / "e.gmr")], ["convert", str(amc), str(tmp_path / "c.gmr")]):
        assert main([*argv, "--asf", str(asf)]) == 0, capsys.readouterr().err
    for name in ("e.gmr", "c.gmr"):
        written = read_motion(tmp_path / name)
        assert written.names == expected.names
        np.testing.assert_allclose(
            world_positions(written), world_positions(expected), rtol=0, atol=1e-12 * expected.size
        )

"""``gmr convert --batch``: a temporary folder of real files and broken ones, in parallel."""

from __future__ import annotations

import io
import shutil

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.cli.batch import Progress, find_motion_files, plan_outputs, run_batch
from gmr_studio.core.cli.convert import ConvertOptions
from gmr_studio.core.formats import load_gmr, read_motion
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.shared_data import shared_data_dir
from tests.conftest import shared_path
from tests.test_export import validate_bvh

BROKEN_BVH = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 2 Xposition\n}\n"


@pytest.fixture
def motion_folder(tmp_path):
    """CMU subjects 01 and 02 and the cgspeed clip, a broken BVH, an AMC without skeleton."""
    shared_path("cmu/subject01/01_01.amc")
    data = shared_data_dir()
    folder = tmp_path / "in"
    for relative in ("cmu/subject01", "cmu/subject02"):
        shutil.copytree(data / relative, folder / relative)
    (folder / "bvh").mkdir()  # one BVH of the folder (the test's counts are of this set)
    shutil.copy(data / "bvh" / "cmu_cgspeed_npybvh_example_75f.bvh", folder / "bvh")
    for path in folder.rglob("*"):
        path.chmod(0o644 if path.is_file() else 0o755)
    (folder / "broken").mkdir()
    (folder / "broken" / "bad.bvh").write_text(BROKEN_BVH)
    (folder / "broken" / "orphan.amc").write_text("1\nroot 0 0 0 0 0 0\n")
    (folder / "broken" / "notes.txt").write_text("not a motion")
    return folder


def test_files_found_and_output_names(motion_folder, tmp_path):
    out = motion_folder / "out"  # inside IN_DIR: its files are never inputs
    out.mkdir()
    (out / "old.gmr").write_text("GMR 1\n")
    files = find_motion_files(motion_folder, out)
    names = [str(f.relative_to(motion_folder)) for f in files]
    assert names == [
        "broken/bad.bvh",
        "broken/orphan.amc",
        "bvh/cmu_cgspeed_npybvh_example_75f.bvh",
        "cmu/subject01/01_01.amc",
        "cmu/subject01/01_01.bvh",
        "cmu/subject02/02_01.amc",
    ]
    pairs = plan_outputs(files, motion_folder, out, "gmr")
    outputs = [str(o.relative_to(out)) for _, o in pairs]
    assert outputs[3:5] == ["cmu/subject01/01_01_amc.gmr", "cmu/subject01/01_01_bvh.gmr"]  # same stem
    assert outputs[5] == "cmu/subject02/02_01.gmr"


@pytest.mark.parametrize("jobs", [2, 1])
def test_batch_converts_real_files_and_reports_the_broken(motion_folder, tmp_path, capsys, jobs):
    out = tmp_path / "out"
    code = main(["convert", "--batch", str(motion_folder), str(out), "--jobs", str(jobs)])
    err = capsys.readouterr().err
    assert code == 1
    lines = err.splitlines()
    failures = [line for line in lines if not line.startswith(("[", "converted"))]
    assert len(failures) == 2  # one line per failed file, with its error
    assert failures[0 if "bad.bvh" in failures[0] else 1].startswith(
        f"{motion_folder / 'broken' / 'bad.bvh'}:6:1: unknown channel '}}'"
    )
    assert "orphan.amc: no .asf skeleton beside this AMC" in err
    assert lines[-1].startswith("converted 4 of 6 files to .gmr in ") and lines[-1].endswith("; 2 failed")
    assert f"({jobs} process" in lines[-1]
    assert len(lines) == 3  # not a terminal: no progress bar, only the failures and the summary
    written = sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file())
    assert written == [
        "bvh/cmu_cgspeed_npybvh_example_75f.gmr",
        "cmu/subject01/01_01_amc.gmr",
        "cmu/subject01/01_01_bvh.gmr",
        "cmu/subject02/02_01.gmr",
    ]  # nothing for the broken files, no temporary files left
    for source, target in [
        ("cmu/subject01/01_01_amc.gmr", "cmu/subject01/01_01.amc"),
        ("cmu/subject02/02_01.gmr", "cmu/subject02/02_01.amc"),
        ("cmu/subject01/01_01_bvh.gmr", "cmu/subject01/01_01.bvh"),
    ]:
        converted, original = read_motion(out / source), load_gmr(motion_folder / target)
        assert converted.names == original.names
        error = np.abs(world_positions(converted) - world_positions(original)).max()
        assert error <= 1e-9 * original.size


def test_batch_to_bvh_with_options(motion_folder, tmp_path, capsys):
    shutil.rmtree(motion_folder / "broken")
    out = tmp_path / "out"
    code = main(["convert", "--batch", str(motion_folder), str(out), "--to", "bvh", "--remove-dummies", "--jobs", "2"])
    err = capsys.readouterr().err
    assert code == 0 and err.splitlines()[-1].startswith("converted 4 of 4 files to .bvh")
    for path in out.rglob("*.bvh"):
        validate_bvh(path.read_text())
    source = load_gmr(motion_folder / "cmu/subject01/01_01.bvh")
    again = read_motion(out / "cmu/subject01/01_01_bvh.bvh")
    joints = [n for j, n in enumerate(source.names) if source.children[j] and n in again.names]
    assert len(joints) == 21  # 31 joints with children, less the 10 dummies
    index = [source.names.index(n) for n in joints]
    error = np.abs(
        world_positions(again)[:, [again.names.index(n) for n in joints]] - world_positions(source)[:, index]
    )
    assert error.max() <= 1e-6 * source.size


def test_a_failed_write_leaves_no_output_and_keeps_the_old_file(tmp_path, monkeypatch):
    import gmr_studio.core.formats.bvh_export as core_export

    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copy(shared_path("bvh/cmu_cgspeed_npybvh_example_75f.bvh"), folder / "clip.bvh")
    out = tmp_path / "out"
    out.mkdir()
    (out / "clip.bvh").write_text("the old file")

    def failing(motion, dialect):
        yield "HIERARCHY\n"
        raise OSError("disk full")

    monkeypatch.setattr(core_export, "format_text_motion", failing)
    stream = io.StringIO()
    assert run_batch(folder, out, "bvh", ConvertOptions(), jobs=1, stream=stream) == 1
    assert f"{folder / 'clip.bvh'}: disk full" in stream.getvalue()
    assert [p.name for p in out.iterdir()] == ["clip.bvh"] and (out / "clip.bvh").read_text() == "the old file"


def test_refusals(tmp_path, capsys):
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["convert", "--batch", str(empty), str(tmp_path / "out")]) == 2
    assert "no motion files (.bvh, .gmr, .amc, .glb, .gltf, .vrma, .fbx) under" in capsys.readouterr().err
    assert main(["convert", "--batch", str(empty), str(empty)]) == 2
    assert "OUT_DIR must differ from IN_DIR" in capsys.readouterr().err
    assert main(["convert", "--batch", str(tmp_path / "missing"), str(tmp_path / "out")]) == 2
    assert "is not a folder" in capsys.readouterr().err


def test_progress_bar_in_place_on_a_terminal_silent_otherwise():
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    for stream in (Terminal(), io.StringIO()):
        progress = Progress(4, stream)
        progress.advance(True)
        progress.message("a.bvh:1:1: bad")
        progress.advance(False)
        progress.close()
        text = stream.getvalue()
        assert "a.bvh:1:1: bad\n" in text and (progress.done, progress.failed) == (2, 1)
        if isinstance(stream, Terminal):
            assert "\r" in text and "2/4" in text and "1 failed" in text
        else:
            assert text == "a.bvh:1:1: bad\n"

"""``gmr dataset``: the table holds every file's FK (positions or rotations), resampled as
``np.interp`` would, in .npz and .parquet alike; a Dask LocalCluster writes the same bytes."""

from __future__ import annotations

import io
import shutil

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from gmr_studio.core.cli import main
from gmr_studio.core.cli.dataset import build_dataset
from gmr_studio.core.edits.clip import trim
from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.bvh import write_bvh
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import reference_forward_kinematics
from gmr_studio.core.timebase.clock import nominal_rate
from tests.conftest import shared_path
from tests.test_gltf import matrix_from_quaternion

#: measured worst difference (matrix entries) between the exported nlerp and scipy's slerp on
#: the cgspeed clip resampled 120 -> 30 Hz: 4.0e-7, float32 rounding dominates
SLERP_TOLERANCE = 1e-6


@pytest.fixture
def folder(tmp_path):
    """CMU 02_01 (AMC + ASF), the cgspeed clip, and a broken BVH."""
    root = tmp_path / "in"
    (root / "s02").mkdir(parents=True)
    for relative in ("cmu/subject02/02_01.amc", "cmu/subject02/02.asf"):
        shutil.copy(shared_path(relative), root / "s02")
    shutil.copy(shared_path("bvh/cmu_cgspeed_npybvh_example_75f.bvh"), root / "clip.bvh")
    (root / "broken.bvh").write_text("HIERARCHY\nROOT Hips\n{\n")
    return root


def test_positions_npz_equal_fk(folder, tmp_path):
    out = tmp_path / "positions.npz"
    stream = io.StringIO()
    assert build_dataset(folder, out, jobs=1, stream=stream) == 1  # the broken file is reported, left out
    assert "broken.bvh" in stream.getvalue() and "wrote positions of 2 of 3 files" in stream.getvalue()
    with np.load(out) as data:
        assert list(data["files"]) == ["clip.bvh", "s02/02_01.amc"]
        assert str(data["quantity"]) == "positions"
        for i, name in enumerate(data["files"]):
            motion = read_motion(folder / name)
            expected = reference_forward_kinematics(motion, with_rotations=False)[0]
            assert list(data[f"joints_{i}"]) == list(motion.names)
            np.testing.assert_array_equal(data[f"values_{i}"], expected.astype(np.float32))
            assert data["frame_rate"][i] == pytest.approx(motion.frame_rate)


def test_rotations_resampled_parquet_equal_the_npz_and_fk(folder, tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    (folder / "broken.bvh").unlink()
    npz, parquet = tmp_path / "rot.npz", tmp_path / "rot.parquet"
    for out in (npz, parquet):
        assert (
            main(["dataset", str(folder), "-o", str(out), "--quantity", "rotations", "--rate", "30", "--jobs", "1"])
            == 0
        )
    table = pq.read_table(parquet)
    with np.load(npz) as data:
        motion = pre_from_post(read_motion(folder / "clip.bvh"))
        world = reference_forward_kinematics(motion)[1]
        values = data["values_0"]
        # resampled to 30 Hz: sample k at k/30 s is scipy's slerp of FK's world rotations
        # (normalised lerp differs from slerp by O(angle^3) between neighbouring frames), on
        # the clock the file means: 30 Hz divides its 120 Hz (printed 0.0083333 s)
        times = np.arange(values.shape[0]) / 30.0
        frame_times = np.arange(motion.n_frames) / nominal_rate(motion.frame_time)
        for j in range(motion.n_joints):
            slerp = Slerp(frame_times, Rotation.from_matrix(world[:, j]))(times).as_matrix()
            np.testing.assert_allclose(matrix_from_quaternion(values[:, j]), slerp, atol=SLERP_TOLERANCE)
        assert np.allclose(np.linalg.norm(values, axis=-1), 1, atol=1e-6)
        n_rows = sum(data[f"values_{i}"].shape[0] * data[f"values_{i}"].shape[1] for i in range(len(data["files"])))
        assert table.num_rows == n_rows
    columns = table.column_names
    assert columns == ["file", "frame", "time", "joint", "qx", "qy", "qz", "qw"]
    clip_rows = np.asarray(table["file"]) == "clip.bvh"
    # the rate stored and the times written are the new rate's (30 Hz), not the source's 120 Hz
    with np.load(npz) as data:
        np.testing.assert_array_equal(data["frame_rate"], [30.0, 30.0])
        n_clip = data["values_0"].shape[0]
    clip_frames = np.asarray(table["frame"])[clip_rows]
    np.testing.assert_array_equal(np.asarray(table["time"])[clip_rows], clip_frames / 30.0)
    assert clip_frames.max() == n_clip - 1
    quats = np.stack([np.asarray(table[c])[clip_rows] for c in ("qx", "qy", "qz", "qw")], axis=-1)
    np.testing.assert_array_equal(quats, values.reshape(-1, 4))
    assert np.array_equal(np.asarray(table["frame"])[clip_rows], np.repeat(np.arange(len(values)), values.shape[1]))


def test_positions_resampled_like_np_interp(folder, tmp_path):
    (folder / "broken.bvh").unlink()
    out = tmp_path / "p.npz"
    assert build_dataset(folder, out, rate=50.0, jobs=1, stream=io.StringIO()) == 0
    motion = read_motion(folder / "s02/02_01.amc")
    source = reference_forward_kinematics(motion, with_rotations=False)[0]
    with np.load(out) as data:
        values = data["values_1"]
        np.testing.assert_array_equal(data["frame_rate"], [50.0, 50.0])
    times = np.arange(values.shape[0]) / 50.0
    assert times[-1] <= (motion.n_frames - 1) * motion.frame_time < times[-1] + 1 / 50
    frame_times = np.arange(motion.n_frames) * motion.frame_time
    expected = np.stack(
        [[np.interp(times, frame_times, source[:, j, a]) for a in range(3)] for j in range(motion.n_joints)]
    ).transpose(2, 0, 1)
    np.testing.assert_allclose(values, expected, atol=1e-5 * motion.size)


def test_a_take_whose_frame_time_is_printed_rounded_keeps_its_last_frame(tmp_path):
    # 'Frame Time: 0.033333' is 30 Hz to six decimals: 31 frames at 15 Hz are 16 rows, the
    # last at 1 s on the last frame (the clip's clock, core.timebase.sampling.resample_grid)
    take = trim(read_motion(shared_path("bvh/bvh-python_test_mocapbank.bvh")), 0, 31)
    (tmp_path / "in").mkdir()
    write_bvh(take, tmp_path / "in" / "take.bvh")
    out = tmp_path / "take.npz"
    assert build_dataset(tmp_path / "in", out, rate=15.0, jobs=1, stream=io.StringIO()) == 0
    with np.load(out) as data:
        values = data["values_0"]
    source = reference_forward_kinematics(take, with_rotations=False)[0]
    assert values.shape[0] == 16
    np.testing.assert_array_equal(values[[0, -1]], source[[0, -1]].astype(np.float32))


@pytest.mark.slow
def test_local_cluster_writes_the_same_bytes(folder, tmp_path):
    pytest.importorskip("distributed", reason="the 'cluster' extra (dask[distributed]) is not installed")
    single, cluster = tmp_path / "single.npz", tmp_path / "cluster.npz"
    assert build_dataset(folder, single, jobs=1, stream=io.StringIO()) == 1
    stream = io.StringIO()
    assert build_dataset(folder, cluster, scheduler="local:2", stream=stream) == 1
    assert "(Dask local:2)" in stream.getvalue()
    assert cluster.read_bytes() == single.read_bytes()
    assert sorted(p.name for p in tmp_path.iterdir() if p.suffix == ".tmp") == []


def test_refusals(folder, tmp_path, capsys):
    assert main(["dataset", str(folder), "-o", str(tmp_path / "x.csv")]) == 2
    assert "written as .npz or .parquet" in capsys.readouterr().err

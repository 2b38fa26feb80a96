"""``gmr convert --batch --scheduler``: a real ``distributed.LocalCluster`` of worker
processes gives byte-identical outputs to the single-process run, and a worker killed in
the middle of a run loses no file."""

from __future__ import annotations

import io
import os
import shutil
import signal
import threading
import time

import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.cli.batch import run_batch
from gmr_studio.core.cli.convert import ConvertOptions, convert_file
from tests.conftest import shared_path

distributed = pytest.importorskip("distributed", reason="the 'cluster' extra (dask[distributed]) is not installed")


@pytest.fixture
def cmu_folder(tmp_path):
    """CMU 01_01 (BVH and AMC with its ASF), 02_01 (AMC) and the cgspeed clip."""
    folder = tmp_path / "in"
    for relative in ("cmu/subject01/01_01.bvh", "cmu/subject01/01_01.amc", "cmu/subject01/01.asf"):
        (folder / "s01").mkdir(parents=True, exist_ok=True)
        shutil.copy(shared_path(relative), folder / "s01")
    (folder / "s02").mkdir()
    for relative in ("cmu/subject02/02_01.amc", "cmu/subject02/02.asf"):
        shutil.copy(shared_path(relative), folder / "s02")
    shutil.copy(shared_path("bvh/cmu_cgspeed_npybvh_example_75f.bvh"), folder)
    return folder


def tree_bytes(folder) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.mark.slow
def test_local_cluster_outputs_equal_the_single_process_run(cmu_folder, tmp_path, capsys, to="gmr"):
    single, cluster = tmp_path / "single", tmp_path / "cluster"
    assert main(["convert", "--batch", str(cmu_folder), str(single), "--to", to, "--jobs", "1"]) == 0
    assert main(["convert", "--batch", str(cmu_folder), str(cluster), "--to", to, "--scheduler", "local:2"]) == 0
    summary = capsys.readouterr().err.splitlines()[-1]
    assert summary.startswith("converted 4 of 4 files") and "(Dask local:2," in summary
    expected = tree_bytes(single)
    assert len(expected) == 4 and tree_bytes(cluster) == expected


@pytest.mark.slow
def test_a_worker_killed_mid_run_loses_no_file(tmp_path):
    folder, out = tmp_path / "in", tmp_path / "out"
    folder.mkdir()
    source = shared_path("cmu/subject01/01_01.bvh")
    copies = 6
    for k in range(copies):
        shutil.copy(source, folder / f"take{k}.bvh")
    reference = tmp_path / "reference.gmr"
    convert_file(folder / "take0.bvh", reference, ConvertOptions())
    expected = reference.read_bytes()
    with (
        distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster,
        distributed.Client(cluster) as client,
    ):
        pids = client.run(os.getpid)
        victim = sorted(pids.values())[0]
        killed = threading.Event()

        def kill_after_the_first_output() -> None:
            deadline = time.monotonic() + 120
            while time.monotonic() < deadline and not list(out.glob("*.gmr")):
                time.sleep(0.05)
            os.kill(victim, signal.SIGKILL)
            killed.set()

        killer = threading.Thread(target=kill_after_the_first_output)
        killer.start()
        stream = io.StringIO()
        code = run_batch(folder, out, "gmr", ConvertOptions(), None, stream, scheduler=cluster.scheduler_address)
        killer.join()
        assert killed.is_set()
        assert victim not in client.run(os.getpid).values()  # the worker did die (the nanny made a new one)
    assert code == 0, stream.getvalue()
    assert f"converted {copies} of {copies} files" in stream.getvalue()
    written = sorted(p.name for p in out.iterdir())
    assert written == sorted(f"take{k}.gmr" for k in range(copies))  # every file, no temporary left
    for k in range(copies):
        data = (out / f"take{k}.gmr").read_bytes()
        assert data == expected.replace(b"from take0.bvh", f"from take{k}.bvh".encode())


def test_scheduler_refusals(cmu_folder, tmp_path, capsys):
    assert main(["convert", "--batch", str(cmu_folder), str(tmp_path / "o"), "--scheduler", "local:0"]) == 2
    assert "expected local:N with N >= 1" in capsys.readouterr().err

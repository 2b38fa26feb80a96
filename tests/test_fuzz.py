"""The fuzzer: a fast subset of the hostile-file run, and the runner's own classification."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.fuzz.mutations import TEXT_MUTATIONS
from gmr_studio.core.fuzz.runner import make_case, run_case, run_fuzz
from gmr_studio.core.fuzz.targets import Target, all_targets
from tests.conftest import DATA, MISSING_DATA

needs_data = pytest.mark.skipif(not DATA.is_dir(), reason=MISSING_DATA)


@needs_data
def test_fast_subset_of_every_format_is_read_or_refused_cleanly():
    in_process = [name for name in all_targets() if name not in ("c3d", "fbx")]
    report = run_fuzz(in_process, cases=150, seed=7, timeout=20, jobs=2, stride=37)
    binary = run_fuzz(["c3d", "fbx"], cases=24, seed=7, jobs=2, stride=97)  # each read starts a process
    assert set(report.counts) == {"bvh", "gmr", "trc", "asf", "amc", "gltf"} and set(binary.counts) == {"c3d", "fbx"}
    report.counts.update(binary.counts)
    report.failures += binary.failures
    for name, counts in report.counts.items():
        assert sum(counts.values()) == (24 if name in ("c3d", "fbx") else 150), name
        assert counts["clean"] > 0, f"{name}: no mutation was refused: the mutations are not biting"
    assert report.failures == [], "\n".join(f"{f.target}:{f.index} {f.outcome} {f.detail}" for f in report.failures)


@needs_data
def test_cases_are_deterministic_and_start_with_structural_cuts():
    target = all_targets()["bvh"]
    first = make_case(target, 3, 5)
    assert first == make_case(target, 3, 5)
    assert first.mutations[0].startswith("truncate at structural point")
    later = make_case(target, 3, 5000)
    assert later.data == make_case(target, 3, 5000).data and later.mutations[0] in TEXT_MUTATIONS


@needs_data
def test_the_command_line_turns_fuzzed_errors_into_one_line(tmp_path, capsys):
    target = all_targets()["bvh"]
    checked = 0
    for index in range(2000, 2200):
        case = make_case(target, 11, index)
        path = tmp_path / f"case{index}.bvh"
        path.write_bytes(case.data)
        try:
            target.read(path, case.data, case.seed_file)
        except MotionFileError:
            pass
        else:
            continue
        code = main(["info", str(path)])
        out, err = capsys.readouterr()
        assert code == 2 and out == ""
        assert err.count("\n") == 1 and err.startswith(f"{path}:") and "Traceback" not in err
        checked += 1
    assert checked > 50


def _fake_target(read) -> Target:
    return Target(
        name="fake",
        suffix=".txt",
        seeds=lambda: [("seed", b"data\n")],
        read=read,
        check=lambda value: None,
        mutations={"nothing": lambda data, rng: data},
        structure=lambda data: [],
    )


def test_runner_classifies_every_kind_of_outcome(monkeypatch):
    def hang(path, data, seed):
        import time

        time.sleep(60)

    def crash(path, data, seed):
        import os

        os._exit(3)

    def hog(path, data, seed):
        return np.ones((10**6, 10**6))  # 8 TB: must hit the memory bound

    def sloppy(path, data, seed):
        raise MotionFileError(path, "no line given")

    readers = {
        "hang": hang,
        "crash": crash,
        "memory": hog,
        "other": lambda p, d, s: 1 / 0,
        "sloppy": sloppy,
        "overflow": lambda p, d, s: np.float64(1e308) * 10,
        "clean": lambda p, d, s: (_ for _ in ()).throw(MotionFileError(p, "bad", 1, 1)),
        "read": lambda p, d, s: 1,
    }
    fakes = {name: dataclasses.replace(_fake_target(read), name=name) for name, read in readers.items()}
    monkeypatch.setattr("gmr_studio.core.fuzz.runner.all_targets", lambda: fakes)
    report = run_fuzz(cases=2, timeout=2, memory_mb=256, jobs=2)
    outcome_of = {name: counts.most_common(1)[0][0] for name, counts in report.counts.items()}
    assert outcome_of == {
        "hang": "hang",
        "crash": "crash",
        "memory": "memory",
        "other": "other",
        "sloppy": "other",
        "overflow": "other",
        "clean": "clean",
        "read": "read",
    }
    assert {f.target for f in report.failures} == {"hang", "crash", "memory", "other", "sloppy", "overflow"}
    overflow = next(f for f in report.failures if f.target == "overflow")
    assert overflow.detail.startswith("RuntimeWarning at test_fuzz.py:") and "overflow" in overflow.detail


def test_run_case_checks_successful_reads(tmp_path):
    target = dataclasses.replace(
        _fake_target(lambda p, d, s: "value"), check=lambda v: (_ for _ in ()).throw(AssertionError("impossible value"))
    )
    case = make_case(target, 0, 0)
    result = run_case(target, case, Path(tmp_path))
    assert (result.outcome, result.detail) == ("other", "impossible value")


def test_the_fuzz_command_exits_1_and_prints_the_replay_line_when_a_case_fails(monkeypatch, capsys):
    fakes = {
        "good": dataclasses.replace(_fake_target(lambda p, d, s: 1), name="good"),
        "bad": dataclasses.replace(_fake_target(lambda p, d, s: 1 / 0), name="bad"),
    }
    monkeypatch.setattr("gmr_studio.core.fuzz.runner.all_targets", lambda: fakes)
    monkeypatch.setattr("gmr_studio.core.cli.fuzz.all_targets", lambda: fakes)
    assert main(["fuzz", "--formats", "good", "--cases", "3", "--seed", "5", "--jobs", "1"]) == 0
    assert "every case was a correct read or a clean error" in capsys.readouterr().out
    assert main(["fuzz", "--formats", "good,bad", "--cases", "3", "--seed", "5", "--jobs", "1"]) == 1
    out = capsys.readouterr().out
    assert "3 cases ended otherwise than read or clean:" in out
    assert "  bad:0 [other] seed + nothing: ZeroDivisionError" in out
    assert "replay one with: gmr fuzz --seed 5 --replay FORMAT:INDEX --save case.bin" in out
    assert main(["fuzz", "--seed", "5", "--replay", "bad:1"]) == 1
    assert "outcome: other" in capsys.readouterr().out
    assert main(["fuzz", "--seed", "5", "--replay", "good:1"]) == 0

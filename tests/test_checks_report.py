"""The report of ``gmr check`` (core.checks.report): the document's fields, the table's rows and
heading, the batch row, the strict verdict at each severity."""

from __future__ import annotations

from gmr_studio.core.checks.model import KINDS, Finding
from gmr_studio.core.checks.report import (
    SUMMARY_COLUMNS,
    check_document,
    failing,
    findings_text,
    summary_row,
)
from tests.checks_walk import clean_walk

FINDINGS = [
    Finding("pop", (10,), ("LeftHand",), 200, 200, "warning", 4.98765, "cm"),
    Finding("duplicate", (), (), 251, 252, "error", 2.0, "frames"),
    Finding("jitter", tuple(range(12)), tuple(f"Joint{k:02d}" for k in range(12)), 60, 540, "info", 0.5, "cm"),
]


def test_the_document_of_a_file():
    motion = clean_walk(30.0, seconds=1.0)
    document = check_document("walk.bvh", motion, FINDINGS[:1])
    assert document == {
        "file": "walk.bvh",
        "frames": 30,
        "frame_rate": 30.0,
        "units": "file units",
        "findings": [FINDINGS[0].to_dict()],
        "skipped": [],
    }
    rates = [
        check_document("x", motion.replace(frame_time=1 / r), [])["frame_rate"] for r in (29.9700000004, 29.970000004)
    ]
    assert rates == [29.97, 29.970000004]  # to 9 decimals


def test_failing_at_each_severity():
    dicts = [f.to_dict() for f in FINDINGS]
    assert failing(FINDINGS, "info") == FINDINGS
    assert failing(FINDINGS, "warning") == FINDINGS[:2]
    assert failing(FINDINGS, "error") == FINDINGS[1:2]
    assert failing(dicts, "warning") == dicts[:2]


def test_the_table():
    document = {"file": "walk.bvh", "frames": 600, "frame_rate": 120.0, "units": "cm"}
    text = findings_text(document | {"findings": [f.to_dict() for f in FINDINGS]})
    lines = text.split("\n")
    assert lines[0] == "walk.bvh: 600 frames at 120 Hz, lengths in cm; 3 findings (1 error, 1 warning, 1 info)"
    assert lines[1] == f"{'kind':<12} {'severity':<8} {'frames':>11}  {'joints':<40} value"
    assert lines[2] == f"{'pop':<12} {'warning':<8} {'200':>11}  {'LeftHand':<40} 4.988 cm"
    assert lines[3] == f"{'duplicate':<12} {'error':<8} {'251-252':>11}  {'(whole pose)':<40} 2 frames"
    joints = ", ".join(f"Joint{k:02d}" for k in range(12))[:37] + "..."
    assert len(joints) == 40
    assert lines[4] == f"{'jitter':<12} {'info':<8} {'60-540':>11}  {joints} 0.5 cm"
    assert (
        findings_text(document | {"findings": [FINDINGS[0].to_dict()]})
        .split("\n")[0]
        .endswith("; 1 finding (1 warning)")
    )
    assert findings_text(document | {"findings": []}) == "walk.bvh: 600 frames at 120 Hz, lengths in cm; 0 findings"


def test_joints_of_exactly_40_characters_are_not_cut():
    names = ["A" * 18, "B" * 20]  # "AAA..., BBB..." is 40 characters
    finding = Finding("pop", (1, 2), tuple(names), 5, 5, "info", 1.0, "cm").to_dict()
    document = {"file": "f", "frames": 10, "frame_rate": 24.0, "units": "cm", "findings": [finding]}
    assert f"{', '.join(names)} 1 cm" in findings_text(document)


def test_the_batch_row():
    document = {
        "file": "walk.bvh",
        "frames": 600,
        "frame_rate": 120.0,
        "units": "cm",
        "findings": [f.to_dict() for f in FINDINGS],
    }
    row = summary_row(document, "walk.bvh")
    assert list(row) == [*SUMMARY_COLUMNS, *KINDS]
    assert row["status"] == "ok" and row["findings"] == 3
    assert (row["frames"], row["frame_rate"], row["units"]) == (600, 120.0, "cm")
    assert (row["info"], row["warning"], row["error"], row["worst"]) == (1, 1, 1, "error")
    assert {k: row[k] for k in KINDS if row[k]} == {"pop": 1, "jitter": 1, "duplicate": 1}
    assert row["flip"] == 0
    assert summary_row(document | {"findings": document["findings"][2:]}, "w")["worst"] == "info"
    assert summary_row(document | {"findings": []}, "w")["worst"] == ""
    failed = summary_row(None, "bad.bvh", "cannot read it")
    assert failed == dict.fromkeys((*SUMMARY_COLUMNS, *KINDS)) | {"file": "bad.bvh", "status": "cannot read it"}

"""The pelvis triple of the ``joints`` map on BVH rigs whose hips sit level with the root: the
technical note's root, left femur and lower back, else any non-collinear triple of pelvis
joints; which one was used is said."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.markers import markers_to_motion
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.markers.pelvis_guess import choose_pelvis, side
from gmr_studio.core.markers.trc import write_trc
from tests.conftest import shared_path
from tests.test_markers_solve import assert_exact, joint_markers

#: a game-style rig: both hips level with the root (root and hips collinear), a spine above
RIG = """HIERARCHY
ROOT {root}
{{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT {left}
  {{
    OFFSET 9 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT {left}Knee
    {{
      OFFSET 0 -40 1
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {{
        OFFSET 0 -40 0
      }}
    }}
  }}
  JOINT {right}
  {{
    OFFSET -9 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT {right}Knee
    {{
      OFFSET 0 -40 1
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {{
        OFFSET 0 -40 0
      }}
    }}
  }}
  JOINT {back}
  {{
    OFFSET 0 10 -1
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT Neck
    {{
      OFFSET 0 40 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {{
        OFFSET 0 10 0
      }}
    }}
  }}
}}
MOTION
Frames: {n}
Frame Time: 0.0333333
{rows}
"""


def write_rig(path, root="Hips", left="LeftUpLeg", right="RightUpLeg", back="Spine", n=40):
    rng = np.random.default_rng(7)
    values = rng.uniform(-60, 60, (n, 6 + 3 * 6))
    values[:, :3] = rng.normal(size=(n, 3)) * 20
    rows = "\n".join(" ".join(f"{v:.6f}" for v in row) for row in values)
    path.write_text(RIG.format(root=root, left=left, right=right, back=back, n=n, rows=rows))
    return load_gmr(path)


@pytest.mark.parametrize(
    ("names", "expected", "how"),
    [
        ({}, ("Hips", "LeftUpLeg", "Spine"), "technical note"),
        (
            {"root": "pelvis", "left": "l_hip", "right": "r_hip", "back": "belly"},
            ("pelvis", "l_hip", "belly"),
            "not collinear",
        ),
    ],
)
def test_rigs_with_level_hips_convert_and_say_which_triple(tmp_path, names, expected, how):
    truth = write_rig(tmp_path / "rig.bvh", **names)
    markers = joint_markers(truth)
    result = markers_to_motion(markers, truth, "joints", reference=truth)
    assert_exact(result.motion, truth)
    assert result.pelvis.labels == expected
    assert f"pelvis triple {', '.join(expected)} (" in result.pelvis_note and how in result.pelvis_note
    free = markers_to_motion(markers, truth, "joints")  # without a reference, positions are still exact
    assert_exact(free.motion, truth, angles=False)


def test_gmr_markers_prints_the_triple(tmp_path, capsys):
    truth = write_rig(tmp_path / "rig.bvh")
    write_trc(joint_markers(truth).replace(source="rig.trc"), tmp_path / "rig.trc", digits=17)
    code = main(["markers", str(tmp_path / "rig.trc"), "--skeleton", str(tmp_path / "rig.bvh"), "--map", "joints",
                 "-o", str(tmp_path / "out.gmr")])  # fmt: skip
    out = capsys.readouterr().out
    assert code == 0 and "pelvis: pelvis triple Hips, LeftUpLeg, Spine (the technical note's" in out


def test_cmu_skeletons_keep_rigid_triples():
    """CMU ASF: the note's lower back turns with the spine (its triangle with root and left hip
    changes by 5%), so root and both hips are used; CMU BVH: LowerBack sits on Hips (a dummy)
    and Spine turns with it, so again the hips."""
    amc = load_gmr(shared_path("cmu/subject01/01_01.amc"), asf=shared_path("cmu/subject01/01.asf")).frame_slice(
        slice(0, 600)
    )
    bvh = load_gmr(shared_path("cmu/subject01/01_01.bvh")).frame_slice(slice(0, 600))
    for motion, expected in ((amc, ("root", "lhipjoint", "rhipjoint")), (bvh, ("Hips", "LeftUpLeg", "RightUpLeg"))):
        markers = joint_markers(motion)
        choice = choose_pelvis(motion.names, markers.positions, motion.parents, motion.offsets)
        assert choice.triple == expected, choice
    assert [side(n) for n in ("LeftUpLeg", "lfemur", "L_Thigh", "thigh.L", "LHipJoint", "RightArm", "Spine")] == [
        "left", "left", "left", "left", "left", "right", None,
    ]  # fmt: skip


def test_collinear_everywhere_is_refused_with_the_reason(tmp_path):
    positions = np.zeros((3, 3, 3))
    positions[:, 1, 0], positions[:, 2, 0] = 1.0, -1.0  # three points on a line
    markers = MarkerSet(labels=["Hips", "LeftUpLeg", "RightUpLeg"], positions=positions, rate=30, units="cm")
    assert choose_pelvis(markers.labels, markers.positions) is None

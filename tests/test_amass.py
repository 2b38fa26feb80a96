"""AMASS/SMPL motions in: FK of the converted motion equals the joints computed directly from
a synthetic body model of the official layout (SMPL's own joint recursion with 4x4
transforms, scipy's rotation vectors); the CLI and the errors."""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.cli import main
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats import load_gmr, read_motion
from gmr_studio.core.formats.amass import matrices_from_axis_angle
from gmr_studio.core.formats.body_model import JOINT_NAMES, load_body_model
from gmr_studio.core.kinematics.fk import reference_forward_kinematics

N_VERTICES, N_BETAS = 300, 16


def smplh_parents() -> list[int]:
    """SMPL-H's kinematic tree: 22 body joints, then 3-joint fingers from each wrist."""
    parents = [-1, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9, 12, 13, 14, 16, 17, 18, 19]
    for wrist in (20, 21):
        for _finger in range(5):
            start = len(parents)
            parents += [wrist, start, start + 1]
    return parents


def synthetic_model(rng: np.random.Generator) -> dict[str, np.ndarray]:
    """A body model of SMPL-H's layout: random template and shape directions, a J_regressor
    averaging a few random vertices per joint, SMPL-H's tree (root's parent id 2**32-1)."""
    parents = smplh_parents()
    n_joints = len(parents)
    regressor = np.zeros((n_joints, N_VERTICES))
    for j in range(n_joints):
        picked = rng.choice(N_VERTICES, size=6, replace=False)
        regressor[j, picked] = rng.dirichlet(np.ones(6))
    kintree = np.array([[p if p >= 0 else 2**32 - 1 for p in parents], list(range(n_joints))], dtype=np.uint32)
    return {
        "v_template": rng.normal(scale=0.5, size=(N_VERTICES, 3)),
        "shapedirs": rng.normal(scale=0.01, size=(N_VERTICES, 3, N_BETAS)),
        "J_regressor": regressor,
        "kintree_table": kintree,
        "f": rng.integers(0, N_VERTICES, size=(50, 3)),
    }


def synthetic_sequence(rng: np.random.Generator, n_frames: int = 25) -> dict[str, np.ndarray]:
    return {
        "poses": rng.normal(scale=0.6, size=(n_frames, 52 * 3)),
        "trans": np.cumsum(rng.normal(scale=0.02, size=(n_frames, 3)), axis=0),
        "betas": rng.normal(size=N_BETAS),
        "gender": np.array("female"),
        "mocap_framerate": np.array(120.0),
    }


def smpl_joint_positions(model: dict, sequence: dict) -> np.ndarray:
    """(F, J, 3) posed joints the way SMPL's reference code computes them: rest joints from
    the regressor, then per frame 4x4 transforms chained from the root, plus ``trans``."""
    vertices = model["v_template"] + model["shapedirs"] @ sequence["betas"]
    joints = model["J_regressor"] @ vertices
    parents = smplh_parents()
    n_frames = sequence["poses"].shape[0]
    out = np.zeros((n_frames, len(parents), 3))
    for f in range(n_frames):
        rotations = Rotation.from_rotvec(sequence["poses"][f].reshape(-1, 3)).as_matrix()
        transforms = []
        for j, p in enumerate(parents):
            local = np.eye(4)
            local[:3, :3] = rotations[j]
            local[:3, 3] = joints[j] - (joints[p] if p >= 0 else 0)
            transforms.append(local if p < 0 else transforms[p] @ local)
            out[f, j] = transforms[j][:3, 3] + sequence["trans"][f]
    return out


@pytest.fixture
def amass_files(tmp_path, rng):
    model, sequence = synthetic_model(rng), synthetic_sequence(rng)
    np.savez(tmp_path / "model.npz", **model)
    np.savez(tmp_path / "walk.npz", **sequence)
    return tmp_path / "model.npz", tmp_path / "walk.npz", model, sequence


def test_fk_equals_the_body_models_joints(amass_files):
    model_path, motion_path, model, sequence = amass_files
    motion = read_motion(motion_path, body_model=model_path)
    assert motion.names == JOINT_NAMES[52] and motion.n_frames == 25 and motion.frame_rate == pytest.approx(120)
    expected = smpl_joint_positions(model, sequence)
    positions = reference_forward_kinematics(motion, with_rotations=False)[0]
    assert np.abs(positions - expected).max() <= 1e-12 * motion.size
    gmr = load_gmr(motion_path, body_model=model_path)  # the GMR form keeps them too
    assert np.abs(reference_forward_kinematics(gmr, with_rotations=False)[0] - expected).max() <= 1e-12 * motion.size
    assert (motion.facts.up_axis, motion.facts.unit.name) == ("z", "m")


def test_pickled_model_reads_the_same(amass_files, tmp_path):
    model_path, motion_path, model, _ = amass_files
    with open(tmp_path / "model.pkl", "wb") as handle:
        pickle.dump(model, handle, protocol=2)
    a = read_motion(motion_path, body_model=model_path)
    b = read_motion(motion_path, body_model=tmp_path / "model.pkl")
    assert np.array_equal(a.offsets, b.offsets) and np.array_equal(a.rotations, b.rotations)


def test_a_pickle_that_would_run_code_is_refused(tmp_path):
    class Sneaky:
        def __reduce__(self):
            return (print, ("this must never run",))

    with open(tmp_path / "evil.pkl", "wb") as handle:
        pickle.dump({"v_template": Sneaky()}, handle)
    with pytest.raises(MotionFileError, match="only numpy arrays and containers are admitted"):
        load_body_model(tmp_path / "evil.pkl")


def test_missing_model_says_what_to_pass(amass_files, capsys):
    _, motion_path, _, _ = amass_files
    with pytest.raises(MotionFileError, match="pass --body-model PATH"):
        read_motion(motion_path)
    assert main(["info", str(motion_path)]) == 2
    assert "--body-model" in capsys.readouterr().err


def test_wrong_family_and_broken_files(amass_files, tmp_path, rng):
    model_path, motion_path, model, sequence = amass_files
    np.savez(
        tmp_path / "smplx_like.npz", **{**sequence, "poses": rng.normal(size=(4, 55 * 3)), "trans": np.zeros((4, 3))}
    )
    with pytest.raises(MotionFileError, match=r"poses rotate 55 joints but the body model model\.npz has 52"):
        read_motion(tmp_path / "smplx_like.npz", body_model=model_path)
    np.savez(tmp_path / "no_kintree.npz", **{k: v for k, v in model.items() if k != "kintree_table"})
    with pytest.raises(MotionFileError, match="lacks kintree_table"):
        read_motion(motion_path, body_model=tmp_path / "no_kintree.npz")
    (tmp_path / "junk.npz").write_bytes(b"not a zip")
    with pytest.raises(MotionFileError, match=r"not an AMASS \.npz"):
        read_motion(tmp_path / "junk.npz", body_model=model_path)


def test_cli_info_convert_positions(amass_files, tmp_path, capsys):
    model_path, motion_path, model, sequence = amass_files
    assert main(["info", str(motion_path), "--body-model", str(model_path), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["format"].startswith("AMASS") and info["frames"] == 25 and info["roots"] == ["pelvis"]
    assert main(["positions", str(motion_path), "--body-model", str(model_path), "-o", str(tmp_path / "p.npz")]) == 0
    with np.load(tmp_path / "p.npz") as data:
        np.testing.assert_allclose(data["positions"], smpl_joint_positions(model, sequence), atol=1e-12)
    out = tmp_path / "walk.bvh"
    assert main(["convert", str(motion_path), str(out), "--body-model", str(model_path), "--up", "y"]) == 0
    bvh = read_motion(out)
    z_up = smpl_joint_positions(model, sequence)
    expected = np.stack([z_up[..., 0], z_up[..., 2], -z_up[..., 1]], axis=-1)  # Z up -> Y up
    parents = smplh_parents()
    names = JOINT_NAMES[52]  # a BVH's leaves are End Sites, named <parent>_End by the reader
    in_bvh = [n if n in bvh.names else f"{names[parents[j]]}_End" for j, n in enumerate(names)]
    got = reference_forward_kinematics(bvh, with_rotations=False)[0][:, [bvh.names.index(n) for n in in_bvh]]
    assert np.abs(got - expected).max() < 1e-5  # BVH stores 6 decimals


def test_axis_angle_matches_scipy(rng):
    rotvecs = np.concatenate([rng.normal(size=(200, 3)) * 2, rng.normal(size=(20, 3)) * 1e-9, np.zeros((1, 3))])
    np.testing.assert_allclose(matrices_from_axis_angle(rotvecs), Rotation.from_rotvec(rotvecs).as_matrix(), atol=1e-15)


def test_smplx_rate_key_and_more_betas_than_the_model_has(tmp_path, rng):
    # planted bugs: SMPL-X's ``mocap_frame_rate`` refused; extra betas not cut to the model's
    model, sequence = synthetic_model(rng), synthetic_sequence(rng, n_frames=6)
    model["shapedirs"] = model["shapedirs"][..., :4]  # a model with 4 shape directions
    smplx = {k: v for k, v in sequence.items() if k != "mocap_framerate"}
    smplx["mocap_frame_rate"] = np.array(59.94)  # SMPL-X releases spell it so
    np.savez(tmp_path / "model.npz", **model)
    np.savez(tmp_path / "smplx.npz", **smplx)
    assert sequence["betas"].shape == (16,)
    motion = read_motion(tmp_path / "smplx.npz", body_model=tmp_path / "model.npz")
    assert motion.frame_rate == pytest.approx(59.94, rel=1e-12) and "16 betas" in motion.comments[0]
    # the first 4 betas shape the body; the 12 others are ignored, as SMPL's own code does
    expected = smpl_joint_positions(model, {**sequence, "betas": sequence["betas"][:4]})
    positions = reference_forward_kinematics(motion, with_rotations=False)[0]
    assert np.abs(positions - expected).max() <= 1e-12 * motion.size
    del smplx["mocap_frame_rate"]
    np.savez(tmp_path / "no_rate.npz", **smplx)
    with pytest.raises(MotionFileError, match="mocap_frame_rate"):
        read_motion(tmp_path / "no_rate.npz", body_model=tmp_path / "model.npz")


def test_bad_sequences_are_refused_naming_the_field(amass_files, tmp_path):
    model_path, _, _, sequence = amass_files

    def refused(name: str, match: str, **changes) -> None:
        arrays = {k: v for k, v in {**sequence, **changes}.items() if v is not None}
        np.savez(tmp_path / name, **arrays)
        with pytest.raises(MotionFileError, match=match) as caught:
            read_motion(tmp_path / name, body_model=model_path)
        assert name in str(caught.value)

    refused("no_poses.npz", r"no 'poses' array \(\(F, 3K\) axis-angle\)", poses=None)
    refused("no_trans.npz", r"no 'trans' array", trans=None)
    refused("no_rate.npz", r"no 'mocap_frame_rate' array", mocap_framerate=None)
    refused("nan.npz", "'trans' holds NaN or infinite values", trans=np.full((25, 3), np.nan))
    refused("text.npz", "'poses' is not numeric", poses=np.array(["a", "b"]))
    refused(
        "zero_rate.npz",
        "mocap_framerate must be a positive number of frames per second, not 0.0",
        mocap_framerate=np.array(0.0),
    )
    refused("negative_rate.npz", "not -30.0", mocap_framerate=np.array(-30.0))
    refused("flat_poses.npz", r"poses must be \(F, 3K\) and trans \(F, 3\)", poses=np.zeros(25 * 156))
    refused("not_by_3.npz", r"poses must be \(F, 3K\)", poses=np.zeros((25, 155)))
    refused("short_trans.npz", r"not \(25, 156\) and \(24, 3\)", trans=np.zeros((24, 3)))


def test_without_betas_the_template_shape_and_the_comments(amass_files, tmp_path):
    model_path, _, model, sequence = amass_files
    plain = {k: v for k, v in sequence.items() if k != "betas"}
    np.savez(tmp_path / "plain.npz", **{**plain, "gender": np.array("male")})
    motion = read_motion(tmp_path / "plain.npz", body_model=model_path)
    expected = smpl_joint_positions(model, {**sequence, "betas": np.zeros(N_BETAS)})
    assert np.abs(reference_forward_kinematics(motion, with_rotations=False)[0] - expected).max() <= 1e-12
    assert motion.comments == ("AMASS/SMPL motion plain.npz, body model model.npz, gender male, 0 betas",)
    assert motion.convention == "post" and set(motion.rotation_orders) == {"ZYX"}
    assert list(np.flatnonzero(motion.has_translation)) == [0] and motion.parents[0] < 0
    np.savez(tmp_path / "no_gender.npz", **{k: v for k, v in plain.items() if k != "gender"})
    assert "gender ?," in read_motion(tmp_path / "no_gender.npz", body_model=model_path).comments[0]
    np.savez(tmp_path / "gender_bytes.npz", **{**plain, "gender": np.array([b"female"])})
    assert "gender [b'female']" in read_motion(tmp_path / "gender_bytes.npz", body_model=model_path).comments[0]


def test_a_rate_stored_as_an_array_gives_its_first_value(amass_files, tmp_path):
    model_path, _, _, sequence = amass_files
    rates = (("one.npz", np.array([60.0])), ("two.npz", np.array([[50.0, 25.0]])), ("slow.npz", np.array(0.5)))
    for name, rate in rates:  # a frame every 2 s is a rate too
        np.savez(tmp_path / name, **{**sequence, "mocap_framerate": rate})
        assert read_motion(tmp_path / name, body_model=model_path).frame_rate == pytest.approx(rate.flat[0])


def test_tiny_rotations_keep_their_off_diagonal_terms_to_rounding(rng):
    # below 1e-8 rad the series is used: its second-order term still shows relative to the first
    directions = rng.normal(size=(50, 3))
    rotvecs = directions / np.linalg.norm(directions, axis=-1, keepdims=True) * rng.uniform(1e-10, 9e-9, (50, 1))
    ours, theirs = matrices_from_axis_angle(rotvecs), Rotation.from_rotvec(rotvecs).as_matrix()
    off = ~np.eye(3, dtype=bool)
    np.testing.assert_allclose(ours[:, off], theirs[:, off], rtol=1e-12, atol=0)


def test_the_roots_offset_is_its_rest_joint_and_options_are_keywords(amass_files):
    from gmr_studio.core.formats.amass import read_amass

    model_path, motion_path, model, sequence = amass_files
    motion = read_amass(motion_path, body_model=model_path)
    rest = model["J_regressor"] @ (model["v_template"] + model["shapedirs"] @ sequence["betas"])
    np.testing.assert_allclose(motion.offsets[0], rest[0], rtol=0, atol=1e-15)  # the pelvis where the model puts it
    np.testing.assert_allclose(motion.offsets[1], rest[1] - rest[0], rtol=0, atol=1e-15)
    with pytest.raises(TypeError):
        read_amass(motion_path, model_path)  # the body model is named, never positional


def test_no_rotation_at_all_is_the_identity_without_a_warning():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no 0 / 0 on the way, even in the branch thrown away
        np.testing.assert_array_equal(matrices_from_axis_angle(np.zeros((3, 3))), np.broadcast_to(np.eye(3), (3, 3, 3)))

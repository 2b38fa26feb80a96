"""The node tree of a glTF file (core.formats.gltf_in.scene): deep chains and cycles, matrices
at the affine tolerance, mirrored, or flattening an axis; zero and unnormalised quaternions;
skins and animations chosen by name or index; the scene's roots; the joints of a skin in
depth-first order with the nodes between them and the armature above."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats.gltf_in.container import GltfDocument
from gmr_studio.core.formats.gltf_in.scene import choose, node_parents, scene_roots, skeleton_nodes, static_trs


def document(nodes: list[dict], **fields) -> GltfDocument:
    return GltfDocument("scene.gltf", {"asset": {"version": "2.0"}, "nodes": nodes, **fields}, None)


def chain(n: int) -> list[dict]:
    return [{"children": [k + 1]} for k in range(n - 1)] + [{}]


# ------------------------------------------------------------------------ parents
def test_a_chain_of_any_depth_is_no_cycle():
    assert node_parents(document(chain(5))).tolist() == [-1, 0, 1, 2, 3]
    assert node_parents(document([{}, {"children": [0]}])).tolist() == [1, -1]


@pytest.mark.parametrize(
    ("nodes", "message"),
    [
        ([{"children": 1}, {}], "node 0: 'children' must be an array of node indices"),
        ([{"children": [0]}], "node 0 has two parents (-1 and 0) or is its own child"),
        ([{"children": [2]}, {"children": [2]}, {}], "node 2 has two parents (0 and 1) or is its own child"),
        ([{}, {"children": [2]}, {"children": [1]}], "the node tree has a cycle through node 1"),
    ],
)
def test_bad_trees_are_refused(nodes, message):
    with pytest.raises(MotionFileError) as caught:
        node_parents(document(nodes))
    assert caught.value.message == message


# ------------------------------------------------------------------------ static TRS
def _column_major(linear: np.ndarray, translation) -> list[float]:
    matrix = np.eye(4)
    matrix[:3, :3], matrix[:3, 3] = linear, translation
    return matrix.T.ravel().tolist()


def test_matrices_become_trs_mirrors_with_one_negative_scale():
    """Scaled unevenly (determinant 3), shrunk (0.125, between 0 and 1), mirrored
    (-0.5, between -1 and 0): T R S again, one negative scale for the mirror only."""
    turn = Rotation.from_rotvec([0.2, -0.5, 0.9])
    scales = ([2.0, 3.0, 0.5], [0.5, 0.5, 0.5], [-0.5, 1.0, 1.0])
    linears = [turn.as_matrix() @ np.diag(scale) for scale in scales]
    t, q, s = static_trs(document([{"matrix": _column_major(linear, [1, 2, k])} for k, linear in enumerate(linears)]))
    np.testing.assert_allclose(t, [[1, 2, 0], [1, 2, 1], [1, 2, 2]], rtol=0, atol=1e-15)
    np.testing.assert_allclose(s, scales, rtol=0, atol=1e-14)
    for k, linear in enumerate(linears):
        np.testing.assert_allclose(Rotation.from_quat(q[k]).as_matrix() @ np.diag(s[k]), linear, rtol=0, atol=1e-14)
    assert abs(q[0] @ turn.as_quat()) == pytest.approx(1.0, abs=1e-14)


def test_a_matrix_last_row_within_its_tolerance_is_affine():
    matrix = _column_major(np.eye(3), [0, 0, 0])
    matrix[3] = 1e-6  # the last row's first number (column-major)
    assert static_trs(document([{"matrix": matrix}]))[2].tolist() == [[1, 1, 1]]
    matrix[3] = 2e-6
    with pytest.raises(
        MotionFileError, match=r"node 0: its matrix is not an affine transform \(last row \[2e-06, 0.0, 0.0, 1.0\]\)"
    ):
        static_trs(document([{"matrix": matrix}]))


def test_a_matrix_flattening_an_axis_is_refused():
    matrix = _column_major(np.diag([1.0, 0.0, 1.0]), [0, 0, 0])
    with pytest.raises(MotionFileError, match=r"node 0: its matrix collapses an axis \(scale 0\)"):
        static_trs(document([{"matrix": matrix}]))


def test_trs_defaults_and_quaternions_normalised_or_the_identity():
    nodes = [{}, {"rotation": [0, 0, 0, 0], "translation": [1, 2, 3], "scale": [2, 2, 2]}, {"rotation": [0, 3, 0, 4]}]
    t, q, s = static_trs(document(nodes))
    np.testing.assert_array_equal(t, [[0, 0, 0], [1, 2, 3], [0, 0, 0]])
    np.testing.assert_array_equal(q, [[0, 0, 0, 1], [0, 0, 0, 1], [0, 0.6, 0, 0.8]])
    np.testing.assert_array_equal(s, [[1, 1, 1], [2, 2, 2], [1, 1, 1]])


# ------------------------------------------------------------------------ choosing
def test_choose_by_default_index_digits_or_name_with_its_note():
    doc = document([{}], skins=[{"name": "body", "joints": [0]}, {"joints": [0]}])
    assert choose(doc, "skins", None, "--skin") == (0, "skin 0 'body' of 2 (--skin to choose)")
    assert choose(doc, "skins", 0, "--skin") == (0, "skin 0 'body' of 2 (--skin to choose)")
    assert choose(doc, "skins", 1, "--skin") == (1, "skin 1 of 2 (--skin to choose)")
    assert choose(doc, "skins", "1", "--skin") == (1, "skin 1 of 2 (--skin to choose)")
    assert choose(doc, "skins", "body", "--skin") == (0, "skin 0 'body' of 2 (--skin to choose)")
    single = document([{}], animations=[{"name": "walk"}])
    assert choose(single, "animations", None, "--animation") == (0, "animation 0 'walk'")
    assert choose(single, "skins", None, "--skin") == (None, "")


@pytest.mark.parametrize(
    ("wanted", "message"),
    [
        (2, "--skin 2: the file has 2 skins (0..1)"),
        (-1, "--skin -1: the file has 2 skins (0..1)"),
        ("leg", "--skin 'leg': no skin of that name (the file has 'body', '')"),
    ],
)
def test_choose_refuses_what_is_not_there(wanted, message):
    doc = document([{}], skins=[{"name": "body", "joints": [0]}, {"joints": [0]}])
    with pytest.raises(MotionFileError) as caught:
        choose(doc, "skins", wanted, "--skin")
    assert caught.value.message == message
    with pytest.raises(MotionFileError) as caught:
        choose(document([{}]), "animations", 0, "--animation")
    assert caught.value.message == "--animation 0: the file has no animations"


# ------------------------------------------------------------------------ scene and skeleton
def test_scene_roots_of_the_chosen_scene_or_every_top_node():
    nodes = [{"children": [1]}, {}, {}, {"children": [4]}, {}]
    parents = node_parents(document(nodes))
    assert scene_roots(document(nodes), parents) == [0, 2, 3]
    assert scene_roots(document(nodes, scenes=[{"nodes": [0]}, {"nodes": [3, 2]}]), parents) == [0]
    assert scene_roots(document(nodes, scenes=[{"nodes": [0]}, {"nodes": [3, 2]}], scene=1), parents) == [3, 2]
    for scenes, message in (
        ([{"nodes": 3}], "scene: 'nodes' must be an array of node indices"),
        ([{"nodes": [1]}], "scene: node 1 is listed as a scene root but has a parent"),
    ):
        with pytest.raises(MotionFileError) as caught:
            scene_roots(document(nodes, scenes=scenes), parents)
        assert caught.value.message == message


def test_without_a_skin_every_scene_node_is_a_joint_depth_first():
    nodes = [{"children": [2, 1]}, {"children": [3]}, {}, {}, {}]
    doc = document(nodes, scenes=[{"nodes": [0]}])
    assert skeleton_nodes(doc, node_parents(doc), None) == ([0, 2, 1, 3], [])
    empty = document(nodes, scenes=[{"nodes": []}])
    with pytest.raises(MotionFileError, match="the file has no skin and its scene has no nodes"):
        skeleton_nodes(empty, node_parents(empty), None)


def test_a_skins_joints_the_nodes_between_them_and_the_armature_above():
    """0 scene root above armature 1; joints 2 (listed), 3 (between 2 and 5, not listed),
    5, 6 (a second branch under 2, listed first), 7 (a joint of another tree under 0,
    listed, with 8 between it and nothing: 8 is above it, not between)."""
    nodes = [
        {"children": [1, 8]},
        {"children": [2]},
        {"children": [6, 3]},
        {"children": [5, 4]},
        {},
        {},
        {},
        {},
        {"children": [7]},
    ]
    doc = document(nodes, skins=[{"joints": [6, 7, 5, 2]}])
    joints, above = skeleton_nodes(doc, node_parents(doc), 0)
    assert joints == [2, 6, 3, 5, 7] and above == [0, 1, 8]


@pytest.mark.parametrize(("listed", "message"), [([], "'joints' must be a non-empty array"), (7, "'joints' must be")])
def test_a_skin_without_joints_is_refused(listed, message):
    doc = document([{}], skins=[{"joints": listed}])
    with pytest.raises(MotionFileError, match=f"skin 0: {message}"):
        skeleton_nodes(doc, node_parents(doc), 0)


def test_the_nodes_between_node_0_and_a_joint_below_it_are_joints():
    doc = document(chain(3), skins=[{"joints": [2, 0]}])
    assert skeleton_nodes(doc, node_parents(doc), 0) == ([0, 1, 2], [])


@pytest.mark.parametrize(
    "linear",
    [
        np.array([[1.0, 0.3, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),  # a shear of x by y
        np.array([[1.0, 2.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 1.0]]),  # singular: two parallel columns
        Rotation.from_rotvec([0.2, -0.5, 0.9]).as_matrix() @ np.array([[1, 2e-5, 0], [0, 1, 0], [0, 0, 1]]),
    ],
)
def test_a_matrix_that_shears_or_is_singular_is_refused(linear):
    """A node matrix must be T R S (glTF 2.0, 'Transformations'): columns scaled to unit
    length form a rotation. A shear, even small, or two parallel columns (determinant 0),
    cannot be one and is refused with the node and how far it is from a rotation."""
    with pytest.raises(MotionFileError, match=r"node 0: its matrix shears \(.* by [0-9.e-]+\), so it is no"):
        static_trs(document([{"matrix": _column_major(linear, [0, 0, 0])}]))


def test_a_float32_rotation_and_scale_is_not_a_shear():
    """Real files store matrices in float32: a rotation times uneven scales rounded to float32
    stays within the tolerance and reads back as its T R S to float32 precision."""
    turn = Rotation.from_rotvec([1.1, 0.4, -2.3])
    linear = (turn.as_matrix() @ np.diag([0.01, 0.02, 0.03])).astype(np.float32).astype(float)
    t, q, s = static_trs(document([{"matrix": _column_major(linear, [0.5, 0, 0])}]))
    assert t.tolist() == [[0.5, 0, 0]]
    np.testing.assert_allclose(s, [[0.01, 0.02, 0.03]], rtol=1e-6)
    assert abs(q[0] @ turn.as_quat()) == pytest.approx(1.0, abs=1e-12)


def test_a_mirror_with_tiny_scales_is_still_a_mirror():
    """The mirror is told by the unit columns' determinant: the matrix's own, a product of
    three scales of 1e-110, underflows to -0.0 and would read the mirror as a rotation."""
    turn = Rotation.from_rotvec([0.3, 0.2, -0.4])
    linear = turn.as_matrix() @ np.diag([-1e-110, 1e-110, 1e-110])
    assert np.linalg.det(linear) == 0.0  # the underflow this guards against
    _t, q, s = static_trs(document([{"matrix": _column_major(linear, [0, 0, 0])}]))
    np.testing.assert_allclose(s, [[-1e-110, 1e-110, 1e-110]], rtol=1e-14)
    np.testing.assert_allclose(Rotation.from_quat(q[0]).as_matrix() @ np.diag(s[0]), linear, rtol=0, atol=1e-124)


def test_a_shear_exactly_at_the_tolerance_is_kept(monkeypatch):
    """The shear allowed is at most SHEAR_TOLERANCE: a matrix exactly at it reads as T R S,
    one a float above it is refused."""
    import gmr_studio.core.formats.gltf_in.scene as scene_module

    linear = np.array([[1.0, 3e-6, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    unit = linear / np.linalg.norm(linear, axis=0)
    shear = float(np.abs(unit.T @ unit - np.eye(3)).max())
    monkeypatch.setattr(scene_module, "SHEAR_TOLERANCE", shear)
    assert static_trs(document([{"matrix": _column_major(linear, [0, 0, 0])}]))[2].shape == (1, 3)
    monkeypatch.setattr(scene_module, "SHEAR_TOLERANCE", np.nextafter(shear, 0.0))
    with pytest.raises(MotionFileError, match="its matrix shears"):
        static_trs(document([{"matrix": _column_major(linear, [0, 0, 0])}]))


def test_a_rotation_within_the_shear_tolerance_is_no_mirror():
    """Columns of unit length 5e-6 from perpendicular (inside the tolerance): the
    determinant is a hair under 1 (1 - 1.25e-11), still a rotation with positive scales."""
    linear = np.array([[1.0, 5e-6, 0.0], [0.0, np.sqrt(1 - 25e-12), 0.0], [0.0, 0.0, 1.0]])
    assert 0.999 < np.linalg.det(linear) < 1.0
    _t, q, s = static_trs(document([{"matrix": _column_major(linear, [0, 0, 0])}]))
    np.testing.assert_allclose(s, [[1.0, 1.0, 1.0]], rtol=0, atol=1e-15)
    assert abs(q[0][3]) == pytest.approx(1.0, abs=1e-10)  # nearly the identity, not a half turn

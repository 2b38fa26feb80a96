"""Mirror keeps the skeleton (issue 21, item 4): End Sites named with a side suffix
(``Hand_L_End``, ``Toes_R_End``) swap with their partners and stay End Sites."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.compare import compare_motions
from gmr_studio.core.edits.mirror import mirror, side_partners
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats.bvh import read_bvh, write_bvh
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.rigs import make_rig


def _parent_names(motion) -> dict[str, str | None]:
    return {n: (motion.names[p] if p >= 0 else None) for n, p in zip(motion.names, motion.parents)}


def test_end_sites_with_side_suffixes_swap_and_stay_end_sites(tmp_path):
    game = make_rig("game_root")
    sides = side_partners(game.names, game.parents)
    partner = {game.names[j]: game.names[k] for j, k in enumerate(sides.partner)}
    assert partner["Hand_L_End"] == "Hand_R_End" and partner["Toes_R_End"] == "Toes_L_End"
    assert partner["Head_End"] == "Head_End" and not sides.unmatched
    mirrored, unmatched = mirror(game)
    assert not unmatched and mirrored.names == game.names
    np.testing.assert_array_equal(mirrored.parents, game.parents)
    assert mirrored.rotation_orders == game.rotation_orders  # End Sites have no channels still
    # the BVH written: the same joints under the same parents, End Sites as End Sites
    write_bvh(game, tmp_path / "W.bvh")
    write_bvh(mirrored, tmp_path / "M.bvh")
    text = (tmp_path / "M.bvh").read_text()
    assert "JOINT Hand_R_End" not in text and "JOINT Hand_L_End" not in text and text.count("End Site") == 5
    before, after = read_bvh(tmp_path / "W.bvh"), read_bvh(tmp_path / "M.bvh")
    assert after.n_joints == before.n_joints == game.n_joints
    assert _parent_names(after) == _parent_names(before)
    result = compare_motions(before, after, offset=0)
    assert not result.unmatched_a and not result.unmatched_b
    # the left hand's end site follows the right one's path, reflected across the body (x)
    positions, moved = world_positions(game), world_positions(mirrored)
    left, right = game.names.index("Hand_L_End"), game.names.index("Hand_R_End")
    assert np.abs(moved[:, left, 1:] - positions[:, right, 1:]).max() < 1e-12
    plane = moved[:, left, 0] + positions[:, right, 0]  # twice the plane's x, every frame
    assert np.ptp(plane) < 1e-12 and np.abs(moved[:, left, 0] - positions[:, left, 0]).max() > 0.01


def test_mirror_twice_is_the_identity_on_the_game_rig():
    game = make_rig("game_root")
    back = mirror(mirror(game)[0])[0]
    assert back.names == game.names and np.array_equal(back.parents, game.parents)
    assert np.abs(world_positions(back) - world_positions(game)).max() <= 1e-12 * game.size


def test_a_mirror_that_would_move_a_joint_to_another_parent_is_refused():
    game = make_rig("game_root")
    names = list(game.names)
    names[names.index("Hand_L_End")] = "TipA"
    names[names.index("Hand_R_End")] = "TipB"
    with pytest.raises(OperationError, match="would change the skeleton: the link 'Hand_L' - 'TipA'"):
        mirror(game.replace(names=tuple(names)))

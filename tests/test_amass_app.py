"""The app opens AMASS .npz motions with the body model set in its settings, and without
one says what to pass."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.kinematics.fk import world_positions
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.test_amass import smpl_joint_positions, synthetic_model, synthetic_sequence

pytestmark = pytest.mark.gui
studio = app_fixtures.studio


def test_open_amass_with_the_body_model_setting(qtbot, studio, tmp_path, rng):
    model, sequence = synthetic_model(rng), synthetic_sequence(rng)
    np.savez(tmp_path / "model.npz", **model)
    np.savez(tmp_path / "walk.npz", **sequence)
    studio.files.open_path(str(tmp_path / "walk.npz"), ask=False, wait=True)
    assert studio.state.motion is None and "--body-model" in studio.status.text()
    studio.files.settings.setValue("body_model", str(tmp_path / "model.npz"))
    open_file(studio, tmp_path / "walk.npz")
    motion = studio.state.motion
    assert motion.n_joints == 52 and motion.n_frames == 25
    expected = smpl_joint_positions(model, sequence)
    assert np.abs(world_positions(motion) - expected).max() <= 1e-12 * motion.size
    assert studio.actions["body_model"] in studio.menuBar().actions()[0].menu().actions()

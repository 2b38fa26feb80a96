"""Arrays handed from a child process through a file come back as they were written: every
dtype, shape and value, the header as JSON; a file cut short or of another kind is refused."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.array_transfer import read_arrays, write_arrays


def test_arrays_and_header_come_back_equal(tmp_path, rng):
    arrays = {
        "rotations": rng.normal(size=(7, 2, 3, 3)),
        "keys": rng.normal(size=11).astype(np.float32),
        "ticks": rng.integers(-(2**40), 2**40, 5),
        "one frame": np.ones((1, 3)),
        "none": np.zeros((0, 3)),
    }
    header = {"frames": 7, "names": ["Hips", "Spine"], "rate": 120.00048}
    write_arrays(tmp_path / "result", header, arrays)
    got_header, got = read_arrays(tmp_path / "result")
    assert got_header == header and list(got) == list(arrays)
    for name, array in arrays.items():
        assert got[name].dtype == array.dtype and got[name].shape == array.shape
        np.testing.assert_array_equal(got[name], array)


def test_a_list_of_rows_comes_back_as_their_stack(tmp_path, rng):
    block = rng.normal(size=(3, 1000))
    rows = [block[0], block[1].copy(), block[2, ::-1][::-1]]  # views and copies alike
    write_arrays(tmp_path / "result", {}, {"rows": rows, "empty": [], "after": np.arange(4)})
    _, got = read_arrays(tmp_path / "result")
    np.testing.assert_array_equal(got["rows"], block)
    assert got["empty"].shape == (0,)
    np.testing.assert_array_equal(got["after"], np.arange(4))
    with pytest.raises(ValueError, match="differ"):
        write_arrays(tmp_path / "bad", {}, {"rows": [block[0], block[1, :10]]})


def test_a_cut_or_foreign_file_is_refused(tmp_path, rng):
    write_arrays(tmp_path / "result", {}, {"values": rng.normal(size=1000)})
    whole = (tmp_path / "result").read_bytes()
    (tmp_path / "cut").write_bytes(whole[: len(whole) // 2])
    with pytest.raises(ValueError, match="cut short"):
        read_arrays(tmp_path / "cut")
    (tmp_path / "other").write_bytes(b"PK\x03\x04 an npz")
    with pytest.raises(ValueError, match="not an array transfer file"):
        read_arrays(tmp_path / "other")

"""A user's system from a file (lcpfric.model.files): JSON and .npz give the system the keys
describe, B = 0 is the uncoupled system bit for bit, and every bad field is named."""

import json

import numpy as np
import pytest

import lcpfric
from lcpfric.errors import InputError
from lcpfric.model.files import load_system


def _chain():
    P1, Q1, phi = np.array([0.3, 0.5, 0.2]), np.array([0.4, 0.6, 0.3]), np.array([0.2, 2.0, 4.0])
    return lcpfric.chain(3, k_coupling=1.0, friction=0.5, P1=P1, Q1=Q1, phi=phi)


def _fields(n=3):
    return {
        "K": _chain().dense_stiffness().tolist(),
        "friction": 0.5,
        "P0": [1.0] * n,
        "P1": [0.3, 0.5, 0.2][:n],
        "psi": [0.0] * n,
        "Q0": [0.0] * n,
        "Q1": [0.4, 0.6, 0.3][:n],
        "phi": [0.2, 2.0, 4.0][:n],
    }


def _write(tmp_path, data, kind="json"):
    if kind == "json":
        path = tmp_path / "system.json"
        path.write_text(json.dumps(data))
    else:
        path = tmp_path / "system.npz"
        np.savez(path, **{k: np.asarray(v) for k, v in data.items()})
    return path


@pytest.mark.parametrize("kind", ["json", "npz"])
def test_a_file_is_the_system_its_keys_describe(tmp_path, kind):
    data = _fields()
    system, start = load_system(_write(tmp_path, data, kind))
    assert start is None and system.coupling is None
    want = _chain()
    np.testing.assert_array_equal(system.dense_stiffness(), want.dense_stiffness())
    t = np.linspace(0, 2 * np.pi, 17)
    np.testing.assert_allclose(system.tangential(t), want.tangential(t), atol=1e-15)
    np.testing.assert_allclose(system.normal.reactions(t), want.normal.reactions(t), atol=1e-15)


def test_b_zero_is_the_uncoupled_system_bit_for_bit(tmp_path):
    data = _fields()
    plain, _ = load_system(_write(tmp_path, data))
    data["B"] = np.zeros((3, 3)).tolist()
    zero, _ = load_system(_write(tmp_path, data))
    assert zero.coupling is None
    a, b = lcpfric.steady_state(plain, "exact"), lcpfric.steady_state(zero, "exact")
    assert a.W == b.W and np.array_equal(a.v, b.v)


def test_a_start_and_a_coupling_block_come_along(tmp_path):
    data = _fields()
    data["B"] = (0.2 * np.eye(3)).tolist()
    data["start"] = [0.01, -0.02, 0.0]
    data["omega"] = 2.0
    system, start = load_system(_write(tmp_path, data, "npz"))
    np.testing.assert_array_equal(start, [0.01, -0.02, 0.0])
    np.testing.assert_array_equal(system.coupling, 0.2 * np.eye(3))
    assert system.period == pytest.approx(np.pi)


@pytest.mark.parametrize(
    "change, field",
    [
        ({"K": [[1.0, 2.0]]}, "K"),
        ({"K": [[1.0, 2.0], [2.0, 1.0]]}, "P0"),  # a 2-node K against 3-node loads
        ({"P1": [0.3, -0.5, 0.2]}, "P1"),
        ({"phi": [0.1, float("nan"), 0.0]}, "phi"),
        ({"friction": [0.5, 0.0, 0.5]}, "friction"),
        ({"B": [[0.0] * 2] * 2}, "B"),
        ({"B": (5.0 * np.eye(3)).tolist()}, "coupling"),  # f |b| > k: not well posed
        ({"start": [0.0, 0.0]}, "start"),
        ({"omega": 0.0}, "omega"),
        ({"extra": 1.0}, "extra"),
        ({"K": [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]]}, "stiffness"),
    ],
)
def test_bad_fields_are_named(tmp_path, change, field):
    data = _fields()
    data.update(change)
    with pytest.raises(InputError, match=field):
        load_system(_write(tmp_path, data))


def test_missing_keys_and_unreadable_files_are_named(tmp_path):
    data = _fields()
    del data["Q1"]
    with pytest.raises(InputError, match="Q1.*missing"):
        load_system(_write(tmp_path, data))
    with pytest.raises(InputError, match="file"):
        load_system(tmp_path / "nothing.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(InputError, match="file.*JSON"):
        load_system(bad)
    with pytest.raises(InputError, match="file.*npz"):
        load_system(bad.rename(tmp_path / "bad.npz"))

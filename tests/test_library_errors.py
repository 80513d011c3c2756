"""The runtime refuses corrupt or mismatching generated code and compiled libraries, and bad
inputs, with an error that names the fix or the sample."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest
from conftest import GENERATED

from planar_sym.errors import InputError, LibraryError
from planar_sym.model.compile import build, library_path
from planar_sym.model.folders import read_manifest
from planar_sym.model.library import Library
from planar_sym.model.locate import load
from planar_sym.model.robot import Robot


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A private, empty compiled-library cache."""
    path = tmp_path / "cache"
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(path))
    return path


@pytest.fixture
def copy(tmp_path):
    dst = tmp_path / "serial_2dof"
    shutil.copytree(GENERATED / "serial_2dof", dst)
    return dst


def test_the_copy_loads_and_computes(copy, cache):
    """Control: the untouched copy compiles into the private cache and agrees with the default."""
    robot = Robot("serial_2dof", Library("serial_2dof", folder=copy))
    assert robot.library.path.parent == cache
    q = np.array([[0.3, -1.1], [2.0, 0.4]])
    np.testing.assert_array_equal(robot.mass_matrix(q), load("serial_2dof").mass_matrix(q))


def test_one_byte_changed_in_the_c_source(copy, cache):
    src = copy / "serial_2dof.c"
    data = bytearray(src.read_bytes())
    i = data.index(b"casadi_real") + 2
    data[i] ^= 0x01
    src.write_bytes(bytes(data))
    with pytest.raises(LibraryError, match="make derive") as info:
        Library("serial_2dof", folder=copy)
    assert "serial_2dof.c" in str(info.value)
    assert not cache.exists() or not list(cache.glob("*.so")), "compiled a corrupt source"


def test_missing_generated_file(copy, cache):
    (copy / "serial_2dof.h").unlink()
    with pytest.raises(LibraryError, match=r"serial_2dof\.h is missing.*make derive"):
        Library("serial_2dof", folder=copy)


def test_manifest_of_another_robot(copy, cache):
    with pytest.raises(LibraryError, match=r"serial_3dof.*make derive"):
        Library("serial_3dof", folder=copy)


def test_library_built_from_another_input_hash(copy, cache):
    """The manifest says hash B; the C source (and so the library) says hash A: refused."""
    path = copy / "manifest.json"
    m = json.loads(path.read_text())
    old = m["input_hash"]
    m["input_hash"] = "0123456789abcdef" * 4
    path.write_text(json.dumps(m, indent=2))
    with pytest.raises(LibraryError) as info:
        Library("serial_2dof", folder=copy)
    msg = str(info.value)
    assert old[:16] in msg and "0123456789abcdef" in msg
    assert "make build" in msg and "make derive" in msg


def test_cached_library_of_another_robot_is_rebuilt(copy, cache):
    """A library of serial_3dof sitting where serial_2dof's should be cannot be loaded as
    serial_2dof: it is rebuilt (with a warning), and the torques are serial_2dof's."""
    other = GENERATED / "serial_3dof"
    built = build(other, read_manifest(other), force=True)  # into the cache, not the install's
    target = library_path(copy, read_manifest(copy))
    assert built.parent == target.parent == cache and built != target
    shutil.copyfile(built, target)
    with pytest.warns(RuntimeWarning, match=r"does not match the hash.*rebuilding it"):
        lib = Library("serial_2dof", folder=copy)
    q = np.array([0.3, -0.4])
    # static torques at q: g1 = g (m1 lc1 + (mM + m2) a1) c1 + g m2 lc2 c12 (seed Table 1)
    g1 = 9.81 * ((0.071 * 0.0373 + (0.292 + 0.075) * 0.1) * np.cos(0.3)
                 + 0.075 * 0.04168 * np.cos(-0.1))
    assert abs(Robot("serial_2dof", lib, exact=True).gravity(q)[0] - g1) < 1e-12


# -- inputs -------------------------------------------------------------------------------------
def test_nan_input_names_the_sample():
    robot = load("serial_2dof")
    q = np.zeros((10, 2))
    qd = np.zeros((10, 2))
    qd[7, 1] = np.nan
    with pytest.raises(InputError, match=r"qd\[7, 1\].*sample 7"):
        robot.inverse_dynamics(q, qd, q)
    q[3, 0] = np.inf
    with pytest.raises(InputError, match="sample 3"):
        robot.mass_matrix(q)


@pytest.mark.parametrize("shape", [(10, 3), (10,), (2, 5, 2), (3,)])
def test_wrong_shape(shape):
    robot = load("serial_2dof")
    with pytest.raises(InputError, match=r"\(N, 2\)"):
        robot.inverse_dynamics(np.zeros(shape), np.zeros(shape), np.zeros(shape))


def test_sample_counts_must_agree():
    robot = load("serial_2dof")
    with pytest.raises(InputError, match="same number of samples"):
        robot.inverse_dynamics(np.zeros((4, 2)), np.zeros((5, 2)), np.zeros((4, 2)))


def test_unknown_parameter_and_closed_chain_misuse():
    with pytest.raises(InputError, match="m_link9"):
        load("serial_2dof").with_parameters(m_link9=1.0)
    with pytest.raises(InputError, match="closed chain"):
        load("five_bar_type1").inverse_dynamics(np.zeros(4), np.zeros(4), np.zeros(4))

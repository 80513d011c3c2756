"""The sample loops find a non-finite input while they copy it in (``derive/simd.py``,
``NONFINITE``), so the callers (``_fastcall.c``) need no pass of their own over the inputs.

* Every loop of a whole-loop robot (serial_2dof) and of a robot whose loops are cut into parts
  (serial_rpr at 23 statements a part), compiled the runtime's way (``-ffast-math``, which may
  fold ``x != x`` and ``isfinite`` away): NaN, +inf or -inf put in any input, in the first
  sample, the last of a full block, the first of the next and the last of a partial block,
  returns ``NONFINITE``; the same inputs finite, including +-1e308, return 0.
* Through the robot's methods, the message names the input, the entry and the sample exactly as
  the callers' own pass does (a caller made for a library derived before the loops checked):
  the two give the same text, and the library's manifest says its loops check.
"""

from __future__ import annotations

import ctypes
import json
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from derive import simd
from derive.codegen import LOOPED
from planar_sym.errors import InputError
from planar_sym.model.compile import SIMD_CFLAGS, compile_shared, fastcall
from planar_sym.model.locate import load

ROOT = Path(__file__).resolve().parent.parent
N = 40  # a full block of 32 and a partial one of 8
WHERE = [0, 31, 32, N - 1]


def _compiled(tmp_path: Path, robot: str, part_ops: int | None):
    folder = ROOT / "generated" / robot
    manifest = json.loads((folder / "manifest.json").read_text())
    fns = [ca.Function.load(str(folder / f"{q}.casadi"))
           for q in manifest["functions"] if q in LOOPED]
    pieces = [piece for f in fns for piece in simd.loop_parts(f, part_ops=part_ops)]
    source, _ = simd.assemble(pieces)
    src = tmp_path / "loops.c"
    src.write_text(source)
    lib = ctypes.CDLL(str(compile_shared([src], tmp_path / "loops.so", SIMD_CFLAGS,
                                         extra=("-Wall", "-Werror"))))
    p = np.array([par["value"] for par in manifest["parameters"]])
    return lib, fns, p


def _status(lib, f, arrays) -> int:
    fn = getattr(lib, f"{f.name()}_loop")
    fn.restype = ctypes.c_int
    outs = [np.zeros((N, f.nnz_out(o))) for o in range(f.n_out())]
    return fn(ctypes.c_longlong(N),
              (ctypes.c_void_p * len(arrays))(*[a.ctypes.data for a in arrays]),
              (ctypes.c_void_p * len(outs))(*[o.ctypes.data for o in outs]))


@pytest.mark.parametrize(("robot", "part_ops"), [("serial_2dof", None), ("serial_rpr", 23)])
def test_every_loop_reports_a_value_that_is_not_finite(robot, part_ops, tmp_path):
    lib, fns, p = _compiled(tmp_path, robot, part_ops)
    if part_ops:
        assert all(len(simd.loop_parts(f, part_ops=part_ops)) > 1 for f in fns)
    rng = np.random.default_rng(5)
    for f in fns:
        ins = [p if f.name_in(i) == "p" else rng.uniform(-1.5, 1.5, (N, f.nnz_in(i)))
               for i in range(f.n_in())]
        assert _status(lib, f, ins) == 0, f.name()
        huge = [a if f.name_in(i) == "p" else np.where(a > 0, 1e308, -1e308)
                for i, a in enumerate(ins)]
        assert _status(lib, f, huge) == 0, f.name()  # big is not infinite
        for i in (i for i in range(f.n_in()) if f.name_in(i) != "p"):
            for k, bad in zip(WHERE, (np.nan, np.inf, -np.inf, np.nan)):
                spoilt = [a.copy() for a in ins]
                spoilt[i][k, f.nnz_in(i) - 1] = bad
                assert _status(lib, f, spoilt) == simd.NONFINITE, (f.name(), i, k, bad)


def test_the_callers_name_the_bad_entry_as_their_own_pass_did():
    robot = load("serial_2dof")
    assert robot.library.manifest["loops_check_inputs"] is True
    rng = np.random.default_rng(8)
    q, qd, qdd = (rng.uniform(-1, 1, (N, 2)) for _ in range(3))
    spec = robot.library.manifest["functions"]["inverse_dynamics"]
    own_pass = fastcall().make(robot.library.loop_address("inverse_dynamics"), (2, 2, 2), 3,
                               ((2, 1, 1),), robot.p, InputError, ("q", "qd", "qdd"),
                               spec["doc"], False)
    np.testing.assert_allclose(robot.inverse_dynamics(q, qd, qdd), own_pass(q, qd, qdd),
                               rtol=1e-15)
    for k, c, bad in ((0, 0, np.nan), (31, 1, np.inf), (32, 0, -np.inf), (N - 1, 1, np.nan)):
        spoilt = qd.copy()
        spoilt[k, c] = bad
        with pytest.raises(InputError) as fused:
            robot.inverse_dynamics(q, spoilt, qdd)
        with pytest.raises(InputError) as scanned:
            own_pass(q, spoilt, qdd)
        assert str(fused.value) == str(scanned.value) == (
            f"qd[{k}, {c}] is {bad!r} at sample {k}: inputs must be finite")
    with pytest.raises(InputError, match=r"^q\[0, 1\] is nan at sample 0: inputs must be "
                                         r"finite$"):
        robot.mass_matrix(np.array([0.1, np.nan]))

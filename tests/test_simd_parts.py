"""Sample loops cut into parts (``derive/simd.py``, issue 28): a loop longer than ``PART_OPS``
statements becomes part functions that pass a block's values through a buffer, and the parts
are shared out into compile units. Checked against CasADi's own evaluation of the same function
(an independent evaluator of the same graph), with the cuts forced small on the built-in robots'
loops so that every kind of crossing value occurs (kept, redone input loads and constants,
outputs made in an early part, parameters), each unit compiled on its own as the runtime builds
it; and the bound itself: no function of a 16-link chain's loops exceeds ``PART_OPS`` statements
and no compile unit ``UNIT_OPS`` (before the cut one 16-link loop held 7,000 statements, and
gcc took over 12 minutes on the 20-link one).
"""

from __future__ import annotations

import ctypes
import json
import re
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from derive import simd
from derive.codegen import LOOPED
from planar_sym.model.compile import SIMD_CFLAGS, compile_shared

ROOT = Path(__file__).resolve().parent.parent
#: a tree with a slider, a closed chain (its loop functions too), the 3-RRR (7 coordinates),
#: each with the statements per part that cut every one of its loops
ROBOTS = [("serial_rpr", 23), ("five_bar_type1", 23), ("parallel_3rrr", 60)]


def _loops(robot: str):
    folder = ROOT / "generated" / robot
    manifest = json.loads((folder / "manifest.json").read_text())
    fns = {q: ca.Function.load(str(folder / f"{q}.casadi"))
           for q in manifest["functions"] if q in LOOPED}
    return manifest, fns


def _build(tmp_path: Path, pieces, unit_ops: int) -> ctypes.CDLL:
    """The pieces compiled the runtime's way: one object per compile unit, linked."""
    source, unit_operations = simd.assemble(pieces, unit_ops=unit_ops)
    src = tmp_path / "loops.c"
    src.write_text(source)
    lib = compile_shared([src], tmp_path / "loops.so", SIMD_CFLAGS, extra=("-Wall", "-Werror"),
                         units=[(f"-DPLANAR_SYM_UNIT={k}",) for k in range(len(unit_operations))])
    return ctypes.CDLL(str(lib)), unit_operations


def _run(lib, name: str, arrays: list[np.ndarray], outs: list[np.ndarray]) -> None:
    fn = getattr(lib, f"{name}_loop")
    fn.restype = ctypes.c_int
    status = fn(ctypes.c_longlong(len(outs[0])),
                (ctypes.c_void_p * len(arrays))(*[a.ctypes.data for a in arrays]),
                (ctypes.c_void_p * len(outs))(*[o.ctypes.data for o in outs]))
    assert status == 0


@pytest.mark.parametrize(("robot", "part_ops"), ROBOTS, ids=[r for r, _ in ROBOTS])
def test_loops_cut_into_small_parts_give_casadi_s_values(robot, part_ops, tmp_path):
    manifest, fns = _loops(robot)
    p = np.array([par["value"] for par in manifest["parameters"]])
    pieces = [piece for f in fns.values() for piece in simd.loop_parts(f, part_ops=part_ops)]
    cut = sum(1 for f in fns.values() if len(simd.loop_parts(f, part_ops=part_ops)) > 1)
    assert cut == len(fns)  # every loop is cut
    lib, unit_operations = _build(tmp_path, pieces, unit_ops=4 * part_ops)
    assert len(unit_operations) > 3
    rng = np.random.default_rng(3)
    n = 37  # a full block of 32 and a partial one
    worst = 0.0
    for quantity, f in fns.items():
        ins = [p if f.name_in(i) == "p" else rng.uniform(-1.5, 1.5, (n, f.nnz_in(i)))
               for i in range(f.n_in())]
        outs = [np.full((n, f.nnz_out(o)), np.nan) for o in range(f.n_out())]
        _run(lib, f.name(), ins, outs)
        for k in range(n):
            ref = f.call([a if f.name_in(i) == "p" else a[k] for i, a in enumerate(ins)])
            for o, (got, r) in enumerate(zip(outs, ref)):
                rows, cols = f.size1_out(o), f.size2_out(o)
                want = np.asarray(r.full()).reshape(rows, cols).reshape(-1)  # row-major
                scale = 1 + np.max(np.abs(want))  # round-off of a sum is relative to its terms
                worst = max(worst, float(np.max(np.abs(got[k] - want)) / scale))
        assert np.all(np.isfinite(np.concatenate([o.ravel() for o in outs]))), quantity
    assert worst < 1e-12, worst


def test_a_loop_within_the_bound_is_one_piece_as_before():
    _, fns = _loops("serial_2dof")
    for f in fns.values():
        ((source, statements),) = simd.loop_parts(f)
        assert "_part" not in source and statements <= simd.PART_OPS


def test_no_function_or_unit_of_a_16_link_chain_outgrows_the_bound(tmp_path):
    from benchmarks.chains import write_chain
    from derive.codegen import render
    from planar_sym.model import description

    desc = description.load(write_chain(16, tmp_path))
    files = render(desc, equations="structure")
    manifest = json.loads(files["manifest.json"])
    src = files["chain_16_simd.c"].decode()
    # operations per C function: the `const double tK = ...;` lines of one function's body that
    # compute (not a value read back from the block's buffer, an input load or a constant)
    bodies = re.split(r"\n(?:PLANAR_SYM_EXPORT int|PLANAR_SYM_PART void) ", src)[1:]
    computed = re.compile(r"const double t\d+ = (?!live\[|ib\d+\[|-?[0-9])")
    per_function = [len(computed.findall(b)) for b in bodies]
    assert max(per_function) <= simd.PART_OPS
    assert sum(per_function) > 5 * simd.PART_OPS  # the chain is big enough to need cuts
    assert max(manifest["compile_units"]["simd"]) <= simd.UNIT_OPS
    biggest = max(fn["operations"] for q, fn in manifest["functions"].items() if q in LOOPED)
    assert biggest > 2 * simd.PART_OPS  # without the cut, one function would hold this

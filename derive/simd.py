"""Vectorisable sample loops: CasADi's own CSE'd instruction list printed as straight-line C.

CasADi's generated functions evaluate one sample through a work array; called in a loop they
cost ~60 ns per 2-DOF sample, mostly scalar sin/cos. Here the same algorithm (the SX
instructions of the same CasADi function, so the same operations in the same order) is
printed as ``const double`` locals inside a loop over samples, which gcc vectorises across
samples with ``-O3 -march=native -ffast-math``, calling glibc's vector sin/cos (libmvec).

Two details make or break that vectorisation:

* ``cos(x)`` is printed as ``sin(x + pi/2)``: gcc fuses a ``sin``/``cos`` pair of one argument
  into ``sincos``, which has no vector variant, and that one call blocks the whole loop;
* inputs and outputs keep the runtime's row-major ``(N, size)`` layout (strided loads cost less
  than transposing the arrays first), matrices written row-major so no transpose follows;
* samples go in blocks: each block's inputs are copied into sample-contiguous buffers, the
  outputs stored the same way and copied out after. gcc 12 vectorises interleaved accesses
  only in groups of 2^k or 3 per sample, so the 3-RRR's 7 coordinates (and its 7x7 mass
  matrix) would otherwise keep its loops scalar;
* parameters are read into locals before the loop;

Every loop has one signature, so the runtime can call any of them the same way:
``int <robot>_<quantity>_loop(long long n, const double *const *in, double *const *out)``.
"""

from __future__ import annotations

import casadi as ca

_BINARY = {ca.OP_ADD: "({} + {})", ca.OP_SUB: "({} - {})", ca.OP_MUL: "({} * {})",
           ca.OP_DIV: "({} / {})", ca.OP_POW: "pow({}, {})", ca.OP_CONSTPOW: "pow({}, {})",
           ca.OP_ATAN2: "atan2({}, {})", ca.OP_FMIN: "fmin({}, {})", ca.OP_FMAX: "fmax({}, {})"}
_UNARY = {ca.OP_NEG: "(-{})", ca.OP_SIN: "sin({})", ca.OP_COS: "sin({} + M_PI_2)",
          ca.OP_TAN: "tan({})", ca.OP_SQ: "({0} * {0})", ca.OP_SQRT: "sqrt({})",
          ca.OP_TWICE: "(2.0 * {})", ca.OP_INV: "(1.0 / {})", ca.OP_FABS: "fabs({})",
          ca.OP_EXP: "exp({})", ca.OP_LOG: "log({})", ca.OP_ASSIGN: "{}",
          ca.OP_TANH: "tanh({})"}

PRELUDE = """#include <math.h>
/* compile units: built whole, or as units compiled in parallel, one per -DPLANAR_SYM_UNIT=k
   (the manifest's compile_units), each holding some of the loops */
#ifdef PLANAR_SYM_UNIT
#define PLANAR_SYM_ALL 0
#else
#define PLANAR_SYM_ALL 1
#define PLANAR_SYM_UNIT 0
#endif
/* samples per block: outputs are stored per block in sample-contiguous order (which gcc
   vectorises; interleaved groups of 49 stores would block it) and then copied out */
#define BLOCK 32
#ifndef M_PI_2
#define M_PI_2 1.57079632679489661923
#endif
#if defined(_WIN32)
#define PLANAR_SYM_EXPORT __declspec(dllexport)
#else
#define PLANAR_SYM_EXPORT __attribute__((visibility("default")))
#endif
"""


#: operations per compile unit: gcc's time and memory grow faster than the length of one
#: function, so big robots' loops are compiled as several units, in parallel
UNIT_OPS = 3000


def units(operations: list[int]) -> list[int]:
    """The compile unit of each loop, in file order: a new unit once ``UNIT_OPS`` is full (a
    robot whose loops all fit in one compiles as one unit, as before)."""
    out, unit, filled = [], 0, 0
    for ops in operations:
        if filled and filled + ops > UNIT_OPS:
            unit, filled = unit + 1, 0
        out.append(unit)
        filled += ops
    return out


def in_unit(unit: int, source: str) -> str:
    """``source`` compiled only in unit ``unit`` (and in a whole-file build)."""
    return f"#if PLANAR_SYM_ALL || PLANAR_SYM_UNIT == {unit}\n{source}#endif\n"


def _row_major(f: ca.Function, out: int, nz: int) -> int:
    """Index of dense column-major nonzero ``nz`` of output ``out`` in row-major order."""
    rows, cols = f.size1_out(out), f.size2_out(out)
    return (nz % rows) * cols + nz // rows


def _statements(f: ca.Function, ins, offsets):
    """(variable, C expression, used variables) per instruction, stores, hoisted p loads."""
    stmts, stores, current, hoisted = [], [], {}, {}
    for k in range(f.n_instructions()):
        op, a, r = f.instruction_id(k), f.instruction_input(k), f.instruction_output(k)
        if op == ca.OP_OUTPUT:
            stores.append((offsets[r[0]] + _row_major(f, r[0], r[1]), current[a[0]]))
            continue
        args = [current[x] for x in a] if op not in (ca.OP_INPUT, ca.OP_CONST) else []
        if op == ca.OP_INPUT:
            name = ins[a[0]][0]
            if name == "p":  # loop-invariant: read once before the loop (see module docstring)
                hoisted.setdefault(a[1], f"  const double p{a[1]} = i{a[0]}[{a[1]}];")
                current[r[0]] = f"p{a[1]}"
                continue
            expr = f"ib{a[0]}[{a[1]} * BLOCK + j]"
        elif op == ca.OP_CONST:
            expr = repr(float(f.instruction_constant(k)))
        elif op in _BINARY:
            expr = _BINARY[op].format(*args)
        elif op in _UNARY:
            expr = _UNARY[op].format(*args)
        else:
            raise NotImplementedError(f"{f.name()}: CasADi operation {op} has no C form here")
        stmts.append((f"t{k}", expr, [x for x in args if x.startswith("t")]))
        current[r[0]] = f"t{k}"
    return stmts, stores, hoisted


def loop_source(f: ca.Function) -> str:
    """C source of ``<name>_loop`` for a dense SX function; shared input ``p``."""
    ins = [(f.name_in(i), f.nnz_in(i)) for i in range(f.n_in())]
    outs = [f.nnz_out(i) for i in range(f.n_out())]
    offsets = [sum(outs[:i]) for i in range(len(outs))]
    for o in range(f.n_out()):  # densified zeros are explicit constants, so every entry is set
        if f.sparsity_out(o).nnz() != f.sparsity_out(o).numel():
            raise ValueError(f"{f.name()}: output {o} is sparse; densify before generating loops")
    stmts, stores, hoisted = _statements(f, ins, offsets)
    body = [f"      const double {v} = {e};" for v, e, _ in stmts]
    body += [f"      buf[{o} * BLOCK + j] = {v};" for o, v in stores]
    decl = [f"  const double *restrict i{j} = in[{j}];" for j in range(len(ins))]
    decl += [f"  double *restrict o{j} = out[{j}];" for j in range(len(outs))]
    decl += [hoisted[k] for k in sorted(hoisted)]
    per_sample = [(i, size) for i, (name, size) in enumerate(ins) if name != "p"]
    decl += [f"  double ib{i}[{size} * BLOCK];" for i, size in per_sample]
    decl += [f"  double buf[{sum(outs)} * BLOCK];"]
    copy_in = [f"    for (j = 0; j < m; ++j)\n"
               f"      for (k = 0; k < {size}; ++k) ib{i}[k * BLOCK + j] = "
               f"i{i}[(s0 + j) * {size} + k];" for i, size in per_sample]
    loops = copy_in + ["    for (j = 0; j < m; ++j) {\n" + "\n".join(body) + "\n    }"]
    copy_out = [f"    for (j = 0; j < m; ++j)\n"
                f"      for (k = 0; k < {size}; ++k) o{o}[(s0 + j) * {size} + k] = "
                f"buf[({offsets[o]} + k) * BLOCK + j];" for o, size in enumerate(outs)]
    return (f"/* {f.name()} over n samples: in/out blocks row-major (n, size), p shared */\n"
            f"PLANAR_SYM_EXPORT int {f.name()}_loop(long long n, const double *const *in, "
            "double *const *out) {\n" + "\n".join(decl) + "\n  long long s0, j, k, m;\n"
            "  for (s0 = 0; s0 < n; s0 += BLOCK) {\n"
            "    m = n - s0 < BLOCK ? n - s0 : BLOCK;\n" + "\n".join(loops) + "\n"
            + "\n".join(copy_out) + "\n  }\n  (void)k;\n  return 0;\n}\n")

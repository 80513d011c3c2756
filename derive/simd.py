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
  matrix) would otherwise keep its loops scalar. A block holds 32 samples, fewer where its
  buffers would outgrow the first-level cache (``block_size``), and its outputs go back out
  through 4 x 4 tiles in AVX registers (``planar_sym_copy_out``): a 20-link mass matrix, 400
  outputs a sample, took 545 ns a sample in cache with 32-sample blocks copied element by
  element, 215 ns with 4-sample blocks and tiles;
* parameters are read into locals before the loop;
* the inputs are checked while they are copied in (``NONFINITE``), not in a pass of their own:
  for a small robot a second pass over the inputs costs about as much as the dynamics;
* no function grows with the robot: a loop longer than ``PART_OPS`` statements is cut into
  part functions (each its own vectorised loop over the block), because gcc's time and memory
  on one function grow faster than its length; the pieces are shared out into compile units
  of ``UNIT_OPS`` statements, compiled in parallel.

Every loop has one signature, so the runtime can call any of them the same way:
``int <robot>_<quantity>_loop(long long n, const double *const *in, double *const *out)``,
returning 0, or ``NONFINITE`` for an input that is not finite (the caller names it), or 1 where
a cut loop's buffers could not be allocated.
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
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
/* compile units: built whole, or as units compiled in parallel, one per -DPLANAR_SYM_UNIT=k
   (the manifest's compile_units), each holding some of the loops */
#ifdef PLANAR_SYM_UNIT
#define PLANAR_SYM_ALL 0
#else
#define PLANAR_SYM_ALL 1
#define PLANAR_SYM_UNIT 0
#endif
#if defined(__AVX__)
#include <immintrin.h>
#endif
/* samples per block (BLOCK, set before each loop by its size): outputs are stored per block in
   sample-contiguous order (which gcc vectorises; interleaved groups of 49 stores would block
   it) and then copied out by planar_sym_copy_out */
#ifndef M_PI_2
#define M_PI_2 1.57079632679489661923
#endif
#if defined(_WIN32)
#define PLANAR_SYM_EXPORT __declspec(dllexport)
#else
#define PLANAR_SYM_EXPORT __attribute__((visibility("default")))
#endif
#if defined(_WIN32)
#define PLANAR_SYM_PART
#else
#define PLANAR_SYM_PART __attribute__((visibility("hidden")))
#endif
/* 1 where x is infinite or NaN. The loops check their inputs while copying them in (a second
   pass over the inputs costs about as much as a small robot's dynamics); a test of the exponent
   bits, because -ffast-math assumes finite values and may fold x != x or isfinite away */
static inline int planar_sym_nonfinite(double x) {
  uint64_t b;
  memcpy(&b, &x, sizeof b);
  return (b & 0x7ff0000000000000ULL) == 0x7ff0000000000000ULL;
}
/* one output of a block back to row-major (m, size): b holds it sample-contiguous, stride
   doubles an entry. A transposition: with AVX, tiles of 4 samples x 4 entries through
   registers (a 20-link mass matrix's copy took longer than computing it, element by element) */
static inline void planar_sym_copy_out(double *restrict o, const double *restrict b,
                                       long long size, long long stride, long long m) {
  long long j = 0, k, a;
  const long long k4 = size - size % 4;
#if defined(__AVX__)
  for (; j + 4 <= m; j += 4) {
    for (k = 0; k < k4; k += 4) {
      const __m256d r0 = _mm256_loadu_pd(b + (k + 0) * stride + j);
      const __m256d r1 = _mm256_loadu_pd(b + (k + 1) * stride + j);
      const __m256d r2 = _mm256_loadu_pd(b + (k + 2) * stride + j);
      const __m256d r3 = _mm256_loadu_pd(b + (k + 3) * stride + j);
      const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
      const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
      _mm256_storeu_pd(o + (j + 0) * size + k, _mm256_permute2f128_pd(t0, t2, 0x20));
      _mm256_storeu_pd(o + (j + 1) * size + k, _mm256_permute2f128_pd(t1, t3, 0x20));
      _mm256_storeu_pd(o + (j + 2) * size + k, _mm256_permute2f128_pd(t0, t2, 0x31));
      _mm256_storeu_pd(o + (j + 3) * size + k, _mm256_permute2f128_pd(t1, t3, 0x31));
    }
    for (a = 0; a < 4; ++a)
      for (k = k4; k < size; ++k) o[(j + a) * size + k] = b[k * stride + j + a];
  }
#endif
  for (; j < m; ++j)
    for (k = 0; k < size; ++k) o[j * size + k] = b[k * stride + j];
  (void)k4;
  (void)a;
}
"""

#: what a loop returns: 0 done, 1 out of memory, 2 an input sample not finite (found in the copy
#: of a block, before anything of that block is computed; the caller scans for it to name it)
NONFINITE = 2


#: operations per compile unit: gcc's time and memory grow faster than the length of one
#: function, so big robots' loops are compiled as several units, in parallel
UNIT_OPS = 3000
#: statements per function: a longer loop is cut into part functions (see ``loop_parts``).
#: gcc's register allocation and post-reload CSE grow faster than linearly with one loop
#: body's length (12-link chain, -O3: a 4,088-statement loop body took 11 s, a 2,942 one 3.5 s;
#: 20 links, 11,084 statements: over 12 min and 520 MiB), so no function may exceed this.
#: 1,500 keeps every built-in robot's loops whole (the largest, the 3-RPR's closed regressor,
#: has 1,299)
PART_OPS = 1500


#: bytes of a block's input and output buffers: kept within the core's first-level cache (32 KiB
#: on most x86 cores; half leaves room for the loop's spills). A 20-link mass matrix's outputs,
#: 400 a sample, fill 100 KiB at 32 samples a block, and the block ran 2.3x slower than at 4
BLOCK_BYTES = 16384


def block_size(doubles: int) -> int:
    """Samples per block for a loop moving ``doubles`` values a sample (inputs and outputs):
    32, halved while its buffers exceed ``BLOCK_BYTES``, never under 4 (one AVX vector)."""
    block = 32
    while block > 4 and doubles * block * 8 > BLOCK_BYTES:
        block //= 2
    return block


def units(operations: list[int], unit_ops: int | None = None,
          groups: list[int] | None = None) -> list[int]:
    """The compile unit of each piece, in file order: a new unit once ``unit_ops`` (default
    ``UNIT_OPS``) is full, or where the piece's compile group (``groups``, derive/groups.py)
    changes, so no unit holds two groups' loops (a robot whose loops all fit in one compiles as
    one unit, as before)."""
    unit_ops = unit_ops or UNIT_OPS
    groups = groups or [0] * len(operations)
    out, unit, filled = [], 0, 0
    for k, ops in enumerate(operations):
        if filled and (filled + ops > unit_ops or groups[k] != groups[k - 1]):
            unit, filled = unit + 1, 0
        out.append(unit)
        filled += ops
    return out


def assemble(pieces: list[tuple[str, int]], first: str = "", unit_ops: int | None = None,
             groups: list[int] | None = None) -> tuple[str, list[int]]:
    """The loops' file after ``PRELUDE`` and each compile unit's statements: pieces
    (``loop_parts``) shared out in order by ``units``. ``first``, if given, opens the file in
    every library: a whole-file build, and the first unit of each group (the builder defines
    ``PLANAR_SYM_HEAD`` there)."""
    where = units([ops for _, ops in pieces], unit_ops, groups)
    ops = [sum(n for (_, n), u in zip(pieces, where) if u == k)
           for k in range(max(where, default=-1) + 1)]
    head = f"#if PLANAR_SYM_ALL || defined(PLANAR_SYM_HEAD)\n{first}#endif\n" if first else ""
    body = head + "\n".join(in_unit(u, source) for (source, _), u in zip(pieces, where))
    return PRELUDE + body, ops


def in_unit(unit: int, source: str) -> str:
    """``source`` compiled only in unit ``unit`` (and in a whole-file build)."""
    return f"#if PLANAR_SYM_ALL || PLANAR_SYM_UNIT == {unit}\n{source}#endif\n"


def _row_major(f: ca.Function, out: int, nz: int) -> int:
    """Index of dense column-major nonzero ``nz`` of output ``out`` in row-major order."""
    rows, cols = f.size1_out(out), f.size2_out(out)
    return (nz % rows) * cols + nz // rows


def _statements(f: ca.Function, ins, offsets):
    """(variable, C expression, used variables) per instruction, stores, hoisted p loads, and
    the variables that are only an input load or a constant (cheaper to redo than to keep)."""
    stmts, stores, current, hoisted, cheap = [], [], {}, {}, set()
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
            cheap.add(f"t{k}")
        elif op == ca.OP_CONST:
            expr = repr(float(f.instruction_constant(k)))
            cheap.add(f"t{k}")
        elif op in _BINARY:
            expr = _BINARY[op].format(*args)
        elif op in _UNARY:
            expr = _UNARY[op].format(*args)
        else:
            raise NotImplementedError(f"{f.name()}: CasADi operation {op} has no C form here")
        stmts.append((f"t{k}", expr, args))
        current[r[0]] = f"t{k}"
    return stmts, stores, hoisted, cheap


def _layout(f: ca.Function):
    """Inputs (name, size), output sizes, and each output's offset in the sample's block."""
    ins = [(f.name_in(i), f.nnz_in(i)) for i in range(f.n_in())]
    outs = [f.nnz_out(i) for i in range(f.n_out())]
    for o in range(f.n_out()):  # densified zeros are explicit constants, so every entry is set
        if f.sparsity_out(o).nnz() != f.sparsity_out(o).numel():
            raise ValueError(f"{f.name()}: output {o} is sparse; densify before generating loops")
    return ins, outs, [sum(outs[:i]) for i in range(len(outs))]


def _copies(ins, outs, offsets):
    """Each block's copies: inputs into sample-contiguous buffers (noting any value that is not
    finite in ``bad``), outputs back out."""
    per_sample = [(i, size) for i, (name, size) in enumerate(ins) if name != "p"]
    copy_in = [f"    for (j = 0; j < m; ++j)\n"
               f"      for (k = 0; k < {size}; ++k) {{\n"
               f"        const double x = i{i}[(s0 + j) * {size} + k];\n"
               f"        ib{i}[k * BLOCK + j] = x;\n"
               f"        bad |= planar_sym_nonfinite(x);\n"
               "      }" for i, size in per_sample]
    copy_out = [f"    for (j = 0; j < m; ++j)\n"
                f"      for (k = 0; k < {size}; ++k) o{o}[(s0 + j) * {size} + k] = "
                f"buf[({offsets[o]} + k) * BLOCK + j];" if size < 4 else
                f"    planar_sym_copy_out(o{o} + s0 * {size}, buf + {offsets[o]} * BLOCK, {size}, "
                "BLOCK, m);" for o, size in enumerate(outs)]
    return per_sample, copy_in, copy_out


def _io_decl(ins, outs) -> list[str]:
    return ([f"  const double *restrict i{j} = in[{j}];" for j in range(len(ins))]
            + [f"  double *restrict o{j} = out[{j}];" for j in range(len(outs))])


def loop_parts(f: ca.Function, part_ops: int | None = None) -> list[tuple[str, int]]:
    """``<name>_loop`` for a dense SX function as C pieces, (source, statements) each, in order.

    A loop of up to ``part_ops`` statements is one piece, as it always was. A longer one is cut
    into part functions of ``part_ops`` statements, each its own loop over the block's samples
    (so each still vectorises), called in turn by ``<name>_loop``; a value one part makes and a
    later one uses goes through ``live``, a sample-contiguous buffer of the block (input loads
    and constants are redone instead). The parts may sit in different compile units.
    """
    part_ops = part_ops or PART_OPS
    ins, outs, offsets = _layout(f)
    stmts, stores, hoisted, cheap = _statements(f, ins, offsets)
    if len(stmts) <= part_ops:
        pieces = [(_whole(f, ins, outs, offsets, stmts, stores, hoisted), len(stmts))]
    else:
        pieces = _cut(f, ins, outs, offsets, stmts, stores, cheap, part_ops)
    # every piece of one loop (its parts may sit in other compile units) sees the same BLOCK
    block = block_size(sum(outs) + sum(size for name, size in ins if name != "p"))
    return [(f"#undef BLOCK\n#define BLOCK {block}\n{source}", ops) for source, ops in pieces]


def _whole(f, ins, outs, offsets, stmts, stores, hoisted) -> str:
    per_sample, copy_in, copy_out = _copies(ins, outs, offsets)
    body = [f"      const double {v} = {e};" for v, e, _ in stmts]
    body += [f"      buf[{o} * BLOCK + j] = {v};" for o, v in stores]
    decl = _io_decl(ins, outs) + [hoisted[k] for k in sorted(hoisted)]
    decl += [f"  double ib{i}[{size} * BLOCK];" for i, size in per_sample]
    decl += [f"  double buf[{sum(outs)} * BLOCK];"]
    loops = copy_in + [f"    if (bad) return {NONFINITE};",
                       "    for (j = 0; j < m; ++j) {\n" + "\n".join(body) + "\n    }"]
    return (f"/* {f.name()} over n samples: in/out blocks row-major (n, size), p shared */\n"
            f"PLANAR_SYM_EXPORT int {f.name()}_loop(long long n, const double *const *in, "
            "double *const *out) {\n" + "\n".join(decl) + "\n  long long s0, j, k, m;\n"
            "  int bad = 0;\n"
            "  for (s0 = 0; s0 < n; s0 += BLOCK) {\n"
            "    m = n - s0 < BLOCK ? n - s0 : BLOCK;\n" + "\n".join(loops) + "\n"
            + "\n".join(copy_out) + "\n  }\n  (void)k;\n  return 0;\n}\n")


def _cut(f, ins, outs, offsets, stmts, stores, cheap, part_ops):
    name = f.name()
    parts = [stmts[c:c + part_ops] for c in range(0, len(stmts), part_ops)]
    made = {v: k for k, part in enumerate(parts) for v, _, _ in part}
    expr = {v: e for v, e, _ in stmts}
    slot: dict[str, int] = {}  # values kept in ``live`` between parts
    for k, part in enumerate(parts):
        for _, _, used in part:
            for u in used:
                if u in made and made[u] < k and u not in cheap:
                    slot.setdefault(u, len(slot))
    stored = {}
    for o, v in stores:  # an output is stored by the part that makes it (parameters: the first)
        stored.setdefault(made.get(v, 0), []).append((o, v))
    p_in = next((i for i, (n, _) in enumerate(ins) if n == "p"), None)
    per_sample = [i for i, (n, _) in enumerate(ins) if n != "p"]
    pieces = []
    for k, part in enumerate(parts):
        work = [(v, e) for v, e, _ in part if v not in cheap]
        used = [u for _, _, us in part for u in us]
        used = list(dict.fromkeys(used + [v for _, v in stored.get(k, [])]))
        # input loads and constants where used (redone rather than kept), then kept values
        body = [f"      const double {u} = {expr[u]};" for u in used if u in cheap]
        body += [f"      const double {u} = live[{slot[u]} * BLOCK + j];"
                 for u in used if u in slot and made[u] < k]
        body += [f"      const double {v} = {e};" for v, e in work]
        body += [f"      live[{slot[v]} * BLOCK + j] = {v};" for v, _ in work if v in slot]
        body += [f"      buf[{o} * BLOCK + j] = {v};" for o, v in stored.get(k, [])]
        text = "\n".join(body)
        decl = [f"  const double *restrict ib{i} = ib[{i}];" for i in per_sample
                if f"ib{i}[" in text]
        decl += [f"  const double p{q} = pv[{q}];"
                 for q in sorted({int(u[1:]) for u in used if u.startswith("p")})]
        pieces.append((
            f"/* {name}_loop, part {k + 1} of {len(parts)}: statements {k * part_ops} to "
            f"{k * part_ops + len(part) - 1} of one block's samples */\n"
            f"PLANAR_SYM_PART void {name}_part{k}(long long m, const double *const *ib, "
            "const double *restrict pv, double *restrict live, double *restrict buf) {\n"
            + "\n".join(decl) + "\n  long long j;\n  (void)ib;\n  (void)pv;\n  (void)live;\n"
            "  for (j = 0; j < m; ++j) {\n" + text + "\n  }\n}\n", len(part)))
    _, copy_in, copy_out = _copies(ins, outs, offsets)
    decl = _io_decl(ins, outs)
    decl += [f"  double ib{i}[{ins[i][1]} * BLOCK];" for i in per_sample]
    decl += ["  const double *ib[] = {"
             + ", ".join(f"ib{i}" if i in per_sample else "0" for i in range(len(ins))) + "};"]
    decl += [f"  const double *pv = {'0' if p_in is None else f'i{p_in}'};"]
    # the block's values between parts, and its outputs: on the heap (a big robot's would not
    # fit a thread's stack)
    decl += [f"  double *live = malloc(sizeof(double) * {max(len(slot), 1)} * BLOCK);",
             f"  double *buf = malloc(sizeof(double) * {sum(outs)} * BLOCK);",
             "  long long s0, j, k, m;",
             "  int bad = 0;",
             "  if (!live || !buf) {\n    free(live);\n    free(buf);\n    return 1;\n  }"]
    calls = [f"    {name}_part{k}(m, ib, pv, live, buf);" for k in range(len(parts))]
    stop = ("    if (bad) {\n      free(live);\n      free(buf);\n"
            f"      return {NONFINITE};\n    }}")
    protos = "".join(f"PLANAR_SYM_PART void {name}_part{k}(long long, const double *const *, "
                     "const double *restrict, double *restrict, double *restrict);\n"
                     for k in range(len(parts)))
    driver = (f"/* {name} over n samples: in/out blocks row-major (n, size), p shared; "
              f"{len(stmts)} statements in {len(parts)} parts */\n" + protos
              + f"PLANAR_SYM_EXPORT int {name}_loop(long long n, const double *const *in, "
              "double *const *out) {\n" + "\n".join(decl) + "\n"
              "  for (s0 = 0; s0 < n; s0 += BLOCK) {\n"
              "    m = n - s0 < BLOCK ? n - s0 : BLOCK;\n"
              + "\n".join(copy_in + [stop] + calls) + "\n"
              + "\n".join(copy_out) + "\n  }\n  free(live);\n  free(buf);\n  (void)k;\n"
              "  return 0;\n}\n")
    # the driver (small) rides with the last part; the parts it calls may sit in other units,
    # which the linker joins
    return pieces[:-1] + [(pieces[-1][0] + driver, pieces[-1][1])]

"""CasADi functions of a model -> C source, header, manifest.json, written atomically.

Every generated function is ``<robot>_<quantity>`` with named inputs in the one argument order
``(q, qd, qdd|tau, p)``. Each also gets a ``_batch`` wrapper that loops over N samples in C
(inputs and outputs row-major ``(N, size)``, ``p`` shared), so a whole trajectory is one call.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import casadi as ca
import sympy as sp

from planar_sym.model import units as _units
from planar_sym.model.description import Description

from . import simd
from .lagrange import gravity_direction
from .model import Model
from .to_casadi import Translator

GENERATOR = "planar-sym derive (derive/codegen.py)"
ROOT = Path(__file__).resolve().parent.parent
#: this package's folder: derive/ in a checkout, planar_sym/_derive once installed
DERIVE_DIR = Path(__file__).resolve().parent
_RUNTIME = Path(_units.__file__).resolve().parents[1]  # the planar_sym in use
#: sources whose change can change the generated files: they are part of the input hash,
#: named by their path in a checkout wherever they are (so an install hashes the same): every
#: module of the description package (reading, validating, assembling) and the units
HASHED_SOURCES = tuple(sorted(
    [f"planar_sym/{p.relative_to(_RUNTIME).as_posix()}"
     for p in (_RUNTIME / "model" / "description").glob("*.py")]
    + ["planar_sym/model/units.py"]))

#: how the runtime shapes each output per sample: scalar (), vector (rows,), matrix (rows, cols);
#: a 1-joint robot's 1x1 mass matrix must still come back as a matrix
OUTPUT_KIND = {"kinetic": "scalar", "potential": "scalar", "cond": "scalar", "M": "matrix",
               "J": "matrix",
               "phi_q": "matrix", "frames": "matrix", "dqdd_dq": "matrix", "dqdd_dqd": "matrix",
               "accelerations": "matrix", "cg": "matrix", "joint_points": "matrix"}


@dataclass(frozen=True)
class Generated:
    """One CasADi function and what the manifest says about it."""

    quantity: str
    function: ca.Function
    doc: str


def relative_input(path: Path) -> str:
    """Path of a description as recorded in headers: repo-relative when inside the repo."""
    path = path.resolve()
    try:
        return path.relative_to(ROOT).as_posix()
    except ValueError:
        return path.name


def input_hash(desc: Description) -> str:
    """sha256 over the description, the derive sources and the derive toolchain versions."""
    h = hashlib.sha256()
    parts = [("description", desc.path.read_bytes())]
    from planar_sym.model import units

    runtime = Path(units.__file__).resolve().parents[1]  # the installed planar_sym
    parts += [(f"derive/{p.name}", p.read_bytes()) for p in sorted(DERIVE_DIR.glob("*.py"))]
    parts += [(s, (runtime / s.removeprefix("planar_sym/")).read_bytes())
              for s in HASHED_SOURCES]
    parts += [("sympy", sp.__version__.encode()), ("casadi", ca.__version__.encode())]
    for label, data in parts:
        h.update(f"{label}\0{len(data)}\0".encode())
        h.update(data)
    return h.hexdigest()


def functions(model: Model) -> list[Generated]:
    """The CasADi functions generated for one robot."""
    s, lag, con = model.sym, model.lagrangian, model.constraints
    n, n_p = len(s.q), len(s.p)
    q, qd, qdd, tau = (ca.SX.sym(k, n) for k in ("q", "qd", "qdd", "tau"))
    p = ca.SX.sym("p", n_p)
    mapping = {sym: var[i] for syms, var in ((s.q, q), (s.qd, qd), (s.qdd, qdd), (s.tau, tau),
                                             (s.p, p)) for i, sym in enumerate(syms)}
    tr = Translator(mapping)
    name = model.desc.name
    M, h, g = tr.matrix(lag.mass_matrix), tr.matrix(lag.bias), tr.matrix(lag.gravity)

    def fn(quantity, ins, outs, doc):
        # densify: CasADi drops structural zeros (e.g. dqdd/dq of a gravity-free arm), but the
        # runtime and the C batch layout read every output as a dense column-major block
        f = ca.Function(f"{name}_{quantity}", [v for _, v in ins],
                        [ca.densify(v) for _, v in outs], [k for k, _ in ins],
                        [k for k, _ in outs])
        return Generated(quantity, f, doc)

    out = [
        fn("mass_matrix", [("q", q), ("p", p)], [("M", M)], "mass matrix M(q)"),
        fn("bias", [("q", q), ("qd", qd), ("p", p)], [("h", h)],
           "h(q, qd) = C(q, qd) qd + g(q): velocity and gravity terms"),
        fn("gravity", [("q", q), ("p", p)], [("g", g)], "gravity terms g(q) = dV/dq"),
        fn("inverse_dynamics", [("q", q), ("qd", qd), ("qdd", qdd), ("p", p)],
           [("tau", ca.mtimes(M, qdd) + h)], "tree inverse dynamics tau = M qdd + h"),
        fn("energy", [("q", q), ("qd", qd), ("p", p)],
           [("kinetic", tr(lag.kinetic)), ("potential", tr(lag.potential))],
           "kinetic and potential energy (J)"),
        fn("frames", [("q", q), ("p", p)], [("frames", tr.matrix(model.frames))],
           "every body's frame: origin x, origin y (m), angle (rad); one row per body"),
        # component rows, one column per body or point: each component of all bodies is
        # contiguous per sample, which is how the runtime's Newton-Euler reads them
        fn("body_motion", [("q", q), ("qd", qd), ("qdd", qdd), ("p", p)],
           [("accelerations", tr.matrix(model.body_accelerations.T)),
            ("cg", tr.matrix(model.cg_positions.T)),
            ("joint_points", tr.matrix(model.joint_points.T))],
           "what Newton-Euler needs, exact, one column per body (as frames' rows): cg "
           "acceleration x, y (m/s^2) and angular acceleration (rad/s^2) rows; cg x, y (m) rows; "
           "joint_points x, y rows, one column per joint's child point (m; the manifest's "
           "joints: tree joints, then cuts), then per cut's parent point, then per prismatic "
           "joint's slide axis in world axes"),
    ]
    if model.task.shape[0]:  # a robot without [task] has no tool point to report
        out.insert(5, fn("task", [("q", q), ("qd", qd), ("p", p)],
                         [("x", tr.matrix(model.task)), ("J", tr.matrix(model.task_jacobian)),
                          ("jdot_qd", tr.matrix(model.task_jdot_qd))],
                         "task coordinates x(q) (m, rad), Jacobian J = dx/dq and Jdot qd"))
    if con.count == 0:
        qdd_free = ca.solve(M, tau - h)
        out.append(fn("forward_dynamics", [("q", q), ("qd", qd), ("tau", tau), ("p", p)],
                      [("qdd", qdd_free)], "forward dynamics qdd = M^-1 (tau - h)"))
        out.append(fn("forward_dynamics_jacobian",
                      [("q", q), ("qd", qd), ("tau", tau), ("p", p)],
                      [("dqdd_dq", ca.jacobian(qdd_free, q)),
                       ("dqdd_dqd", ca.jacobian(qdd_free, qd))],
                      "Jacobian of the forward dynamics, for implicit integrators"))
    else:
        out += [
            fn("constraint", [("q", q), ("p", p)], [("phi", tr.matrix(con.phi))],
               "loop-closure residual Phi(q) (m)"),
            fn("constraint_jacobian", [("q", q), ("p", p)], [("phi_q", tr.matrix(con.jacobian))],
               "constraint Jacobian Phi_q = dPhi/dq"),
            fn("constraint_bias", [("q", q), ("qd", qd), ("p", p)],
               [("gamma", tr.matrix(con.accel_bias))],
               "acceleration term gamma = -(Phi_q qd)_q qd, so Phi_q qdd = gamma"),
            fn("constrained_terms", [("q", q), ("qd", qd), ("p", p)],
               [("M", M), ("h", h), ("phi_q", tr.matrix(con.jacobian)),
                ("gamma", tr.matrix(con.accel_bias))],
               "M, h, Phi_q and gamma in one call: everything a KKT solve needs"),
            _closed_inverse_dynamics(fn, model, q, qd, qdd, p, ca.mtimes(M, qdd) + h,
                                     tr.matrix(con.jacobian), tr.matrix(con.phi),
                                     tr.matrix(con.accel_bias)),
        ]
    return out


def _closed_inverse_dynamics(fn, model: Model, q, qd, qdd, p, b, jac, phi, gamma) -> Generated:
    """Torques, cut-joint forces, the singularity measure and the loop residuals, fused.

    ``[S^T Phi_q^T][tau; lambda] = b`` splits into ``Phi_p^T lambda = b_p`` (passive rows)
    and ``tau = b_a - Phi_a^T lambda``; the whole matrix is singular exactly when ``Phi_p`` is,
    so its 1-norm condition number ``||Phi_p^T||_1 ||Phi_p^-T||_1`` is the measure. The
    residuals ``Phi``, ``Phi_q qd`` and ``Phi_q qdd - gamma`` let the runtime refuse a state
    that is off the loops, at the cost of a few products: one function shares every sine and
    cosine between the dynamics and the constraints.
    """
    act = list(model.desc.actuated)
    pas = [i for i in range(len(model.sym.q)) if i not in act]
    pt = jac[:, pas].T
    inv = ca.inv(pt)  # m is 2 or 4 here: explicit, and the condition number needs it anyway
    lam = ca.mtimes(inv, b[pas])
    tau = b[act] - ca.mtimes(jac[:, act].T, lam)

    def norm1(a):
        return ca.mmax(ca.sum1(ca.fabs(a)))

    return fn("closed_inverse_dynamics", [("q", q), ("qd", qd), ("qdd", qdd), ("p", p)],
              [("tau", tau), ("lambda", lam), ("cond", norm1(pt) * norm1(inv)),
               ("phi", phi), ("phi_v", ca.mtimes(jac, qd)),
               ("phi_a", ca.mtimes(jac, qdd) - gamma)],
              "closed-chain torques tau (actuated), cut-joint forces lambda and the 1-norm "
              "condition number of Phi_p, from M qdd + h = S^T tau + Phi_q^T lambda; and the "
              "loop residuals Phi (m), Phi_q qd (m/s), Phi_q qdd - gamma (m/s^2)")


def _batch_wrapper(g: Generated) -> str:
    f = g.function
    cname = f.name()
    ins = [(f.name_in(i), f.size1_in(i) * f.size2_in(i)) for i in range(f.n_in())]
    outs = [(f.name_out(i), f.size1_out(i) * f.size2_out(i)) for i in range(f.n_out())]
    params = ["long long n"] + [f"const casadi_real *{k}" for k, _ in ins] + \
             [f"casadi_real *{k}" for k, _ in outs]
    lines = [
        f"/* {cname}_batch: {g.doc}, at n samples; per-sample blocks row-major, p shared.",
        "   Returns 0, or 1 + the index of the first sample the function failed on. */",
        f"CASADI_SYMBOL_EXPORT int {cname}_batch({', '.join(params)}) {{",
        f"  const casadi_real *arg[{max(f.sz_arg(), 1)}];",
        f"  casadi_real *res[{max(f.sz_res(), 1)}];",
        f"  casadi_int iw[{f.sz_iw() + 1}];",
        f"  casadi_real w[{f.sz_w() + 1}];",
        "  long long k;",
        "  for (k = 0; k < n; ++k) {",
    ]
    for i, (k, size) in enumerate(ins):
        lines.append(f"    arg[{i}] = {k};" if k == "p" else f"    arg[{i}] = {k} + k * {size};")
    for i, (k, size) in enumerate(outs):
        lines.append(f"    res[{i}] = {k} + k * {size};")
    lines += [f"    if ({cname}(arg, res, iw, w, 0)) return (int)(k + 1);", "  }", "  return 0;",
              "}", ""]
    return "\n".join(lines)


def _header_comment(model: Model, file: str, digest: str) -> str:
    desc = model.desc
    params = desc.parameters()
    lines = [
        f"{file}: generated by {GENERATOR}",
        f"with CasADi {ca.__version__} and SymPy {sp.__version__}",
        f"input: {relative_input(desc.path)}",
        f"input hash: sha256:{digest}",
        "do not edit: run `make derive`",
        "",
        "Inputs of the functions below (each takes those it needs, in this order):",
        f"  q[{len(desc.coordinates)}]   : {list(desc.coordinates)} (rad)",
        "  qd, qdd : their rates (rad/s, rad/s^2); tau: joint torques (N*m)",
        f"  p[{len(params)}]  : parameters, SI:",
    ]
    lines += [f"    p[{i}] {par.name} = {par.value!r} {par.unit}" for i, par in enumerate(params)]
    return "/* " + "\n * ".join(lines) + "\n */\n"


def render(model: Model) -> dict[str, bytes]:
    """All generated files of one robot, as bytes (nothing written yet)."""
    from . import printing

    desc, name = model.desc, model.desc.name
    digest = input_hash(desc)
    gens = functions(model)
    cg = ca.CodeGenerator(name, {"with_header": False, "casadi_real": "double",
                                 "casadi_int": "long long int"})
    for g in gens:
        cg.add(g.function)
    body = _generate(cg, name)
    hash_fn = (f"CASADI_SYMBOL_EXPORT const char *{name}_input_hash(void) "
               f'{{ return "{digest}"; }}\n')
    c_src = (_header_comment(model, f"{name}.c", digest) + body + "\n" + hash_fn + "\n"
             + "\n".join(_batch_wrapper(g) for g in gens))
    h_src = _header_comment(model, f"{name}.h", digest) + _header(model, gens)
    simd_src = (_header_comment(model, f"{name}_simd.c", digest) + simd.PRELUDE
                + f'PLANAR_SYM_EXPORT const char *{name}_simd_input_hash(void) '
                  f'{{ return "{digest}"; }}\n\n'
                + "\n".join(simd.loop_source(g.function) for g in gens))
    eq = printing.render(model)
    files = {
        f"{name}.c": c_src.encode(),
        f"{name}.h": h_src.encode(),
        f"{name}_simd.c": simd_src.encode(),
        "equations.txt": (_text_header(model, "equations.txt", digest) + eq["text"]).encode(),
        "equations.tex": (_text_header(model, "equations.tex", digest, "%") + eq["latex"]).encode(),
        # the same header as an HTML comment: hidden when GitHub renders the Markdown
        "equations.md": ("<!--\n" + _text_header(model, "equations.md", digest, " ").rstrip()
                         + "\n-->\n\n" + eq["markdown"]).encode(),
    }
    files.update({f"{g.quantity}.casadi": _saved(g.function) for g in gens})
    files["manifest.json"] = _manifest(model, gens, digest, files)
    return files


def _generate(cg: ca.CodeGenerator, name: str) -> str:
    """CasADi's own file output, not ``dump()``: only the file carries CasADi's notice (its
    template code is MIT-0 licensed, the rest not copyrighted), which the generated C keeps."""
    with tempfile.TemporaryDirectory() as tmp:
        cg.generate(tmp + os.sep)
        return (Path(tmp) / f"{name}.c").read_text()


def _saved(function: ca.Function) -> bytes:
    """``Function.save``'s bytes: ``casadi.Function.load`` reads them back without SymPy (the
    runtime's evaluator when no C compiler is at hand, and a user's ``casadi.Opti``)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "f.casadi"
        function.save(str(path))
        return path.read_bytes()


def _header(model: Model, gens: list[Generated]) -> str:
    """The C header: sizes as macros, and every function's one-sample, batch and loop forms."""
    name, up = model.desc.name, model.desc.name.upper()
    lines = [f"#ifndef PLANAR_SYM_{up}_H", f"#define PLANAR_SYM_{up}_H",
             "#ifndef casadi_real", "#define casadi_real double", "#endif",
             "#ifndef casadi_int", "#define casadi_int long long int", "#endif",
             f"#define {up}_N_Q {len(model.sym.q)}  /* coordinates */",
             f"#define {up}_N_P {len(model.sym.p)}  /* parameters */",
             f"const char *{name}_input_hash(void);"]
    for g in gens:
        f = g.function
        args = ", ".join(["long long n"] + [f"const casadi_real *{f.name_in(i)}"
                                            for i in range(f.n_in())]
                         + [f"casadi_real *{f.name_out(i)}" for i in range(f.n_out())])
        lines += [f"/* {g.doc} */",
                  (f"int {f.name()}(const casadi_real **arg, casadi_real **res, "
                   "casadi_int *iw, casadi_real *w, int mem);"),
                  (f"int {f.name()}_work(casadi_int *sz_arg, casadi_int *sz_res, "
                   "casadi_int *sz_iw, casadi_int *sz_w);"),
                  f"const casadi_int *{f.name()}_sparsity_in(casadi_int i);",
                  f"int {f.name()}_batch({args});",
                  f"/* in {name}_simd.c: the same over n samples, vectorisable, outputs row-major */",
                  (f"int {f.name()}_loop(long long n, const double *const *in, "
                   "double *const *out);")]
    return "\n".join(lines + ["#endif", ""])


def _text_header(model: Model, file: str, digest: str, mark: str = "#") -> str:
    return (f"{mark} {file}: generated by {GENERATOR} from {relative_input(model.desc.path)}\n"
            f"{mark} input hash: sha256:{digest}\n{mark} do not edit: run `make derive`\n\n")


def _joints(desc: Description) -> list[dict]:
    """Every joint, tree joints (parents first) then cuts: what the runtime needs to find the
    load each joint carries (its bodies, points, coordinate index, slide axis)."""
    coords = {name: i for i, name in enumerate(desc.coordinates)}
    return [{"name": j.name, "type": j.type, "parent": j.parent, "parent_point": j.parent_point,
             "child": j.child, "child_point": j.child_point,
             "coordinate": coords.get(j.name) if not j.closes_loop else None,
             "actuated": j.actuated, "closes_loop": j.closes_loop,
             "axis": list(j.axis) if j.axis is not None else None}
            for j in (*desc.tree_joints, *desc.loop_joints)]


def _actuators(desc: Description) -> list[dict]:
    """Every actuated coordinate's actuator: gear ratio and limits (SI, joint side unless
    named motor); an ideal source (ratio 1, no limits) where the description gives none. The
    gear ratio is also the parameter ``gear_<joint>`` where given, which the runtime prefers."""
    out = []
    for k, j in enumerate(j for j in desc.tree_joints if j.moves):
        if not j.actuated:
            continue
        a = j.actuator
        out.append({"joint": j.name, "coordinate": k,
                    "unit": "N" if j.type == "prismatic" else "N*m",
                    "model": a is not None,
                    "gear_ratio": a.gear_ratio if a else 1.0,
                    "torque_limit": a.torque_limit if a else None,
                    "motor_torque_limit": a.motor_torque_limit if a else None,
                    "motor_speed_limit_rad_s": a.motor_speed_limit_rad_s if a else None})
    return out


def _manifest(model: Model, gens: list[Generated], digest: str, files: dict) -> bytes:
    desc = model.desc
    funcs = {}
    for g in gens:
        f = g.function
        funcs[g.quantity] = {
            "symbol": f.name(),
            "loop": f.name() + "_loop",
            "casadi": f"{g.quantity}.casadi",
            "doc": g.doc,
            "inputs": [[f.name_in(i), f.size1_in(i) * f.size2_in(i)] for i in range(f.n_in())],
            "outputs": [[f.name_out(i), f.size1_out(i), f.size2_out(i),
                         OUTPUT_KIND.get(f.name_out(i), "vector")] for i in range(f.n_out())],
        }
    data = {
        "robot": desc.name,
        "title": desc.title,
        "generator": GENERATOR,
        "input": relative_input(desc.path),
        "input_hash": digest,
        "toolchain": {"casadi": ca.__version__, "sympy": sp.__version__},
        "coordinates": list(desc.coordinates),
        "coordinate_units": list(desc.coordinate_units),
        "actuated": list(desc.actuated),
        "q_drawn": list(desc.q_drawn()),
        "task": list(desc.task_names),
        "bodies": list(model.body_names),
        "loops": [j.name for j in desc.loop_joints],
        "joints": _joints(desc),
        "actuators": _actuators(desc),
        "gravity_direction": [float(c) for c in gravity_direction(desc)],
        "constraints": model.constraints.count,
        "parameters": [{"name": p.name, "value": p.value, "unit": p.unit, "meaning": p.meaning}
                       for p in desc.parameters()],
        "matrix_layout": "column-major (CasADi); per-sample blocks row-major",
        "functions": funcs,
        "files": {k: hashlib.sha256(v).hexdigest() for k, v in sorted(files.items())},
    }
    return (json.dumps(data, indent=2, sort_keys=False) + "\n").encode()

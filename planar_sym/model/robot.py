"""A robot at run time: its compiled dynamics evaluated over whole trajectories.

.. code:: text

    M(q) qdd + h(q, qd) = tau,   h = C(q, qd) qd + g(q)

Every array method takes per-sample arrays of shape ``(N, n)`` (or ``(n,)`` for one sample, in
which case the result drops the sample axis too) and makes one compiled call for all N.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError, LibraryError, WorkspaceError
from .drive import DriveTrain
from .library import Library, builtin_generated_dirs, fastcall

#: a Jacobian whose condition number exceeds this is called singular. Near a singularity the
#: condition number grows like 1 / distance, and joint rates and torques with it: at 1e6 they
#: are already about a million times their size at a well-conditioned pose.
COND_LIMIT = 1e6

#: a closed chain's state is on its loops when its residuals stay within this (m; see
#: Robot.check_on_loops): Newton closes them to 1e-13 m, the seed's closed forms to 1e-16 m
LOOP_TOL_M = 1e-9


def _when(t, k: int) -> str:
    return f"t = {t[k]:.6g} s (sample {k})" if t is not None else f"sample {k}"


@dataclass(frozen=True)
class Parameter:
    """One physical parameter of a robot, as its generated manifest lists it.

    Attributes
    ----------
    name : str
        Its name in ``Robot.parameters`` and ``with_parameters`` (``m_link1``, ``izz_link1``,
        ``g``, ...).
    value : float
        The value the robot was derived with, in SI (``unit``).
    unit : str
        Its SI unit: ``"kg"``, ``"m"``, ``"kg*m^2"``, ``"m/s^2"``, ...
    meaning : str
        What it is, in words ("mass of link1").
    """

    name: str
    value: float
    unit: str
    meaning: str


def as_vector(name: str, a, width: int) -> np.ndarray:
    """``a`` as one finite float64 vector of ``width`` values: (width,) or (1, width) only,
    never the first row of several (a second initial state is a mistake to report).

    Units are the caller's (the values are not converted: SI throughout the package); a bad
    shape or a non-finite value raises InputError naming ``name``. Returns shape (width,).
    """
    arr = as_samples(name, a, width)
    if len(arr) != 1:
        raise InputError(f"{name} must be one vector of {width} values, got {len(arr)} rows "
                         f"(shape {np.shape(a)})")
    return arr[0].copy()


def as_samples(name: str, a, width: int, *, times: np.ndarray | None = None) -> np.ndarray:
    """``a`` as a C-contiguous float64 (N, width) array; names the first bad sample.

    ``a`` is (N, width) or (width,) (one sample); its values are kept as given (SI
    throughout the package, not converted). ``times`` (N,), in s, lets the error name the
    time of a non-finite sample too.
    """
    try:
        raw = np.asarray(a)
        complex_ = np.iscomplexobj(raw)
        arr = raw.astype(np.float64, copy=False) if not complex_ else raw
    except (TypeError, ValueError, OverflowError) as exc:
        raise InputError(f"{name} must be an array of numbers of shape (N, {width}) or "
                         f"({width},): {exc}") from None
    if complex_:
        raise InputError(f"{name} must be real, got complex values")
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != width:
        raise InputError(f"{name} must have shape (N, {width}) or ({width},), "
                         f"got {np.shape(a)}")
    # a finite sum means every entry is finite (one pass, no mask); an inf or NaN sum may be
    # an overflow of finite values, so only then is the mask built
    with np.errstate(over="ignore", invalid="ignore"):  # the fallback below decides
        total = arr.sum()
    if not np.isfinite(total) and (bad := ~np.isfinite(arr)).any():
        k, col = np.argwhere(bad)[0]
        when = f" (t = {times[k]:.6g} s)" if times is not None and k < len(times) else ""
        raise InputError(f"{name}[{k}, {col}] is {arr[k, col]} at sample {k}{when}: "
                         "inputs must be finite")
    return np.ascontiguousarray(arr)


class Robot:
    """Compiled dynamics of one robot; parameters are an input vector, changeable at will.

    Load one with ``planar_sym.load`` (which compiles on first use and caches); the
    constructor is for a generated folder's ``Library`` at hand.

    Parameters
    ----------
    name : str
        A built-in robot's name (its generated folder), when ``library`` is not given.
    library : Library, optional
        The generated code and its manifest (``model.library``).
    parameters : ndarray, shape (len(parameter_list),), optional
        Parameter values in SI (kg, m, kg*m^2, m/s^2), in ``parameter_list`` order; default
        the values the robot was derived with. Checked as ``with_parameters`` checks them.
    exact : bool, optional
        True: CasADi's per-sample functions, compiled without fast math; False: the
        vectorised C callers; None (default): exact only if ``PLANAR_SYM_EXACT=1``.

    Attributes
    ----------
    name, title : str
        The robot's name and its description's title.
    coordinates : tuple of str
        The coordinates' names, in the order of every array's last axis (n).
    coordinate_units : tuple of str
        ``"rad"`` (revolute) or ``"m"`` (prismatic) per coordinate; the matching torque is in
        N*m or N.
    actuated : tuple of int
        The actuated coordinates (0-based); the columns of closed-chain torques (actuated,).
    actuators : tuple of dict
        Per actuated coordinate: ``joint``, ``coordinate``, ``unit``, ``gear_ratio`` and the
        limits in SI (``torque_limit``, ``motor_torque_limit``, ``motor_speed_limit_rad_s``;
        None where there is none).
    task_names : tuple of str
        The task coordinates (``x``, ``y`` in m, ``phi`` in rad), empty without a task point.
    body_names : tuple of str
        The moving bodies, in the order of ``frames`` and ``body_motion``.
    n_constraints : int
        Number of loop equations, two per cut joint (0 for a tree).
    loops : tuple of str
        The cut joints of a closed chain, one per loop.
    q_drawn : ndarray, shape (n,)
        The drawn configuration (rad, m for a slider): the description's own pose.
    parameter_list : tuple of Parameter
        Every parameter: name, SI value as derived, unit and meaning.
    p : ndarray, shape (len(parameter_list),)
        The parameter values the compiled functions use (SI), read in place on every call.
    exact : bool
        Whether the exact per-sample path is used (see ``exact`` above).
    library : Library
        The generated folder, its manifest and the compiled functions.
    """

    def __init__(self, name: str, library: Library | None = None,
                 parameters: np.ndarray | None = None, exact: bool | None = None):
        if library is None and not isinstance(name, str):
            raise InputError(f"Robot(name): a robot name (str), got {type(name).__name__}; "
                             "load robots with planar_sym.load")
        self.library = library or Library(name)
        m = self.library.manifest
        self.name = m["robot"]
        self.title = m["title"]
        self.coordinates: tuple[str, ...] = tuple(m["coordinates"])
        units = m.get("coordinate_units", "rad")  # one string in manifests before sliders
        #: "rad" (revolute) or "m" (prismatic) per coordinate; torques are N*m or N alike
        self.coordinate_units: tuple[str, ...] = (
            tuple(units) if isinstance(units, list) else (units,) * len(self.coordinates))
        self.actuated: tuple[int, ...] = tuple(m["actuated"])
        self.task_names: tuple[str, ...] = tuple(m["task"])
        self.body_names: tuple[str, ...] = tuple(m["bodies"])
        self.n_constraints: int = m["constraints"]
        self.loops: tuple[str, ...] = tuple(m["loops"])
        #: per actuated coordinate: joint, coordinate, unit, gear ratio and limits (SI); an
        #: ideal source (ratio 1, no limits) for a manifest from before actuator models
        self.actuators: tuple[dict, ...] = tuple(m.get("actuators") or (
            {"joint": self.coordinates[i], "coordinate": i, "unit": "N*m", "model": False,
             "gear_ratio": 1.0, "torque_limit": None, "motor_torque_limit": None,
             "motor_speed_limit_rad_s": None} for i in self.actuated))
        self.q_drawn = np.array(m["q_drawn"])
        self.parameter_list = tuple(Parameter(**p) for p in m["parameters"])
        p = np.array([x.value for x in self.parameter_list]) if parameters is None else parameters
        if np.ndim(p) != 1:
            raise InputError(f"parameters must be a vector of {len(self.parameter_list)} values "
                             f"(got shape {np.shape(p)})")
        self.p = as_samples("parameters", p, len(self.parameter_list))[0].copy()
        if parameters is not None:  # the manifest's own values passed the description's checks
            from .parameters import problems

            found = problems(self.parameters, self.body_names)
            if found:
                raise InputError(f"{self.name}: " + "; ".join(found))
        self._fns = self.library.functions
        #: exact: CasADi's per-sample functions compiled without fast math. Otherwise the
        #: hot methods below are C-level callers of the vectorised loops (same algorithm,
        #: -ffast-math: agrees with the exact path to ~1e-15 relative, tested to 1e-12).
        self.exact = (os.environ.get("PLANAR_SYM_EXACT") == "1") if exact is None else exact
        if not self.exact:
            self._bind_fast_paths()

    def _bind_fast_paths(self) -> None:
        fast = fastcall()
        if fast is None or self.library.simd is None:
            return
        methods = {"mass_matrix": "mass_matrix", "bias": "bias", "gravity": "gravity",
                   "tree_inverse_dynamics": "inverse_dynamics", "energy": "energy"}
        if not self.is_closed_chain:
            methods.update(forward_dynamics="forward_dynamics")
            if len(self.actuated) == self.n:  # else the method refuses (passive joints)
                methods.update(inverse_dynamics="inverse_dynamics")
        else:
            methods.update(constraint="constraint", constraint_jacobian="constraint_jacobian",
                           constraint_bias="constraint_bias",
                           _closed_inverse_dynamics="closed_inverse_dynamics")
        if "body_motion" in self.library.manifest["functions"]:  # folders derived before lack it
            methods.update(body_motion="body_motion")
        kinds = {"scalar": 0, "vector": 1, "matrix": 2}
        for attr, quantity in methods.items():
            spec = self.library.manifest["functions"][quantity]
            if "loop" not in spec:  # derive makes loops only for these (codegen.LOOPED)
                continue
            ins = [(name, size) for name, size in spec["inputs"]]
            names = tuple(name for name, _ in ins if name != "p")
            caller = fast.make(
                self.library.loop_address(quantity),
                tuple(size for name, size in ins if name != "p"),
                [name for name, _ in ins].index("p"),
                tuple((rows, cols, kinds[kind]) for _, rows, cols, kind in spec["outputs"]),
                self.p, InputError, names, getattr(type(self), attr, None).__doc__
                if hasattr(type(self), attr) else spec["doc"])
            setattr(self, attr, caller)  # instance attribute: no Python frame per call

    @property
    def n(self) -> int:
        """Number of coordinates n (passive joints of closed chains included): the last axis
        of q, qd, qdd and tau."""
        return len(self.coordinates)

    @property
    def is_builtin(self) -> bool:
        """True for the package's own robots (their generated folders ship with it): a user's
        robot that shares a built-in name is not one, so it never gets a built-in's solver."""
        return self.library.folder.resolve().parent in builtin_generated_dirs()

    @property
    def description_file(self) -> Path | None:
        """The description this robot was derived from, where it is at hand: a built-in one's
        ``robots/<name>.toml``, or the ``description.toml`` copy in its generated folder."""
        if self.is_builtin:
            from .description import robots_dir

            return robots_dir() / f"{self.name}.toml"
        copy = self.library.folder / "description.toml"
        return copy if copy.is_file() else None

    @property
    def has_friction(self) -> bool:
        """Whether an actuator's friction dissipates energy (a free motion then loses it)."""
        return any(p.name.startswith(("fv_", "fc_")) for p in self.parameter_list)

    @property
    def drive_train(self) -> DriveTrain:
        """The actuated joints' gears, rotors, friction and limits with the parameters in use
        (``model.drive``): what every consumer of the drive train reads."""
        return DriveTrain.of(self.actuators, self.parameters, self.n)

    @property
    def is_closed_chain(self) -> bool:
        """Whether the robot has loops (cut joints): then ``closed_chain_inverse_dynamics``,
        not ``inverse_dynamics``."""
        return self.n_constraints > 0

    @property
    def parameters(self) -> dict[str, float]:
        """Name -> value (SI, the unit in ``parameter_list``) of every parameter, as used."""
        return {par.name: float(v) for par, v in zip(self.parameter_list, self.p)}

    def casadi_function(self, quantity: str):
        """One of the robot's functions as a ``casadi.Function`` (saved at derive time with
        ``Function.save``), for ``casadi.Opti``, integrators or your own graphs: no SymPy and no
        compiler needed. Symbolic (``MX``/``SX``) or numeric inputs, one sample as columns.

        Parameters
        ----------
        quantity : str
            A key of ``library.manifest["functions"]``: ``"mass_matrix"`` (q, p) -> M (n, n),
            ``"bias"`` (q, qd, p) -> h (n,), ``"constraint"`` (q, p) -> Phi (m,) in m,
            ``"inverse_dynamics"``, ``"task"``, ... Inputs are q (n,) in rad or m, qd in rad/s
            or m/s, qdd in rad/s^2 or m/s^2, and p (n_p,) the parameter vector (SI, ``self.p``).

        Returns
        -------
        casadi.Function
        """
        import casadi as ca

        functions = self.library.manifest["functions"]
        if quantity not in functions:
            raise InputError(f"{self.name} has no function {quantity!r}; it has: "
                             f"{', '.join(functions)}")
        saved = functions[quantity].get("casadi")
        if saved is None:
            raise InputError(f"{self.library.folder} was derived before functions were saved "
                             "for CasADi: derive it again (`make derive`, or planar-sym derive)")
        return ca.Function.load(str(self.library.folder / saved))

    def with_parameters(self, **values: float) -> Robot:
        """A copy with some parameters changed (SI units), no re-derivation needed.

        The new values pass the description's physical checks (``model.parameters``): positive
        masses, plausible inertias, finite values, a plausible gravity; else InputError names
        the parameter and the value.

        Parameters
        ----------
        **values : float
            Parameter name -> new value in SI (kg, m, kg*m^2, m/s^2: the ``unit`` of its
            ``parameter_list`` entry), e.g. ``m_motor2=0.5``.

        Returns
        -------
        Robot
            The same compiled code with the new parameter vector ``p``.
        """
        names = [par.name for par in self.parameter_list]
        p = self.p.copy()
        for k, v in values.items():
            if k not in names:
                raise InputError(f"unknown parameter {k!r} of {self.name}; known: "
                                 f"{', '.join(names)}")
            try:
                p[names.index(k)] = float(v)
            except (TypeError, ValueError, OverflowError):
                raise InputError(f"parameter {k} must be a number (got {v!r})") from None
            if not np.isfinite(p[names.index(k)]):
                raise InputError(f"{self.name}: parameter {k} must be finite (got {v!r})")
        return Robot(self.name, self.library, p, exact=self.exact)

    # -- evaluation --------------------------------------------------------------------------
    def _call(self, quantity: str, **arrays) -> tuple[dict[str, np.ndarray], bool]:
        args = {k: as_samples(k, a, self.n) for k, a in arrays.items()}  # validates first
        single = all(np.ndim(a) == 1 for a in arrays.values())
        sizes = {a.shape[0] for a in args.values()}
        if len(sizes) != 1:
            raise InputError(f"{', '.join(args)} must have the same number of samples, got "
                             + ", ".join(f"{k}: {a.shape[0]}" for k, a in args.items()))
        args["p"] = self.p
        return self._fns[quantity](sizes.pop(), args), single

    @staticmethod
    def _out(res: np.ndarray, single: bool) -> np.ndarray:
        return res[0] if single else res

    def mass_matrix(self, q) -> np.ndarray:
        """M(q), shape (N, n, n) in kg*m^2."""
        r, s = self._call("mass_matrix", q=q)
        return self._out(r["M"], s)

    def bias(self, q, qd) -> np.ndarray:
        """h(q, qd) = C(q, qd) qd + g(q), shape (N, n), N*m."""
        r, s = self._call("bias", q=q, qd=qd)
        return self._out(r["h"], s)

    def gravity(self, q) -> np.ndarray:
        """g(q), shape (N, n), N*m."""
        r, s = self._call("gravity", q=q)
        return self._out(r["g"], s)

    def tree_inverse_dynamics(self, q, qd, qdd) -> np.ndarray:
        """M qdd + h for every coordinate of the spanning tree, shape (N, n), N*m."""
        r, s = self._call("inverse_dynamics", q=q, qd=qd, qdd=qdd)
        return self._out(r["tau"], s)

    def inverse_dynamics(self, q, qd, qdd) -> np.ndarray:
        """Joint torques (N*m) of a serial (tree) robot, shape (N, n), one compiled call.

        tau = M(q) qdd + C(q, qd) qd + g(q). Every joint must be actuated; a closed chain
        uses ``closed_chain_inverse_dynamics``.

        Parameters
        ----------
        q : ndarray, shape (N, n) or (n,)
            Joint coordinates (rad; m for a prismatic joint).
        qd : ndarray, shape (N, n) or (n,)
            Joint rates (rad/s; m/s).
        qdd : ndarray, shape (N, n) or (n,)
            Joint accelerations (rad/s^2; m/s^2).

        Returns
        -------
        tau : ndarray, shape (N, n), or (n,) for one sample
            Joint torques (N*m; N at a prismatic joint).

        Raises
        ------
        InputError
            A closed chain, a passive joint, a bad shape or a non-finite value (naming the
            sample).
        """
        if self.is_closed_chain:
            raise InputError(f"{self.name} is a closed chain: use closed_chain_inverse_dynamics "
                             "(torques and loop reaction forces together)")
        self._refuse_passive_joints()
        return self.tree_inverse_dynamics(q, qd, qdd)

    def _refuse_passive_joints(self) -> None:
        """A tree with a joint that has no motor cannot follow an arbitrary joint trajectory:
        the torque a motorless joint would need is not a number to return."""
        passive = [c for i, c in enumerate(self.coordinates) if i not in self.actuated]
        if passive:
            raise InputError(
                f"{self.name}: joint{'s' if len(passive) > 1 else ''} {', '.join(passive)} "
                f"{'have' if len(passive) > 1 else 'has'} no motor (actuated = false): a serial "
                "robot cannot follow an arbitrary joint trajectory with a passive joint, so "
                "there is no torque to return there; simulate it under the actuated joints' "
                "torques (planar_sym.simulate) or mark the joint actuated")

    def closed_chain_inverse_dynamics(self, q, qd, qdd, t=None) -> tuple[np.ndarray, np.ndarray]:
        """Actuated torques (N, actuated) in N*m and cut-joint forces lambda (N, 2 * loops) in N.

        q, qd, qdd: every coordinate, on the loops (from inverse_kinematics or
        motion.closure.from_actuated). Convention: M qdd + h = S^T tau + Phi_q^T lambda, solved
        in one generated function, which also returns the loop residuals; a sample off the
        loops (``LOOP_TOL_M``, see ``check_on_loops``) raises InputError, and a pose where the
        passive-joint constraint Jacobian Phi_p is singular (1-norm condition number above
        COND_LIMIT) raises WorkspaceError, each naming the sample (and the time ``t``, s).

        Parameters
        ----------
        q, qd, qdd : ndarray, shape (N, n) or (n,)
            Every coordinate (rad; m at a slider), its rate (rad/s) and acceleration
            (rad/s^2), passive joints included.
        t : ndarray, shape (N,), optional
            Times (s), only to name the time of a refused sample.

        Returns
        -------
        tau : ndarray, shape (N, actuated)
            Torques at the actuated coordinates (N*m; N at a slider), in ``actuated`` order.
        lam : ndarray, shape (N, 2 * loops)
            Force (N, world x and y per cut joint, in ``loops`` order) the cut joint's child
            body exerts on its parent body.
        """
        if not self.is_closed_chain:
            raise InputError(f"{self.name} is not a closed chain: use inverse_dynamics")
        q, qd, qdd = (as_samples(k, a, self.n, times=t) for k, a in (("q", q), ("qd", qd),
                                                                       ("qdd", qdd)))
        out = self._closed_inverse_dynamics(q, qd, qdd)
        tau, lam, cond, phi, phi_v, phi_a = (np.asarray(a).reshape(len(q), -1) for a in out)
        self.check_on_loops(phi, phi_v, phi_a, qd, qdd, t)
        self.refuse_singular(cond[:, 0], t)
        return tau, lam

    def refuse_singular(self, cond: np.ndarray, t=None) -> None:
        """Refuse the first sample whose passive-joint constraint Jacobian Phi_p has a 1-norm
        condition number ``cond`` above COND_LIMIT (or not finite), naming it.

        Parameters
        ----------
        cond : ndarray, shape (N,)
            Condition numbers (dimensionless), one per sample.
        t : ndarray, shape (N,), optional
            Times (s), to name the time of the sample refused.

        Raises
        ------
        WorkspaceError
            At the first singular sample.
        """
        bad = ~np.isfinite(cond) | (cond > COND_LIMIT)
        if bad.any():
            k = int(np.argmax(bad))
            raise WorkspaceError(f"{self.name}: singular pose at {_when(t, k)}: the passive-joint "
                                 f"constraint Jacobian Phi_p (which the actuation matrix "
                                 f"[S^T Phi_q^T] needs) has 1-norm condition number "
                                 f"{cond[k]:.3g} > {COND_LIMIT:g}")

    def check_on_loops(self, phi, phi_v, phi_a, qd, qdd, t=None) -> None:
        """Refuse samples off the loop constraints, naming the first and its residual.

        .. code:: text

            |Phi|                  <= LOOP_TOL_M                              (m)
            |Phi_q qd|             <= LOOP_TOL_M (1 + max|qd|)                (m/s)
            |Phi_q qdd - gamma|    <= LOOP_TOL_M (1 + max|qd|^2 + max|qdd|)   (m/s^2)

        (rates in rad/s, accelerations in rad/s^2: the allowance grows with the terms' size)

        Parameters
        ----------
        phi, phi_v, phi_a : ndarray, shape (N, 2 * loops)
            The residuals Phi (m), Phi_q qd (m/s) and Phi_q qdd - gamma (m/s^2).
        qd, qdd : ndarray, shape (N, n)
            Rates (rad/s) and accelerations (rad/s^2), which scale the allowances.
        t : ndarray, shape (N,), optional
            Times (s), to name the time of the sample refused.

        Raises
        ------
        InputError
            At the first sample off the loops, naming the residual and the cut joint.
        """
        if all(r.size == 0 or max(r.max(), -r.min()) <= LOOP_TOL_M for r in (phi, phi_v, phi_a)):
            return  # every sample within the smallest allowance: one pass per array, no rows
        speed = np.max(np.abs(qd), axis=1)
        limits = {"Phi (m)": (phi, LOOP_TOL_M * np.ones(len(phi))),
                  "Phi_q qd (m/s)": (phi_v, LOOP_TOL_M * (1 + speed)),
                  "Phi_q qdd - gamma (m/s^2)": (
                      phi_a, LOOP_TOL_M * (1 + speed**2 + np.max(np.abs(qdd), axis=1)))}
        for what, (residual, limit) in limits.items():
            worst = np.max(np.abs(residual), axis=1)
            bad = ~(worst <= limit)
            if bad.any():
                k = int(np.argmax(bad))
                cut = self.loops[int(np.argmax(np.abs(residual[k]))) // 2]
                raise InputError(
                    f"{self.name}: sample {k}{f' (t = {t[k]:.6g} s)' if t is not None else ''} "
                    f"is off the loop constraints: |{what.split(' (')[0]}| = {worst[k]:.3g} "
                    f"{what.split('(')[1][:-1]} at cut joint {cut} (limit {limit[k]:.3g}); "
                    "give q, qd, qdd that close the loops (inverse_kinematics, from_actuated)")

    def _closed_inverse_dynamics(self, q, qd, qdd):
        """The fused generated function's outputs (exact path): tau, lambda, cond and the loop
        residuals Phi, Phi_q qd, Phi_q qdd - gamma."""
        r = self._fns["closed_inverse_dynamics"](len(q), {"q": q, "qd": qd, "qdd": qdd,
                                                          "p": self.p})
        return tuple(r[k] for k in ("tau", "lambda", "cond", "phi", "phi_v", "phi_a"))

    def forward_dynamics(self, q, qd, tau) -> np.ndarray:
        """qdd = M^-1 (tau - h) of a serial robot, shape (N, n), rad/s^2.

        ``q`` (rad), ``qd`` (rad/s) and ``tau`` (N*m, every coordinate: 0 at a passive joint)
        are each (N, n) or (n,); a closed chain is simulated with ``planar_sym.simulate``.
        """
        if self.is_closed_chain:
            raise InputError(f"{self.name} is a closed chain: use planar_sym.simulate, which "
                             "keeps the loop constraints")
        r, s = self._call("forward_dynamics", q=q, qd=qd, tau=tau)
        return self._out(r["qdd"], s)

    def energy(self, q, qd) -> tuple[np.ndarray, np.ndarray]:
        """Kinetic and potential energy (J), each shape (N,)."""
        r, s = self._call("energy", q=q, qd=qd)
        return self._out(r["kinetic"], s), self._out(r["potential"], s)

    def task(self, q, qd=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Task coordinates x (m, rad), Jacobian J = dx/dq and Jdot qd at each sample.

        Parameters
        ----------
        q : ndarray, shape (N, n) or (n,)
            Coordinates (rad; m for a slider).
        qd : ndarray, shape (N, n) or (n,), optional
            Rates (rad/s), default zero (then Jdot qd is zero).

        Returns
        -------
        x : ndarray, shape (N, n_task)
            Task coordinates in ``task_names`` order: x, y of the task point (m), and the
            orientation phi (rad) where the task has one.
        J : ndarray, shape (N, n_task, n)
            The task Jacobian dx/dq (m/rad, or rad/rad for phi).
        jdot_qd : ndarray, shape (N, n_task)
            dJ/dt qd (m/s^2, rad/s^2): the task acceleration at zero joint acceleration.
        """
        if not self.task_names:
            raise InputError(f"{self.name} has no task point (its description has no [task]): "
                             "give [task] point = 'body.point' for task coordinates and moves")
        q = as_samples("q", q, self.n) if np.ndim(q) != 1 else as_samples("q", q, self.n)[0]
        qd = np.zeros_like(q) if qd is None else qd
        r, s = self._call("task", q=q, qd=qd)
        return self._out(r["x"], s), self._out(r["J"], s), self._out(r["jdot_qd"], s)

    def frames(self, q) -> np.ndarray:
        """Origin (m) and angle (rad) of every body frame, shape (N, bodies, 3)."""
        r, s = self._call("frames", q=q)
        return self._out(r["frames"], s)

    def body_motion(self, q, qd, qdd) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """What Newton-Euler needs, exact (derived, no differences), in one compiled call.

        Component first (each component of every body contiguous per sample):

        Returns
        -------
        accelerations : ndarray, shape (N, 3, bodies)
            Centre of gravity acceleration x, y (m/s^2, world axes) and angular acceleration
            (rad/s^2), bodies as ``body_names``.
        cg : ndarray, shape (N, 2, bodies)
            Centre of gravity x, y (m).
        joint_points : ndarray, shape (N, 2, joints + cuts + prismatic joints)
            x and y of every joint's child point (m; the manifest's ``joints`` order: tree
            joints, then cuts), then of every cut's parent point (m), then of every prismatic
            joint's slide axis in world axes (unit vector).
        """
        if "body_motion" not in self._fns:
            raise LibraryError(f"{self.name}: the generated code in {self.library.folder} "
                               "predates body_motion (joint loads need it): re-derive it "
                               "(`make derive`, or `planar-sym derive` for your own robot)")
        r, s = self._call("body_motion", q=q, qd=qd, qdd=qdd)
        return tuple(self._out(r[k], s)  # type: ignore[return-value]
                     for k in ("accelerations", "cg", "joint_points"))

    def constraint(self, q) -> np.ndarray:
        """Loop-closure residual Phi(q) (m), shape (N, 2 * loops)."""
        r, s = self._call("constraint", q=q)
        return self._out(r["phi"], s)

    def constraint_jacobian(self, q) -> np.ndarray:
        """Loop-closure Jacobian Phi_q = dPhi/dq (m/rad; m/m at a slider), shape
        (N, 2 * loops, n)."""
        r, s = self._call("constraint_jacobian", q=q)
        return self._out(r["phi_q"], s)

    def constraint_bias(self, q, qd) -> np.ndarray:
        """gamma = -(Phi_q qd)_q qd, so that Phi_q qdd = gamma: shape (N, 2 * loops), m/s^2
        (``q`` in rad, ``qd`` in rad/s, each (N, n))."""
        r, s = self._call("constraint_bias", q=q, qd=qd)
        return self._out(r["gamma"], s)


"""A robot at run time: its compiled dynamics evaluated over whole trajectories.

.. code:: text

    M(q) qdd + h(q, qd) = tau,   h = C(q, qd) qd + g(q)

Every array method takes per-sample arrays of shape ``(N, n)`` (or ``(n,)`` for one sample, in
which case the result drops the sample axis too) and makes one compiled call for all N.
"""

from __future__ import annotations

from functools import cached_property
from pathlib import Path

import numpy as np

from ..environment import flag
from ..errors import InputError, LibraryError
from .arrays import as_samples, as_vector, when
from .drive import DriveTrain
from .fast_paths import bind_fast_paths
from .library import Library
from .loop_functions import LoopFunctions
from .loops import COND_LIMIT, LOOP_TOL_M
from .parameter_set import Parameter, Parameters, fixed_points

# defined in their own modules; still importable from here, where they first were
__all__ = ["COND_LIMIT", "LOOP_TOL_M", "Parameter", "Parameters", "Robot", "as_samples",
           "as_vector", "when"]


class Robot(LoopFunctions):
    """The model of one robot: its description's names, its compiled functions, its checked
    parameters and its drive train; immutable (``with_parameters`` makes another robot on the
    same compiled code, no re-derivation). The algorithms that use it are functions of the
    layers above (``dynamics``, ``motion``, ``analysis``); the methods here evaluate the
    generated functions over whole trajectories.

    Load one with ``planar_sym.load`` (which compiles on first use and caches); the
    constructor is for a generated folder's ``Library`` at hand.

    Parameters
    ----------
    name : str
        A built-in robot's name (its generated folder), when ``library`` is not given.
    library : Library, optional
        The generated code and its manifest (``model.library``).
    parameters : ndarray, shape (len(parameter_list),), or Parameters, optional
        Parameter values in SI (kg, m, kg*m^2, m/s^2), in ``parameter_list`` order; default
        the values the robot was derived with. Checked as ``with_parameters`` checks them (a
        ``Parameters`` is already checked).
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
    passive : tuple of int
        The other coordinates (0-based), without a motor: a closed chain's passive joints.
    actuators : tuple of dict
        Per actuated coordinate: ``joint``, ``coordinate``, ``unit``, ``gear_ratio`` and the
        limits in SI (``torque_limit``, ``motor_torque_limit``, ``motor_speed_limit_rad_s``;
        None where there is none), and the motor's ``torque_constant`` (N*m/A) and
        ``winding_resistance`` (ohm), None where not given.
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
    parameters : Parameters
        Name -> SI value of every parameter in use, one checked immutable value.
    p : ndarray, shape (len(parameter_list),)
        ``parameters.vector``: what the compiled functions read (SI), read-only.
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
        #: the coordinates without a motor (0-based), in order: a closed chain's passive joints
        self.passive: tuple[int, ...] = tuple(i for i in range(len(self.coordinates))
                                              if i not in self.actuated)
        self.task_names: tuple[str, ...] = tuple(m["task"])
        self.body_names: tuple[str, ...] = tuple(m["bodies"])
        self.n_constraints: int = m["constraints"]
        self.loops: tuple[str, ...] = tuple(m["loops"])
        #: per actuated coordinate: joint, coordinate, unit, gear ratio and limits (SI); an
        #: ideal source (ratio 1, no limits) for a manifest from before actuator models
        self.actuators: tuple[dict, ...] = tuple(m.get("actuators") or (
            {"joint": self.coordinates[i], "coordinate": i, "unit": "N*m", "model": False,
             "gear_ratio": 1.0, "torque_limit": None, "motor_torque_limit": None,
             "motor_speed_limit_rad_s": None, "torque_constant": None,
             "winding_resistance": None} for i in self.actuated))
        self.q_drawn = np.array(m["q_drawn"])
        #: the one parameter value of this robot (checked once, read-only: a change makes a
        #: new Robot); the compiled callers read its vector in place
        self._parameters = parameters if isinstance(parameters, Parameters) else Parameters(
            tuple(Parameter(**p) for p in m["parameters"]), parameters,
            bodies=self.body_names, owner=self.name, fixed=fixed_points(m))
        self._fns = self.library.functions
        #: exact: CasADi's per-sample functions compiled without fast math. Otherwise the
        #: hot methods below are C-level callers of the vectorised loops (same algorithm,
        #: -ffast-math: agrees with the exact path to ~1e-15 relative, tested to 1e-12).
        self.exact = bool(flag("PLANAR_SYM_EXACT")) if exact is None else exact
        if not self.exact:
            bind_fast_paths(self)

    @property
    def n(self) -> int:
        """Number of coordinates n (passive ones included): the last axis of q, qd, qdd, tau."""
        return len(self.coordinates)

    @property
    def is_builtin(self) -> bool:
        """True for the package's own robots (``Library.is_builtin``)."""
        return self.library.is_builtin

    @property
    def description_file(self) -> Path | None:
        """The description it was derived from, where at hand (``Library.description_file``)."""
        return self.library.description_file

    @property
    def length_unit(self) -> str:
        """Its description's length unit, its pictures' too (``Library.length_unit``)."""
        return self.library.length_unit

    @property
    def has_friction(self) -> bool:
        """Whether an actuator's friction dissipates energy (a free motion then loses it)."""
        return any(p.name.startswith(("fv_", "fc_")) for p in self.parameter_list)

    @cached_property
    def drive_train(self) -> DriveTrain:
        """The actuated joints' gears, rotors, friction and limits with the parameters in use
        (``model.drive``): what every consumer of the drive train reads."""
        return DriveTrain.of(self.actuators, self.parameters, self.n)

    @property
    def is_closed_chain(self) -> bool:
        """Whether it has loops (cut joints): then ``closed_chain_inverse_dynamics`` applies."""
        return self.n_constraints > 0

    @property
    def parameters(self) -> Parameters:
        """Name -> value (SI, the unit in ``parameter_list``) of every parameter, as used: one
        immutable, checked ``Parameters`` (a mapping; ``.vector`` in ``parameter_list``
        order)."""
        return self._parameters

    @property
    def parameter_list(self) -> tuple[Parameter, ...]:
        """Every parameter: name, SI value as derived, unit and meaning."""
        return self._parameters.entries

    @property
    def p(self) -> np.ndarray:
        """The parameter values the compiled functions use, shape (len(parameter_list),), SI, in
        ``parameter_list`` order; read-only (``with_parameters`` makes a robot with others)."""
        return self._parameters.vector

    def casadi_function(self, quantity: str):
        """One of the robot's functions as a ``casadi.Function`` (``Library.casadi_function``:
        for ``casadi.Opti``, integrators or your own graphs; inputs q, qd, ... and the
        parameter vector ``p``, one sample as columns)."""
        return self.library.casadi_function(quantity)

    def with_parameters(self, **values: float | str) -> Robot:
        """A copy with some parameters changed, no re-derivation needed.

        The new values pass the description's physical checks (``model.parameters``): positive
        masses, plausible inertias, finite values, a plausible gravity; else InputError names
        the parameter and the value.

        Parameters
        ----------
        **values : float or str
            Name -> value in SI (the ``unit`` of its ``parameter_list`` entry), ``m_motor2=0.5``,
            or typed with its unit as a study or ``--set`` would, ``m_motor2="500 g"``.

        Returns
        -------
        Robot
            The same compiled code with the new parameter vector ``p``.
        """
        return self.with_values(self._parameters.replace_typed(**values))

    def with_values(self, parameters: Parameters) -> Robot:
        """The same compiled code with ``parameters`` (made from this robot's own by
        ``Parameters.replace`` or ``with_vector``, so already checked)."""
        if parameters.entries != self._parameters.entries:
            raise InputError(f"{self.name}: these parameters belong to another robot "
                             f"({parameters.owner})")
        return Robot(self.name, self.library, parameters, exact=self.exact)

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
        passive = [self.coordinates[i] for i in self.passive]
        if passive:
            raise InputError(
                f"{self.name}: joint{'s' if len(passive) > 1 else ''} {', '.join(passive)} "
                f"{'have' if len(passive) > 1 else 'has'} no motor (actuated = false): a serial "
                "robot cannot follow an arbitrary joint trajectory with a passive joint, so "
                "there is no torque to return there; simulate it under the actuated joints' "
                "torques (planar_sym.simulate) or mark the joint actuated")

    def _refuse_torque_at_passive_joints(self, tau) -> None:
        """A joint without a motor takes no torque: the rule ``simulate`` applies (its torques
        are the actuated joints' only), here for a torque given at every coordinate."""
        if not self.passive or np.ndim(tau) not in (1, 2) or np.shape(tau)[-1] != self.n:
            return  # no passive joint, or a shape the compiled call refuses with its message
        cols = np.atleast_2d(np.asarray(tau, dtype=float))[:, list(self.passive)]
        hit = np.argwhere(cols != 0.0)
        if len(hit):
            k, j = hit[0]
            raise InputError(
                f"{self.name}: joint {self.coordinates[self.passive[j]]} has no motor "
                f"(actuated = false) but tau gives it {cols[k, j]:.6g} at sample {k}: give 0 "
                "there (a passive joint's torque is zero), or mark the joint actuated")

    def forward_dynamics(self, q, qd, tau) -> np.ndarray:
        """qdd = M^-1 (tau - h) of a serial robot, shape (N, n), rad/s^2.

        ``q`` (rad), ``qd`` (rad/s) and ``tau`` (N*m, every coordinate: 0 at a passive joint)
        are each (N, n) or (n,); a closed chain is simulated with ``planar_sym.simulate``.
        """
        if self.is_closed_chain:
            raise InputError(f"{self.name} is a closed chain: use planar_sym.simulate, which "
                             "keeps the loop constraints")
        self._refuse_torque_at_passive_joints(tau)
        return self.tree_forward_dynamics(q, qd, tau)

    def tree_forward_dynamics(self, q, qd, tau) -> np.ndarray:
        """qdd = M^-1 (tau - h) for a torque at every coordinate of the spanning tree, passive
        ones included, shape (N, n), rad/s^2: the generated function as it is (validation)."""
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

"""The hot methods of a Robot bound to C-level callers of the vectorised loops: one compiled
call per batch with no Python frame in between (``_fastcall.c``).

Same algorithm as the exact per-sample CasADi functions, compiled with -ffast-math: agrees to
~1e-15 relative (tested to 1e-12). Each caller reads the robot's parameter vector in place, so
a robot's vector is never changed after binding (``Parameters.vector`` is read-only).
"""

from __future__ import annotations

from functools import cache

from ..errors import InputError
from .compile import fastcall

#: output kind of the manifest -> the caller's shape code
_KINDS = {"scalar": 0, "vector": 1, "matrix": 2}


def bind_fast_paths(robot) -> None:
    """Replace ``robot``'s hot methods by callers of the generated loops, where its library
    has them (a folder derived before a loop existed keeps the Python method). A loop whose
    group is not compiled yet (a big robot's) is bound by its first call (``_OnFirstCall``)."""
    fast = fastcall()
    if fast is None or not robot.library.has_loops:
        return
    recipes = _recipes(robot.library, type(robot), robot.is_closed_chain,
                       len(robot.actuated) == robot.n)
    checked = _loops_check_inputs(robot.library)
    for attr, quantity, recipe in recipes:
        if not robot.library.is_built(quantity):
            setattr(robot, attr, _OnFirstCall(robot, attr, quantity, recipe, checked))
            continue
        address = robot.library.loop_address(quantity)
        if address is not None:
            setattr(robot, attr, _caller(fast, address, recipe, robot, checked))


def _caller(fast, address: int, recipe: tuple, robot, checked: bool):
    sizes, p_slot, outputs, names, doc = recipe
    return fast.make(address, sizes, p_slot, outputs, robot.p, InputError, names, doc, checked)


class _OnFirstCall:
    """A hot method of a big robot whose loop compiles on first use: the first call compiles
    the loop's group, puts the C-level caller in this one's place, and calls it (where the
    loops cannot be built, the Python method takes over)."""

    def __init__(self, robot, attr: str, quantity: str, recipe: tuple, checked: bool):
        self._robot, self._attr, self._quantity = robot, attr, quantity
        self._recipe, self._checked = recipe, checked
        self.__doc__ = recipe[-1]

    def __call__(self, *args, **kwargs):
        return self._bind()(*args, **kwargs)

    @property
    def designs(self):
        """The C-level caller's ``designs`` (a sweep's many parameter vectors in one call):
        compiles the group as a call would; AttributeError where no loops can be built, so
        ``hasattr`` tells a sweep to run design by design, as on the exact path."""
        return self._bind().designs

    def _bind(self):
        """The caller now in this one's place (or the class's method, with no loops)."""
        robot = self._robot
        if robot.__dict__.get(self._attr) is not self:  # bound already (by another path)
            return getattr(robot, self._attr)
        address = robot.library.loop_address(self._quantity)
        if address is None:  # no loops on this machine: the class's method
            del robot.__dict__[self._attr]
            return getattr(robot, self._attr)
        caller = _caller(fastcall(), address, self._recipe, robot, self._checked)
        setattr(robot, self._attr, caller)
        return caller


@cache
def _recipes(library, cls, closed: bool, fully_actuated: bool) -> tuple:
    """What each caller of a library is made from (shapes, names, docstring; the address
    comes from the library when it is built): the same for every robot on that library, so
    worked out once (a sweep makes a robot per design)."""
    methods = {"mass_matrix": "mass_matrix", "bias": "bias", "gravity": "gravity",
               "tree_inverse_dynamics": "inverse_dynamics", "energy": "energy"}
    if not closed:
        methods.update(tree_forward_dynamics="forward_dynamics")
        if fully_actuated:  # else the methods check the passive joints first
            methods.update(forward_dynamics="forward_dynamics",
                           inverse_dynamics="inverse_dynamics")
    else:
        methods.update(constraint="constraint", constraint_jacobian="constraint_jacobian",
                       constraint_bias="constraint_bias",
                       _closed_inverse_dynamics="closed_inverse_dynamics")
    functions = library.manifest["functions"]
    if "body_motion" in functions:  # folders derived before lack it
        methods.update(body_motion="body_motion")
    out = []
    for attr, quantity in methods.items():
        spec = functions[quantity]
        if "loop" not in spec:  # derive makes loops only for these (codegen.LOOPED)
            continue
        method = getattr(cls, attr, None)
        out.append((attr, quantity, _shapes(spec, method.__doc__ if method is not None
                                             else spec["doc"])))
    return tuple(out)


def _shapes(spec: dict, doc: str) -> tuple:
    """(input sizes, the slot of p, output shapes, input names, docstring) of a loop."""
    ins = [(name, size) for name, size in spec["inputs"]]
    return (tuple(size for name, size in ins if name != "p"),
            [name for name, _ in ins].index("p"),
            tuple((rows, cols, _KINDS[kind]) for _, rows, cols, kind in spec["outputs"]),
            tuple(name for name, _ in ins if name != "p"), doc)


def loop_caller(robot, quantity: str, doc: str = ""):
    """A C-level caller of one generated loop (``quantity`` of the manifest) reading ``robot``'s
    parameter vector, or None where the library has no loop for it (derived before it, or no
    compiler): what a consumer above the model (identification's regressor) binds once."""
    fast = fastcall()
    spec = robot.library.manifest["functions"].get(quantity)
    if fast is None or not robot.library.has_loops or spec is None or "loop" not in spec:
        return None
    address = robot.library.loop_address(quantity)
    if address is None:
        return None
    return _caller(fast, address, _shapes(spec, doc or spec["doc"]), robot,
                   _loops_check_inputs(robot.library))


def _loops_check_inputs(library) -> bool:
    """Whether the library's loops report a non-finite input themselves (derived since they
    do): the caller then skips its own pass over the inputs."""
    return bool(library.manifest.get("loops_check_inputs", False))

"""Reading the sections of a study file ([parameters], [motion], [simulation], [optimise],
[outputs]) into their typed form, every problem noted with its field (``checks.Checker``).
"""

from __future__ import annotations

from itertools import pairwise

from ..expressions import ExpressionError, quantity
from .checks import Checker, finite
from .control_spec import parse_torque
from .spec_tables import (
    _MOTION,
    _OPTIMISE,
    _OUTPUTS,
    _SIMULATION,
    ANIMATIONS,
    INTEGERS,
    MAX_DURATION_S,
    METHODS,
    PROFILES,
    SOLVERS,
    SPACES,
)
from .spec_types import Motion, Optimise, Outputs, Simulation


class StudyChecker(Checker):
    """The sections of a study file."""

    def robot_ref(self, robot: str | None) -> str:
        """A built-in name stays a name; a path is made absolute against the study file."""
        if robot is None or ("/" not in robot and not robot.endswith(".toml")):
            return robot or ""
        return str((self.base / robot).resolve())

    def parameters(self, tbl: dict, section: str = "parameters"
                   ) -> dict[str, tuple[float, str | None]]:
        out = {}
        for name, v in tbl.items():
            fld = f"{section}.{name}"
            if isinstance(v, str):  # "0.5 kg", "2*0.3 kg", "m1/2": the unit is checked later
                try:
                    out[name] = quantity(v, self.names)
                except ExpressionError as exc:
                    self.err(fld, str(exc))
                    continue
            elif isinstance(v, (int, float)) and not isinstance(v, bool):
                out[name] = (float(v), None)
            else:
                self.err(fld, f"must be a number, or a number and a unit such as \"0.5 kg\" "
                              f"(got {v!r})")
                continue
            if not finite(out[name][0]):
                self.err(fld, f"must be finite (got {v!r})")
                del out[name]
        return out

    def motion(self, m: dict) -> Motion | None:
        self.keys(m, _MOTION, "motion.")
        space = self.choice(m, "space", "motion.space", SPACES)
        profile = self.choice(m, "profile", "motion.profile", PROFILES, "cubic")
        ik = self.choice(m, "ik", "motion.ik", SOLVERS, "auto")
        samples = self.integer(m, "samples", "motion.samples", *INTEGERS["motion"]["samples"])
        start_pose = self.vector(m, "start_pose", "motion.start_pose")
        if space == "joint" and "ik" in m:
            self.err("motion.ik", "only for space = \"task\" (a joint-space motion needs no "
                                  "inverse kinematics)")
        kw: dict = {}
        shape = profile or ("via" if "points" in m else "table" if "file" in m else "cubic")
        if shape in ("cubic", "quintic", "trapezoid"):  # (an unknown profile: checked as cubic)
            kw["start"] = self.vector(m, "start", "motion.start", required=True) or ()
            by, end = self.vector(m, "by", "motion.by"), self.vector(m, "end", "motion.end")
            if (by is None) == (end is None) and "by" not in m and "end" not in m:
                self.err("motion", "give the displacement `by = [...]` or the end `end = [...]`")
            elif "by" in m and "end" in m:
                self.err("motion", "give `by` or `end`, not both")
            for key, vec in (("by", by), ("end", end)):
                if vec is not None and kw["start"] and len(vec) != len(kw["start"]):
                    # which of the two is wrong, the robot says: checked when it is loaded
                    self.err(f"motion.{key}", f"has {len(vec)} values and motion.start "
                                              f"{len(kw['start'])}: both need one per "
                                              "coordinate moved")
            kw.update(by=by, end=end)
            if shape == "trapezoid":
                kw["v_max"] = self.vector(m, "v_max", "motion.v_max", required=True)
                kw["a_max"] = self.vector(m, "a_max", "motion.a_max", required=True)
                for key in ("v_max", "a_max"):
                    if kw[key] is not None and min(kw[key]) <= 0:
                        self.err(f"motion.{key}", f"must be > 0 (got {list(kw[key])})")
                if "duration" in m:
                    kw["duration_s"] = self.number(m, "duration", "motion.duration",
                                                   positive=True, limit=MAX_DURATION_S)
            else:
                kw["duration_s"] = self.number(m, "duration", "motion.duration", positive=True,
                                               limit=MAX_DURATION_S)
        elif shape == "via":
            kw.update(self._via(m))
        elif shape == "table":
            if "file" not in m:
                self.err("motion.file", "missing: a CSV of t_s and the coordinates")
            else:
                kw["table"] = self.file(m["file"], "motion.file")
        if shape != "table" and "file" in m:
            self.err("motion.file", "only for profile = \"table\"")
        if None in (space, profile, ik):
            return None
        return Motion(space, profile, samples=samples, ik=ik, start_pose=start_pose, **kw)

    def _via(self, m: dict) -> dict:
        times = self.vector(m, "times", "motion.times", required=True)
        raw = m.get("points")
        points = None
        if not isinstance(raw, list) or not raw or not all(isinstance(p, list) for p in raw):
            self.err("motion.points", f"must be a list of points [[...], [...]] (got {raw!r:.80})")
        else:
            rows = [self.vector({"p": p}, "p", f"motion.points[{i}]") for i, p in enumerate(raw)]
            if all(r is not None for r in rows):
                if len({len(r) for r in rows}) != 1:
                    self.err("motion.points", "every point must have the same number of values")
                else:
                    points = tuple(rows)
        if times is not None:
            if any(b <= a for a, b in pairwise(times)) or times[0] != 0.0:
                self.err("motion.times", f"must start at 0 and increase (got {list(times)})")
            elif times[-1] > MAX_DURATION_S:
                self.err("motion.times", f"must end by {MAX_DURATION_S:g} s")
            if points is not None and len(points) != len(times):
                self.err("motion.points", f"{len(points)} points for {len(times)} times")
            if len(times) < 2:
                self.err("motion.times", "needs at least 2 via points")
        for key in ("start", "by", "end", "duration"):
            if key in m:
                self.err(f"motion.{key}", "not used by profile = \"via\" (the points and times "
                                          "give the motion)")
        return {"times_s": times, "points": points}

    def simulation(self, s: dict) -> Simulation | None:
        self.keys(s, _SIMULATION, "simulation.")
        q0 = self.vector(s, "q0", "simulation.q0", required=True)
        qd0 = self.vector(s, "qd0", "simulation.qd0")
        duration = self.number(s, "duration", "simulation.duration", positive=True,
                               limit=MAX_DURATION_S)
        samples = self.integer(s, "samples", "simulation.samples",
                               *INTEGERS["simulation"]["samples"])
        method = self.choice(s, "method", "simulation.method", METHODS, "dopri5")
        rtol = self.number(s, "rtol", "simulation.rtol", positive=True, default=1e-11)
        atol = self.number(s, "atol", "simulation.atol", positive=True, default=1e-12)
        torque = parse_torque(self, s.get("torque"), "simulation.torque")
        if q0 is not None and qd0 is not None and len(qd0) != len(q0):
            self.err("simulation.qd0", f"must have {len(q0)} values like simulation.q0 "
                                       f"(got {len(qd0)})")
        if None in (q0, duration, method, rtol, atol):
            return None
        return Simulation(q0, duration, qd0, samples, torque, method, rtol, atol)

    def optimise(self, o: dict) -> Optimise:
        self.keys(o, _OPTIMISE, "optimise.")
        limits = {}
        for key in sorted(_OPTIMISE):
            v = self.vector(o, key, f"optimise.{key}")
            if v is not None and not all(x > 0 for x in v):
                self.err(f"optimise.{key}", f"must be positive (got {list(v)})")
            limits[key] = v
        return Optimise(**limits)

    def outputs(self, o: dict) -> Outputs:
        self.keys(o, _OUTPUTS, "outputs.")
        anim = o.get("animation", False)
        if anim is True:
            anim = "gif"
        if anim is not False and anim not in ANIMATIONS:
            self.err("outputs.animation", f"must be false, true, \"gif\" or \"mp4\" (got {anim!r})")
            anim = False
        return Outputs(self.flag(o, "csv", "outputs.csv", True),
                       self.flag(o, "plot", "outputs.plot", True),
                       self.flag(o, "split", "outputs.split", False),
                       anim or None,
                       self.integer(o, "frames", "outputs.frames", *INTEGERS["outputs"]["frames"]))

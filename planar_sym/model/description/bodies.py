"""Bodies: their points and centre of gravity into the body frame, and a plausibility check of
mass and inertia against the body's size.

``pose = "world"``: points are world coordinates of the drawn configuration; the frame (origin
at a point, x toward another or world-aligned) fixes the body's drawn placement too.
``pose = "joints"``: points are in the body's own coordinates; the frame only re-expresses them
(origin at a point, x toward another, or the coordinates as typed), and the body is placed later
along the tree from the joint angles.
"""

from __future__ import annotations

import math

from ...spelling import unknown_keys
from .fields import BODY_KEYS, GROUND_KEYS, NAME, snap
from .plausibility import Plausibility
from .quantities import (
    POINT_BALL,
    QUANTITIES,
    doubt,
    gyration_slip,
    inertia_doubt,
    inertia_fits,
    mass_doubt,
)
from .types import CLOSURE_TOLERANCE_M, GROUND, GYRATION_LIMIT, Body


class Bodies(Plausibility):
    """The ground and body stage of the validator."""

    def _ground(self, g, scale) -> Body | None:
        if not isinstance(g, dict):
            self.err("ground", "missing table [ground] with its points (world frame)")
            return None
        unknown_keys(g, GROUND_KEYS, lambda key, msg: self.err(f"ground.{key}", msg))
        before = len(self.problems)
        pts = self._points(g.get("points"), "ground.points", scale.get("length"))
        if len(self.problems) > before:
            return None  # a bad point is not (0, 0): no joint at it is checked
        return Body(GROUND, 0.0, 0.0, (0.0, 0.0), pts, 0.0, (0.0, 0.0))

    def _cg_from(self, raw: dict, f: str, pts: dict, pose: str | None,
                 points_ok: bool) -> tuple[bool, str | None]:
        """(valid, cg_from): a point, "world" (pose world), or None (pose joints: the origin of
        the body's coordinates). With a problem in the points, a point they lack is not another."""
        if pose == "world":
            cg_from = self._str(raw, "cg_from", f"{f}.cg_from")
            if cg_from is not None and cg_from != "world" and cg_from not in pts:
                if not points_ok:
                    return False, None
                self.err(f"{f}.cg_from", f"must be 'world' or one of its points {sorted(pts)} "
                                         f"(got {cg_from!r})")
                return False, None
            return cg_from is not None, cg_from
        cg_from = raw.get("cg_from")
        if cg_from is None or (pose is None and cg_from == "world"):
            return True, None  # an unknown pose: no second message about the same mistake
        if not isinstance(cg_from, str) or cg_from not in pts:
            if not points_ok and isinstance(cg_from, str):
                return False, None
            self.err(f"{f}.cg_from", f"must be one of its points {sorted(pts)}, or omitted for "
                                     "the origin of the body's own coordinates (pose = "
                                     f"'joints' has no world point) (got {cg_from!r})")
            return False, None
        return True, cg_from

    def _body(self, i: int, raw: dict, scale, pose: str | None) -> Body | None:
        f = f"bodies[{i}]"
        unknown_keys(raw, BODY_KEYS, lambda key, msg: self.err(f"{f}.{key}", msg))
        # a body with a problem of its own is not built: nothing after it (frame, closure,
        # plausibility, joints naming it) reports the same mistake again
        before = len(self.problems)
        name = self._str(raw, "name", f"{f}.name")
        if name is not None:
            f = f"bodies[{i}] ({name})"
            if not NAME.match(name) or name == GROUND:
                self.err(f"{f}.name", f"must be an identifier other than 'ground' (got {name!r})")
        length, mass_u, inertia_u = scale.get("length"), scale.get("mass"), scale.get("inertia")
        mass = self._num(raw, "mass", f"{f}.mass")
        if mass is not None and not self._judge(f"{f}.mass", "mass", mass):
            mass = None
        mass_at = raw.get("mass_at")
        if mass_at is None:
            izz = self._num(raw, "izz", f"{f}.izz")
            if izz is not None and not self._judge(f"{f}.izz", "inertia", izz):
                izz = None
        else:  # a massless link carrying a point mass: cg at the point, no inertia about it
            izz, inertia_u = 0.0, 1.0
            for key in sorted({"izz", "cg", "cg_from"} & set(raw)):
                self.err(f"{f}.{key}", f"not with mass_at (a point mass at {mass_at!r}: its "
                                       "centre of gravity is that point and its inertia "
                                       "about it is 0)")
        n_points = len(self.problems)
        pts = self._points(raw.get("points"), f"{f}.points", length)
        points_ok = len(self.problems) == n_points
        if mass_at is not None:
            if not isinstance(mass_at, str) or (points_ok and mass_at not in pts):
                self.err(f"{f}.mass_at", f"must name one of its points {sorted(pts)} (got "
                                         f"{mass_at!r})")
                return None
            cg_given, cg_ok, cg_from = (0.0, 0.0), True, mass_at
            if pose == "world" and mass_at in pts:
                cg_given = pts[mass_at]
                cg_from = "world"
        else:
            cg_given = self._vec(raw, "cg", f"{f}.cg", length)
            cg_ok, cg_from = self._cg_from(raw, f, pts, pose, points_ok)
        # world: the frame is at the first point unless named; joints: the coordinates as typed
        frame = raw.get("frame")
        if frame is None:
            frame = [next(iter(pts))] if pts and pose != "joints" else []
        elif (not isinstance(frame, list) or not 1 <= len(frame) <= 2
                or any(not isinstance(p, str) or p not in pts for p in frame)):
            if not points_ok and isinstance(frame, list) and 1 <= len(frame) <= 2 \
                    and all(isinstance(p, str) for p in frame):
                return None  # it may name the point in error
            self.err(f"{f}.frame", f"must be [origin] or [origin, x_toward], naming its points "
                                   f"{sorted(pts)} (got {frame!r})")
            return None
        if (None in (name, mass, izz, length, mass_u, inertia_u) or not pts or not cg_ok
                or len(self.problems) > before):
            return None
        origin = pts[frame[0]] if frame else (0.0, 0.0)
        angle = 0.0
        if len(frame) == 2:
            dx, dy = pts[frame[1]][0] - origin[0], pts[frame[1]][1] - origin[1]
            if math.hypot(dx, dy) < CLOSURE_TOLERANCE_M:
                self.err(f"{f}.frame", f"points {frame} coincide: no x-axis direction")
                return None
            angle = math.atan2(dy, dx)
        local = {p: to_body(xy, origin, angle) for p, xy in pts.items()}
        # offset rotated on its own, then added in the body frame: keeps 0.04168 exact
        base = to_body((0.0, 0.0), origin, angle) if cg_from in ("world", None) else local[cg_from]
        off = to_body(cg_given, (0.0, 0.0), angle)
        cg = snap(base[0] + off[0]), snap(base[1] + off[1])
        # pose = "joints": this placement is the typed coordinates; the tree replaces it
        body = Body(name, mass * mass_u, izz * inertia_u, cg, local, angle, origin,
                    point_mass=mass_at is not None)
        if mass_at is None and not self._cg_plausible(f, body, cg_from, pose):
            self._plausible(f, body, (raw["mass"], raw["izz"]), self.unit_names)
        return body

    def _plausible(self, f: str, body: Body, typed: tuple[float, float], units: dict) -> None:
        """A body with extent needs inertia, and not more than its size allows; a warning for a
        mass or inertia its size makes a likely slip (``quantities``), both as ``typed`` in
        ``units``."""
        izz_given, unit = typed[1], units["inertia"]
        if body.mass_kg <= 0 or body.izz_kg_m2 < 0:
            return  # reported already
        extent = max(math.dist(body.cg_m, xy) for xy in body.points_m.values())
        if extent < CLOSURE_TOLERANCE_M:  # a point mass (a motor at a joint, a bob, a piston)
            self._point_plausible(f, body, typed, units)
            return
        if body.izz_kg_m2 == 0.0:
            self.err(f"{f}.izz", f"must be > 0 for a body with extent (its points reach "
                                 f"{extent * 1e3:.4g} mm from its centre of gravity); only a "
                                 "body with a single point may be a point mass")
            return
        radius = math.sqrt(body.izz_kg_m2 / body.mass_kg)
        light = doubt(QUANTITIES["mass"], typed[0], units["mass"])
        if radius > GYRATION_LIMIT * extent and not self.length_slip and light is not None:
            # a mass slip makes the radius (a trial: 1e-9 kg was blamed on izz): at the mass
            self.err(f"{f}.mass", f"{light} (with izz = {izz_given} {unit} it gives a radius "
                                  f"of gyration of {radius * 1e3:.4g} mm for a body whose "
                                  f"points reach {extent * 1e3:.4g} mm)")
        elif radius > GYRATION_LIMIT * extent and not self.length_slip and (
                slip := gyration_slip(typed, units, extent)) is not None:
            # the mass or the points read in another unit fit: not izz's fault (a trial)
            if slip[0] == "points":
                self.points_slip |= {body.name}
            self.err(f"{f}.{slip[0]}", slip[1])
        elif radius > GYRATION_LIMIT * extent and not self.length_slip:  # the slip is reported
            hint = inertia_fits(izz_given, unit, body.mass_kg, extent,
                                "a unit or decimal-point slip?")
            self.err(f"{f}.izz", f"implausible: {izz_given} {unit} gives a radius of gyration "
                                 f"of {radius * 1e3:.4g} mm for a body whose points reach "
                                 f"{extent * 1e3:.4g} mm from its centre of gravity (more than "
                                 f"{GYRATION_LIMIT:g} times); {hint}")
        elif not self.span_doubt:  # one mistake, one message: a heavy mass lowers the radius
            if (msg := mass_doubt(typed[0], units["mass"], extent)) is not None:
                self.warn(f"{f}.mass", msg)
            elif (msg := inertia_doubt(izz_given, unit, body.mass_kg, extent)) is not None:
                slip = gyration_slip(typed, units, extent)  # g typed as kg: a small radius
                self.warn(f"{f}.{slip[0]}" if slip else f"{f}.izz", slip[1] if slip else msg)


    def _point_plausible(self, f: str, body: Body, typed: tuple[float, float],
                         units: dict) -> None:
        """A single-point body has no size of its own: its inertia (any izz >= 0, a rotor's)
        and mass are measured against the robot's span. A user trial: izz = 1e8 kg*mm^2 on a
        0.29 kg motor (48 N*m where 0.39 N*m is right) and 2000 kg at a 0.1 m arm's elbow
        passed every route silently."""
        span = self.span_m
        if span < CLOSURE_TOLERANCE_M or self.span_doubt:  # the span's own slip is reported
            return
        izz_given, unit = typed[1], units["inertia"]
        radius = math.sqrt(body.izz_kg_m2 / body.mass_kg)
        if radius > GYRATION_LIMIT * span:
            hint = inertia_fits(izz_given, unit, body.mass_kg, span,
                                "a unit or decimal-point slip?")
            self.err(f"{f}.izz", f"implausible: {izz_given} {unit} gives a radius of gyration "
                                 f"of {radius * 1e3:.4g} mm to a body of a single point in a "
                                 f"robot whose points span {span * 1e3:.4g} mm (more than "
                                 f"{GYRATION_LIMIT:g} times); {hint}")
        elif (msg := mass_doubt(typed[0], units["mass"], span, POINT_BALL)) is not None:
            self.warn(f"{f}.mass", msg)


def to_body(xy, origin, angle: float) -> tuple[float, float]:
    """A position ``xy`` into the frame at ``origin`` turned by ``angle``; tiny values snap to 0."""
    dx, dy = xy[0] - origin[0], xy[1] - origin[1]
    c, s = math.cos(angle), math.sin(angle)
    return (snap(c * dx + s * dy), snap(-s * dx + c * dy))

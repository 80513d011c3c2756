"""Study files fuzzed (issue 25, class 4): the shipped studies of every kind (joint and task
moves, tracking with a plant, a free swing, closed chains), parsed, mutated at random (a key
deleted, a value of the wrong type or a hostile number, a number scaled, an unknown key) and
written back. Whatever comes in, ``load_study`` and the robot with the study's parameters either
work or raise a ``PlanarSymError`` naming the file; a study that loads then runs (at 5 samples,
inverse kinds) to a result or a ``PlanarSymError``; never another exception.

The suite runs ``PLANAR_SYM_FUZZ_CASES`` (default 40) cases, a few seconds;
``PLANAR_SYM_FUZZ_CASES=2000 pytest tests/test_hypothesis_studies.py`` runs it longer.
"""

from __future__ import annotations

import math
import os
import tomllib
import warnings

from conftest import ROOT
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from test_hypothesis_descriptions import dumps

from planar_sym.errors import PlanarSymError
from planar_sym.study.run import load_study, robot_of, run

CASES = int(os.environ.get("PLANAR_SYM_FUZZ_CASES") or 40)
BUILTIN = ROOT / "planar_sym" / "studies"
STUDIES = ["serial_2dof_joint_move", "serial_2dof_cartesian_move", "serial_2dof_cartesian_track",
           "serial_2dof_free_swing", "five_bar_type1_move_x", "slider_crank_turn",
           "serial_rpr_tool_move"]
BASES = {name: tomllib.loads((BUILTIN / f"{name}.toml").read_text()) for name in STUDIES}

HOSTILE = [0, -1, 1, 2, 0.0, -0.0, 1e-300, 1e300, math.inf, -math.inf, math.nan, 10 ** 30,
           -(10 ** 30), 2.5, "", "x", "é", "1 kg", "-1 m", "deg", "rad", "cubic", True, False,
           [], [0.0], [1.0, 2.0], [1.0, 2.0, 3.0], ["a", "b"], [math.nan, 0.0], {}, {"x": 1}]

SCALES = [0, -1, 1e-3, 1e3, 1e6, 0.5, 2, 1.0001]


def _at(table: dict, path):
    for k in path:
        table = table[k]
    return table


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _leaves(table: dict, path=()):
    """Every key path of ``table`` (tables and values)."""
    for k, v in table.items():
        yield (*path, k)
        if isinstance(v, dict):
            yield from _leaves(v, (*path, k))


@st.composite
def mutated(draw):
    name = draw(st.sampled_from(STUDIES))
    data = tomllib.loads(dumps(BASES[name]))  # a deep copy
    for _ in range(draw(st.sampled_from([1, 1, 1, 2]))):
        paths = sorted(_leaves(data))
        if not paths:
            break
        numbers = [p for p in paths if _is_number(_at(data, p))]
        scale = bool(numbers) and draw(st.booleans())  # half the cases keep every type right
        path = draw(st.sampled_from(numbers if scale else paths))
        parent = _at(data, path[:-1])
        value = parent[path[-1]]
        action = "scale" if scale else draw(st.sampled_from(["delete", "replace", "unknown"]))
        event(action)
        if action == "scale":  # the right type, a hostile size: reaches past the file checks
            parent[path[-1]] = value * draw(st.sampled_from(SCALES))
        elif action == "delete":
            del parent[path[-1]]
        elif action == "replace":
            parent[path[-1]] = draw(st.sampled_from(HOSTILE))
        else:
            parent["no_such_key"] = draw(st.sampled_from(HOSTILE))
    return name, data


@settings(max_examples=CASES, deadline=None, derandomize=CASES <= 40,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(case=mutated())
def test_any_study_file_is_run_or_refused_by_name(tmp_path_factory, case):
    name, data = case
    path = tmp_path_factory.mktemp("fuzz") / f"{name}.toml"
    try:
        path.write_text(dumps(data))
    except (TypeError, ValueError):  # a value the writer cannot write: not a study file
        return
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            study = load_study(path)
            robot_of(study)
        except PlanarSymError as exc:
            assert str(path) in str(exc) or path.name in str(exc), str(exc)
            event("refused at load")
            return
        if study.kind != "inverse":
            event("loads (not run here)")
            return
        try:
            run(study, samples=5)
            event("runs")
        except PlanarSymError:
            event("refused at run")

"""Sweeps over designs (issue 13): every route against the study run once per design through a
new Robot (``with_parameters``, the independent route), serial against threads, processes and a
Dask cluster (equal to the bit), the C loop over designs against the per-sample caller, pickling
by reference, the GIL released, and every bad input with its one message."""

from __future__ import annotations

import copyreg
import multiprocessing
import pickle
import threading
import warnings
from concurrent.futures import Future, ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.analysis.designs import design_space
from planar_sym.analysis.sweep import kinematic_parameters, sweep
from planar_sym.cli import main
from planar_sym.errors import InputError
from planar_sym.study.run import load_study, robot_of, run_on

ROOT = Path(__file__).resolve().parent.parent


def per_design(study: str, result) -> dict[str, np.ndarray]:
    """The independent route: a new Robot per design (with_parameters, checked), the study's
    whole run, its torque and cut-force columns reduced here in numpy (the RMS over time by
    the trapezoidal rule)."""
    st = load_study(study)
    base = robot_of(st)
    out: dict[str, list] = {}
    for k in range(len(result)):
        values = {n: result.columns[c][k] for n, c in zip(result.parameters, result.varied)}
        res = run_on(st, base.with_parameters(**values))
        for name, v in res.columns.items():
            if name.startswith("tau"):
                out.setdefault(f"peak_{name}", []).append(np.max(np.abs(v)))
                t = res.columns["t_s"]
                out.setdefault(f"rms_{name}", []).append(
                    np.sqrt(np.trapezoid(v**2, t) / (t[-1] - t[0])))
            if name.startswith(("fx_", "fy_")):
                out.setdefault(f"peak_{name}", []).append(np.max(np.abs(v)))
    return {k: np.array(v) for k, v in out.items()}


@pytest.mark.parametrize("study, vary, route", [
    ("serial_2dof_cartesian_move", {"m_link2": (0.05, 0.1, 3), "izz_link2": [1e-4, 3e-4]},
     "shared motion"),
    ("serial_2dof_cartesian_move", {"px_link1_CS2": (0.09, 0.12, 4)}, "motion per design"),
    ("five_bar_type1_move_x", {"m_R_Link2": (0.03, 0.09, 3), "g": [9.81, 1.62]},
     "shared motion"),
    ("five_bar_type1_move_x", {("px_L_Link1_CS2", "px_R_Link1_CS2"): (0.09, 0.12, 3)},
     "motion per design"),
    ("parallel_3rrr_move_x", {"m_Link1_2": [0.03, 0.06]}, "shared motion"),
])
def test_sweep_equals_a_new_robot_per_design(study, vary, route):
    result = sweep(study, vary)
    assert result.route == route and not result.failed
    ref = per_design(study, result)
    assert set(ref) == {f for f in result.figures if f != "max_cond_phi_p"}
    for name, v in ref.items():
        np.testing.assert_allclose(result.columns[name], v, rtol=1e-12, atol=1e-15,
                                   err_msg=name)


def test_simulation_and_control_sweeps_equal_their_runs():
    """Forward and controlled studies run per design on one robot whose parameters are set in
    place; the figures equal a new Robot's run. The control study's model only (on="model"),
    against a new model Robot under the study's own plant (m_link2 = 0.09 kg); the plant and
    both: tests/test_sweep_drive_plant.py."""
    for study, name in (("serial_2dof_free_swing", "energy_change_j"),
                        ("serial_2dof_cartesian_track_pd", "max_abs_e_task_mm")):
        on = "model" if "track" in study else "both"
        result = sweep(study, {"m_link2": [0.06, 0.09]}, workers=1, on=on)
        assert result.route == "per design" and not result.failed
        st = load_study(study)
        for k, m in enumerate((0.06, 0.09)):
            res = run_on(st, robot_of(st).with_parameters(m_link2=m))
            want = (res.columns["energy_j"][-1] - res.columns["energy_j"][0]
                    if name == "energy_change_j" else np.max(np.abs(res.columns["e_task_mm"])))
            assert result.columns[name][k] == pytest.approx(want, rel=1e-12, abs=1e-15)


def test_which_parameters_move_the_joints():
    """Task-space motion depends on the lengths to the task point; masses never move joints;
    a joint-space move of a tree depends on nothing."""
    arm = ps.load("serial_2dof")
    assert kinematic_parameters(arm, "task") == {"px_link1_CS2", "px_link2_CS2"}
    assert kinematic_parameters(arm, "joint") == set()
    five = ps.load("five_bar_type1")
    moving = kinematic_parameters(five, "joint")  # the loops: every length on them
    assert "px_ground_E" in moving and not any(n.startswith(("m_", "izz_")) for n in moving)


def test_designs_loop_equals_per_sample_calls():
    """Caller.designs: per-design parameter vectors against one call per design; the reduced
    statistics against numpy on the full output."""
    arm = ps.load("serial_2dof")
    rng = np.random.default_rng(3)
    q, qd, qdd = (rng.normal(size=(50, 2)) for _ in range(3))
    P = np.tile(arm.p, (7, 1))
    P[:, 6] = np.linspace(0.05, 0.2, 7)  # m_link2
    full = arm.tree_inverse_dynamics.designs(P, q, qd, qdd)
    stats = arm.tree_inverse_dynamics.designs(P, q, qd, qdd, reduce=True)
    per = np.stack([arm.with_parameters(m_link2=p[6]).inverse_dynamics(q, qd, qdd) for p in P])
    np.testing.assert_array_equal(full, per)
    np.testing.assert_allclose(stats[:, :, 0], per.min(axis=1), rtol=0, atol=0)
    np.testing.assert_allclose(stats[:, :, 1], per.max(axis=1), rtol=0, atol=0)
    np.testing.assert_allclose(stats[:, :, 2], (per**2).mean(axis=1), rtol=1e-14)
    # per-design motion (D, N, n) too
    Q = np.stack([q + k for k in range(7)])
    full = arm.tree_inverse_dynamics.designs(P, Q, qd, qdd)
    np.testing.assert_array_equal(full[4], arm.with_parameters(m_link2=P[4, 6])
                                  .inverse_dynamics(Q[4], qd, qdd))
    with pytest.raises(InputError, match=r"q\[3, 1\] is nan"):
        bad = q.copy()
        bad[3, 1] = np.nan
        arm.tree_inverse_dynamics.designs(P, bad, qd, qdd)
    with pytest.raises(InputError, match=r"shape \(designs, 11\)"):
        arm.tree_inverse_dynamics.designs(P[:, :5], q, qd, qdd)


def test_the_designs_loop_releases_the_gil():
    """While one thread is inside the C loop, another Python thread runs: it counts while the
    loop is busy (with the GIL held it could not count at all)."""
    arm = ps.load("serial_2dof")
    q = np.random.default_rng(0).normal(size=(201, 2))
    P = np.tile(arm.p, (20000, 1))
    count, stop = [0], threading.Event()

    def counter():
        while not stop.is_set():
            count[0] += 1

    inside = []

    def busy():
        before = count[0]
        arm.tree_inverse_dynamics.designs(P, q, q, q, reduce=True)
        inside.append(count[0] - before)

    t = threading.Thread(target=counter)
    t.start()
    try:
        busy()
    finally:
        stop.set()
        t.join()
    assert inside[0] > 100


def test_threads_processes_and_serial_agree_to_the_bit():
    vary = {"px_link1_CS2": (0.09, 0.12, 6), "m_link2": [0.05, 0.08]}
    serial = sweep("serial_2dof_cartesian_move", vary, workers=1)
    threads = sweep("serial_2dof_cartesian_move", vary, workers=2, batch=3)
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as pool:
        procs = sweep("serial_2dof_cartesian_move", vary, executor=pool, batch=4)
    for other in (threads, procs):
        assert list(other.columns) == list(serial.columns)
        for k, v in serial.columns.items():
            np.testing.assert_array_equal(other.columns[k], v)


def test_dask_local_cluster_of_two_processes_equals_serial():
    distributed = pytest.importorskip("dask.distributed")
    vary = {("px_L_Link1_CS2", "px_R_Link1_CS2"): (0.09, 0.12, 8)}
    serial = sweep("five_bar_type1_move_x", vary, workers=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        result = sweep("five_bar_type1_move_x", vary, executor=client, batch=2)
        where = client.run(lambda: __import__("os").getpid())
    assert len(set(where.values())) == 2
    for k, v in serial.columns.items():
        np.testing.assert_array_equal(result.columns[k], v)


def test_robot_pickles_by_reference(tmp_path):
    five = ps.load("five_bar_type1").with_parameters(m_L_Link1=0.1)
    data = pickle.dumps(five)
    assert len(data) < 2000  # a reference, not the compiled code
    back = pickle.loads(data)
    assert back.parameters == five.parameters and back.library is five.library
    np.testing.assert_array_equal(back.gravity(five.q_drawn), five.gravity(five.q_drawn))
    own = ps.load(ROOT / "examples" / "four_bar.toml")
    ref = copyreg.dispatch_table[type(own)](own)  # the folder and the description's text
    restore, (where, digest, p, exact) = ref[0], ref[1]
    assert where[1] == str(own.library.folder.resolve()) and "[[bodies]]" in where[2]
    # a node without the folder derives the same robot from the text (same input hash)
    moved = restore((where[0], str(tmp_path / "elsewhere"), where[2]), digest, p, exact)
    q = own.q_drawn
    np.testing.assert_array_equal(moved.mass_matrix(q), own.mass_matrix(q))


def test_a_failing_design_is_reported_and_the_others_kept():
    """A proximal link too short for the move's targets: those designs fail with the inverse
    kinematics' own message, the rest have figures equal to their own runs."""
    result = sweep("serial_2dof_cartesian_move", {"px_link1_CS2": [0.1, 0.03, 0.11]})
    assert list(result.failed) == [1]
    assert "outside the workspace" in result.failed[1] or "reach" in result.failed[1]
    assert np.isnan(result.columns["peak_tau1_n_m"][1])
    assert np.isfinite(result.columns["peak_tau1_n_m"][[0, 2]]).all()
    assert "error" in result.csv_text().splitlines()[0]


class _Flaky:
    """An executor whose second batch dies in its worker (as a killed process would)."""

    def __init__(self):
        self.calls = 0

    def submit(self, fn, *args):
        self.calls += 1
        fut: Future = Future()
        if self.calls == 2:
            fut.set_exception(RuntimeError("worker 2 was killed"))
        else:
            fut.set_result(fn(*args))
        return fut


def test_a_failing_executor_loses_only_its_batch():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = sweep("serial_2dof_cartesian_move", {"m_link2": (0.05, 0.1, 9)},
                       executor=_Flaky(), batch=3)
    assert sorted(result.failed) == [3, 4, 5]
    assert all("worker 2 was killed" in why for why in result.failed.values())
    assert any("3 of 9 designs were lost" in str(w.message) for w in caught)
    whole = sweep("serial_2dof_cartesian_move", {"m_link2": (0.05, 0.1, 9)})
    keep = [0, 1, 2, 6, 7, 8]
    np.testing.assert_array_equal(result.columns["peak_tau1_n_m"][keep],
                                  whole.columns["peak_tau1_n_m"][keep])


@pytest.mark.parametrize("vary, kwargs, pattern", [
    ({"m_lnk2": [0.1]}, {}, r"unknown parameter 'm_lnk2' of serial_2dof; known: g, m_link1"),
    ({"m_link2": (0.1, 0.05, 3)}, {}, r"low < high"),
    ({"m_link2": (-0.05, 0.1, 4)}, {},
     (r"design 0 \(m_link2 = -0.05\) is not physical: parameter m_link2 must be > 0 kg .*"
      r"\(2 of 4 designs are not\)")),
    ({"izz_link2": (1e-4, 10.0, 3)}, {}, r"radius of gyration"),
    ({"m_link2": (0.05, 0.1)}, {"sample": "random"}, r"count of designs >= 1"),
    ({"m_link2": [0.05, 0.1]}, {"sample": "random", "count": 5}, r"\(low, high\)"),
    ({f"m_link{k}": (0.05, 0.1, 2000) for k in (1, 2)} | {"g": (1.0, 9.0, 100)}, {},
     r"4e\+08 designs of 11 parameters would take 35.2 GB"),
])
def test_bad_sweeps_get_one_clear_message(vary, kwargs, pattern):
    arm = ps.load("serial_2dof")
    with pytest.raises(InputError, match=pattern):
        design_space(arm, vary, **kwargs)


def test_cli_sweep_writes_table_and_plot(tmp_path, capsys):
    rc = main(["sweep", "five_bar_type1_move_x", "--vary",
               "px_L_Link1_CS2,px_R_Link1_CS2=0.09:0.11:3", "--out", str(tmp_path)])
    assert rc == 0
    text = (tmp_path / "five_bar_type1_move_x_sweep.csv").read_text().splitlines()
    assert text[0].startswith("px_L_Link1_CS2_m,px_R_Link1_CS2_m,peak_tau1_n_m,rms_tau1_n_m")
    assert len(text) == 4 and (tmp_path / "five_bar_type1_move_x_sweep.png").stat().st_size > 1e4
    assert "3 designs (grid), motion per design" in capsys.readouterr().out
    for argv, msg in ((["--vary", "m_link2"], "write NAME=LOW:HIGH:COUNT"),
                      (["--vary", "m_link2=0.1:0.2"], "LOW:HIGH:COUNT expected on a grid"),
                      (["--vary", "m_link2=a,b"], "is not numbers"),
                      # the second --vary of a name replaced the first, the grid gone silently
                      (["--vary", "m_link2=0.1:0.2:3", "--vary", "m_link2=0.3,0.4"],
                       "'m_link2' is varied twice (give its values in one --vary"),
                      (["--vary", "m_link2,m_link2=0.3,0.4"], "names a parameter twice")):
        assert main(["sweep", "serial_2dof_cartesian_move", *argv, "--out", str(tmp_path)]) == 2
        assert msg in capsys.readouterr().err


def test_atlas_sweep_equals_each_designs_atlas():
    """Sweeping the Type II 5-bar's pivot distance: each design's atlas summary equals the
    atlas of a new Robot with that parameter (its drawn pose re-assembled by the atlas)."""
    from planar_sym.analysis.atlas import atlas

    result = sweep("five_bar_type2_move_x", {"px_ground_E": [0.15, 0.25]},
                   atlas={"points": 30})
    assert result.route == "atlas" and not result.failed
    base = ps.load("five_bar_type2")
    for k, e in enumerate((0.15, 0.25)):
        s = atlas(base.with_parameters(px_ground_E=e), points=30).summary()
        assert result.columns["area_m2"][k] == s["area_m2"]
        assert result.columns["median_dexterity"][k] == s["median_dexterity"]
    # pivots further apart reach less (the legs overlap less)
    assert result.columns["area_m2"][1] < result.columns["area_m2"][0]


@pytest.mark.parametrize("name", ["serial_2dof", "five_bar_type1", "parallel_3rrr", "serial_rpr"])
def test_column_checks_agree_with_the_scalar_rules(name):
    """model.parameters.failing (whole columns, for sweeps) refuses exactly the designs that
    model.parameters.problems (one design, for with_parameters) finds a problem in."""
    from planar_sym.model.parameters import failing, problems

    robot = ps.load(name)
    names = [p.name for p in robot.parameter_list]
    P = robot.p * np.random.default_rng(5).uniform(-0.5, 3.0, (600, len(names)))
    scalar = [bool(problems(dict(zip(names, map(float, row))), robot.body_names)) for row in P]
    np.testing.assert_array_equal(failing(names, P, robot.body_names), scalar)
    assert 0 < sum(scalar) < len(P)


def test_a_bad_value_in_a_design_array_names_the_design_and_the_sample():
    arm = ps.load("serial_2dof")
    P = np.tile(arm.p, (3, 1))
    q = np.zeros((3, 4, 2))
    q[1, 2, 0] = np.nan
    with pytest.raises(InputError, match=r"q\[1, 2, 0\] is nan at design 1, sample 2"):
        arm.tree_inverse_dynamics.designs(P, q, np.zeros((4, 2)), np.zeros((4, 2)))
    P[2, 3] = np.inf
    with pytest.raises(InputError, match=r"parameters\[2, 3\] is inf at design 2"):
        arm.tree_inverse_dynamics.designs(P, q[0], q[0], q[0])


def test_a_range_in_the_wrong_unit_is_warned_about():
    """Grams typed as kg (50 to 100 'kg' for a 75 g forearm): physically possible, so the
    sweep runs, but says so, naming the parameter and the factor."""
    with pytest.warns(RuntimeWarning, match=r"m_link2 = 50 kg \(read in kg\) is more than "
                                             r"osmium .* a slip\? In \"g\" it would be 0\.05 kg"):
        result = sweep("serial_2dof_cartesian_move", {"m_link2": [50.0, 100.0]})
    assert np.isfinite(result.columns["peak_tau2_n_m"]).all()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a range of ordinary size is quiet
        sweep("serial_2dof_cartesian_move", {"m_link2": [0.05, 0.1]})

"""Section 6: design tools: sweeps over designs and atlases.

* **Sweep overhead** (target: at most 2x the pure computation, S3 over 1e5 designs, one core):
  ``analysis.sweep.sweep`` of ``serial_2dof_cartesian_move`` varying ``m_link2`` and
  ``izz_link2`` on a grid (masses move no joint, so the motion is shared), one worker thread,
  against the pure computation: the generated inverse-dynamics loop called directly on the same
  number of samples (designs x 201) at one parameter vector, in calls of 2e6 samples (it writes
  every sample's torques, which the sweep reduces as it goes: so the sweep is also compared with
  its own compiled work, the C loop over the designs called alone). The sweep
  includes everything: the design grid and its physical checks, the study's motion, the C loop
  per batch, peak and RMS per design and the table. The old way (a new ``Robot`` per design by
  ``with_parameters``, then ``inverse_dynamics``) is timed on fewer designs and shown per design.
* **Lengths** (``px_link1_CS2``: the inverse kinematics per design): time per design of the
  sweep against a new Robot and ``run_study``'s motion per design.
* **Cores**: the same mass sweep on 2 threads against 1 (the C loop releases the GIL); a length
  sweep of the 5-bar (``five_bar_type1_move_x``, both proximal links tied) on a Dask
  ``LocalCluster`` of 2 worker processes against one serial thread (the cluster started
  beforehand, as a user's would be; results checked equal to the serial run before timing).
* **Atlas**: time per grid point of ``analysis.atlas.atlas`` at 100 x 100 points, against the
  2-DOF inverse dynamics per sample in the same rounds.
* **Animation** (a study's GIF): the S3 tracking scene (the arm and its faint reference, 40
  frames at 80 dpi) written by ``outputs.animation.write_animation`` (the still figure drawn
  once, the moving artists blitted per frame) against matplotlib's route, ``FuncAnimation``
  saved with its Pillow writer (the whole figure rendered per frame), in the same rounds; the
  frames are checked pixel-equal in the tests.
"""

from __future__ import annotations

import numpy as np

from . import Config
from .report import Check, Section, Table
from .timing import fmt_ratio, fmt_stats, interleaved, once_each, ratio

STUDY = "serial_2dof_cartesian_move"


def _mass_vary(designs: int) -> dict:
    k = designs // 100
    return {"m_link2": (0.05, 0.1, k), "izz_link2": (1e-4, 2e-4, 100)}


def run(cfg: Config) -> Section:
    from planar_sym.analysis.sweep import sweep
    from planar_sym.study.motion import joint_motion
    from planar_sym.study.run import load_study, robot_of, run_on

    sec = Section("design", "6. Design tools: sweeps and atlases", __doc__.split("\n\n")[0])
    designs = 1_000 if cfg.quick else 100_000
    st = load_study(STUDY)
    robot = robot_of(st)
    jt, _ = joint_motion(st, robot)
    per_call = 10_000  # designs' worth of samples per direct call: 2e6 samples
    n_calls = designs // per_call or 1
    chunk = min(designs, per_call)
    Q, QD, QDD = (np.ascontiguousarray(np.tile(a, (chunk, 1))) for a in (jt.q, jt.qd, jt.qdd))

    def pure():
        for _ in range(n_calls):
            robot.tree_inverse_dynamics(Q, QD, QDD)

    P = np.tile(robot.p, (designs, 1))

    def core():  # the compiled work of the sweep alone: one C loop over the designs
        robot.tree_inverse_dynamics.designs(P, jt.q, jt.qd, jt.qdd, reduce=True)

    vary = _mass_vary(designs)
    # gate: the sweep's figures against a new Robot's run for a few designs
    res = sweep(st, vary, workers=1)
    worst = 0.0
    for k in np.linspace(0, len(res) - 1, 5).astype(int):
        r = robot.with_parameters(m_link2=res.columns["m_link2_kg"][k],
                                  izz_link2=res.columns["izz_link2_kg_m2"][k])
        tau = run_on(st, r).columns["tau1_n_m"]
        worst = max(worst, abs(res.columns["peak_tau1_n_m"][k] / np.max(np.abs(tau)) - 1))
    sec.checks.append(Check("sweep peak torque vs a new Robot's run (5 designs)", worst, 1e-12))

    reps = 3 if cfg.quick else 5
    t = once_each({"pure": pure, "core": core, "sweep1": lambda: sweep(st, vary, workers=1),
                   "sweep2": lambda: sweep(st, vary, workers=2)}, repeats=reps)
    few = 200 if cfg.quick else 1000
    masses = np.linspace(0.05, 0.1, few)

    def new_robot_each():
        for m in masses:
            robot.with_parameters(m_link2=m).inverse_dynamics(jt.q, jt.qd, jt.qdd)

    t_old = once_each({"old": new_robot_each, "pure": pure}, repeats=reps)
    tab = Table(f"S3 ({STUDY}), {designs:,} designs of m_link2 x izz_link2, 201 samples each",
                ["", "time", "per design", "ratio"])
    tab.add("pure computation (generated loop, designs x 201 samples)",
            fmt_stats(t["pure"]), fmt_stats(t["pure"].scaled(1 / designs)), "1")
    tab.add("the sweep's compiled work alone (Caller.designs, reduce=True)", fmt_stats(t["core"]),
            fmt_stats(t["core"].scaled(1 / designs)), fmt_ratio(ratio(t["core"], t["pure"])))
    over = ratio(t["sweep1"], t["core"])
    tab.add("sweep, 1 thread", fmt_stats(t["sweep1"]), fmt_stats(t["sweep1"].scaled(1 / designs)),
            fmt_ratio(ratio(t["sweep1"], t["pure"])) + " of pure (target <= 2x); "
            + fmt_ratio(over) + " of its compiled work")
    tab.add("sweep, 2 threads", fmt_stats(t["sweep2"]),
            fmt_stats(t["sweep2"].scaled(1 / designs)),
            fmt_ratio(ratio(t["sweep1"], t["sweep2"])) + " speedup over 1 thread")
    old = t_old["old"].scaled(1 / few)
    tab.add(f"a new Robot per design ({few} designs)", "", fmt_stats(old),
            fmt_ratio(ratio(old, t["sweep1"].scaled(1 / designs))) + " the sweep's per design")
    sec.tables.append(tab)
    sec.headlines["sweep, S3, 1e5 designs, 1 core"] = (
        fmt_ratio(ratio(t["sweep1"], t["pure"])) + " of pure computation, "
        + fmt_ratio(over) + " of its own compiled work")
    sec.headlines["sweep, 2 threads vs 1"] = fmt_ratio(ratio(t["sweep1"], t["sweep2"]))

    # lengths: the motion per design
    n_len = 100 if cfg.quick else 1000
    lengths = {"px_link1_CS2": (0.09, 0.12, n_len)}

    def new_robot_runs():
        for a in np.linspace(0.09, 0.12, n_len // 10):
            run_on(st, robot.with_parameters(px_link1_CS2=a))

    t_len = once_each({"sweep": lambda: sweep(st, lengths, workers=1), "old": new_robot_runs},
                      repeats=3)
    tab = Table("Lengths: the inverse kinematics per design (S3, px_link1_CS2)",
                ["", "per design", "ratio"])
    s_len, o_len = t_len["sweep"].scaled(1 / n_len), t_len["old"].scaled(10 / n_len)
    tab.add(f"sweep, 1 thread ({n_len} designs)", fmt_stats(s_len), "1")
    tab.add(f"new Robot + run_study per design ({n_len // 10} designs)", fmt_stats(o_len),
            fmt_ratio(ratio(o_len, s_len)) + " slower")
    sec.tables.append(tab)
    _dask(cfg, sec)
    _atlas(cfg, sec, robot, jt)
    _animation(cfg, sec, robot, jt)
    return sec


def _animation(cfg: Config, sec: Section, robot, jt) -> None:
    import tempfile
    from pathlib import Path

    from matplotlib.animation import FuncAnimation, PillowWriter

    from planar_sym.outputs.animation import scene_figure, write_animation

    frames = 8 if cfg.quick else 40
    pick = np.linspace(0, len(jt.t_s) - 1, frames).astype(int)
    t, q = jt.t_s[pick], jt.q[pick]
    title = f"S3, {frames} frames"
    folder = Path(tempfile.mkdtemp())

    def ours():
        write_animation(robot, t, q, folder / "ours.gif", title, reference=(robot, q + 0.05))

    def matplotlib_route():
        fig, update = scene_figure(robot, t, q, title, reference=(robot, q + 0.05))
        anim = FuncAnimation(fig, update, frames=len(t), blit=False)
        anim.save(folder / "mpl.gif", writer=PillowWriter(fps=20), dpi=80)

    st = once_each({"ours": ours, "mpl": matplotlib_route}, repeats=2 if cfg.quick else 5)
    tab = Table(f"Animation: a {frames}-frame GIF of the S3 scene at 80 dpi",
                ["route", "time", "ratio"])
    tab.add("write_animation (blitted frames)", fmt_stats(st["ours"]), "1")
    tab.add("FuncAnimation.save, PillowWriter (full render per frame)", fmt_stats(st["mpl"]),
            fmt_ratio(ratio(st["mpl"], st["ours"])) + " slower")
    sec.tables.append(tab)
    sec.headlines["GIF of a study, blitted vs matplotlib's Animation.save"] = (
        fmt_ratio(ratio(st["mpl"], st["ours"])) + " faster")


def _dask(cfg: Config, sec: Section) -> None:
    from planar_sym.analysis.sweep import sweep

    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        sec.notes.append("dask.distributed not installed: the 2-worker row is skipped")
        return
    count = 100 if cfg.quick else 2000
    vary = {("px_L_Link1_CS2", "px_R_Link1_CS2"): (0.09, 0.12, count)}
    study = "five_bar_type1_move_x"
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        serial = sweep(study, vary, workers=1)
        dist = sweep(study, vary, executor=client)
        diff = max(float(np.nanmax(np.abs(dist.columns[k] - v))) for k, v in
                   serial.columns.items())
        sec.checks.append(Check("Dask 2-worker sweep equals the serial one", diff, 0.0))
        t = once_each({"serial": lambda: sweep(study, vary, workers=1),
                       "dask": lambda: sweep(study, vary, executor=client)}, repeats=3)
    tab = Table(f"Cluster: {study}, {count} designs of the tied proximal lengths (IK per design)",
                ["", "time", "speedup"])
    tab.add("1 thread, serial", fmt_stats(t["serial"]), "1")
    tab.add("Dask LocalCluster, 2 worker processes", fmt_stats(t["dask"]),
            fmt_ratio(ratio(t["serial"], t["dask"])))
    sec.tables.append(tab)
    sec.headlines["2-worker Dask speedup"] = fmt_ratio(ratio(t["serial"], t["dask"]))


def _atlas(cfg: Config, sec: Section, robot, jt) -> None:
    try:
        from planar_sym.analysis.atlas import atlas
    except ImportError:  # pragma: no cover - the atlas ships with this section
        return
    import planar_sym as ps

    points = 30 if cfg.quick else 100
    tab = Table(f"Atlas, {points} x {points} grid points", ["robot", "per grid point",
                                                             "ratio to 2-DOF ID per sample"])
    q = np.ascontiguousarray(np.tile(jt.q, (50, 1)))
    qd, qdd = (np.ascontiguousarray(np.tile(a, (50, 1))) for a in (jt.qd, jt.qdd))
    for name in ("serial_2dof", "five_bar_type1", "five_bar_type2"):
        r = ps.load(name)
        t = once_each({"atlas": lambda r=r: atlas(r, points=points)}, repeats=3)
        t_id = interleaved({"id": lambda: robot.inverse_dynamics(q, qd, qdd)},
                           repeats=cfg.repeats, per=len(q), min_block_s=cfg.min_block_s)
        cell_t = t["atlas"].scaled(1 / points**2)
        tab.add(name, fmt_stats(cell_t), f"{cell_t.median / t_id['id'].median:,.0f}x")
        if name == "five_bar_type1":
            sec.headlines["atlas per grid point (5-bar)"] = fmt_stats(cell_t)
    sec.tables.append(tab)

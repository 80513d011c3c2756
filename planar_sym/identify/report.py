"""What ``planar-sym identify`` writes: the tables, the report and the validation plot, all
written together or not at all (``files.atomic_files``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..files import atomic_files
from ..model.robot import Robot
from .data import Experiment
from .description_file import identified_description
from .estimate import Estimate, predicted_torques
from .physical import PhysicalFit

#: the robot parameters an identification sets (a study's [parameters] names)
IDENTIFIED = ("m_", "cgx_", "cgy_", "izz_", "jm_", "fv_", "fc_")


def write_results(robot: Robot, est: Estimate, fit: PhysicalFit, identified: Robot,
                  check: Experiment, validated: bool, out: Path) -> str:
    """Write DIR's files; returns the report's text."""
    out = Path(out)
    base = est.base
    rows = ["name,value,std,relative_std_pct,unit,expression"]
    for (name, v, s, r, u), expr in zip(est.table(), base.expressions()):
        rows.append(f"{name},{float(v)!r},{float(s)!r},{100 * r:.4g},{u},"
                    f"\"{expr.split(' = ', 1)[1]}\"")
    std_rows = ["name,value,unit,meaning"] + [
        f"{n},{float(v)!r},{u},\"{m}\"" for n, v, u, m in zip(
            fit.standard.names, fit.standard.values, fit.standard.units, fit.standard.meanings)]
    par = identified.parameters
    toml = [("# identified by planar-sym identify: paste into a study to run it on the "
             "identified robot"), "[parameters]"]
    toml += [f'{k} = "{float(par[k])!r} {par.unit(k)}"' for k in par
             if k.startswith(IDENTIFIED)]
    pred = predicted_torques(robot, est, check)
    err = np.sqrt(np.mean((pred - check.tau) ** 2, axis=0))
    rms = np.sqrt(np.mean(check.tau ** 2, axis=0))
    names = [robot.coordinates[i] for i in robot.actuated]
    units = ["N" if robot.coordinate_units[i] == "m" else "N*m" for i in robot.actuated]
    lines = [(f"{robot.name}: {len(base)} base parameters of {len(base.standard)} standard, "
              f"from {est.samples} samples (condition number {est.condition:.3g})")]
    lines += [f"  {n:16s} {v:+.6g} +- {s:.2g} ({100 * r:.2g} %) {u}"
              for n, v, s, r, u in est.table()]
    lines.append("regrouped: " + "; ".join(base.expressions()[k] for k in range(len(base))
                                           if np.count_nonzero(base.regrouping[k]) > 1))
    if base.unidentifiable:
        lines.append("no effect on any torque (not identifiable): "
                     + ", ".join(base.unidentifiable))
    lines.append("residual torque (std per joint): " + ", ".join(
        f"{robot.coordinates[robot.coordinates.index(r)]} {s:.3g}" for r, s in
        zip(est.rows, est.sigma)))
    what = "validation on data kept out of the fit" if validated else "fit (no --validate)"
    lines.append(f"{what}: RMS error " + ", ".join(
        f"{n} {e:.3g} {u} ({100 * e / max(r, 1e-300):.2g} % of its RMS)"
        for n, e, u, r in zip(names, err, units, rms)))
    lines.append(f"physically consistent standard parameters: {fit.distance:.3g} standard "
                 "deviations (Mahalanobis) from the estimate"
                 + (f"; on their limits: {', '.join(fit.active)}" if fit.active else ""))
    lines += [f"note: {n}" for n in est.notes]
    files = {"base_parameters.csv": "\n".join(rows) + "\n",
             "standard_parameters.csv": "\n".join(std_rows) + "\n",
             "identified_parameters.toml": "\n".join(toml) + "\n"}
    if robot.description_file is not None:  # every command runs on it: run identified_robot.toml
        files["identified_robot.toml"] = identified_description(
            robot, identified, f"Fit: {est.samples} samples, {len(base)} base parameters.")
    else:
        lines.append("note: no identified_robot.toml (the robot was not loaded from a "
                     "description file); identified_parameters.toml has the values")
    text = "\n".join(lines)
    files["report.txt"] = text + "\n"
    targets = [out / k for k in files] + [out / "validation.png"]
    with atomic_files(targets) as temps:
        for tmp, content in zip(temps, files.values()):
            tmp.write_text(content)
        _plot(temps[-1], check, pred, names, units, what, err)
    return text + f"\nwrote {out}/ ({', '.join(p.name for p in targets)})"


def _plot(path: Path, ex: Experiment, pred: np.ndarray, names, units, what: str, err) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(names), 1, figsize=(8, 2.4 * len(names)), sharex=True,
                             squeeze=False)
    for k, ax in enumerate(axes[:, 0]):
        ax.plot(ex.t_s, ex.tau[:, k], lw=1.0, label="measured (filtered)")
        ax.plot(ex.t_s, pred[:, k], lw=1.0, ls="--", label="identified model")
        ax.set_ylabel(f"{names[k]} torque ({units[k]})")
        ax.set_title(f"{names[k]}: RMS error {err[k]:.3g} {units[k]}", fontsize=9)
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=8)
    axes[-1, 0].set_xlabel("time (s)")
    fig.suptitle(what, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)

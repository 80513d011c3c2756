# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Identifying the 5-bar's masses from its motor torques
#
# A student built the Type I 5-bar. Its geometry is known (it was machined to drawing); its
# masses, centres of gravity and inertias are not, nor the friction of its two motors. The
# dynamics is *linear* in those parameters:
#
# $$\tau = Y(q, \dot q, \ddot q)\, \pi ,$$
#
# $\pi$ holding per link $m$, $m c_x$, $m c_y$ and the inertia about the link frame's origin,
# and per motor the viscous and Coulomb friction. For a closed chain $Y$ gives the actuated
# torques, pushed through the loop constraints like the torques themselves.
#
# Not every parameter shows in the torques: some act only together. The **base parameters**
# are the combinations that do.

# %%
import numpy as np
from IPython.display import display

import planar_sym as ps
from planar_sym.control.laws import controller
from planar_sym.dynamics.engine import simulate_controlled
from planar_sym.identify import (
    base_parameters,
    default_limits,
    excite,
    experiment,
    identified_robot,
    identify,
    physical_parameters,
    predicted_torques,
    standard_parameters,
)

robot = ps.load("five_bar_type1")
base = base_parameters(robot)
print(f"{len(base.standard)} standard parameters, {len(base)} base parameters")
for line in base.expressions(4):
    print("  " + line)
print("not identifiable (no effect on any torque):", ", ".join(base.unidentifiable))

# %% [markdown]
# The first links' masses do not show at all: each turns about a fixed pivot, so its mass only
# appears through its first moment and its inertia about the pivot. The distal links' masses
# are lumped into the proximal links' parameters (the parallel-axis theorem at work).
#
# ## The hidden truth
#
# To check the method we play the robot: a "true" 5-bar whose inertial parameters differ from
# the drawing by up to 30 %. The identification below never looks at it.

# %%
rng = np.random.default_rng(26)
keep = ("m_", "izz_", "cgx_", "cgy_")
truth = robot.with_parameters(**{k: robot.parameters[k] * rng.uniform(0.7, 1.3)
                                 for k in robot.parameters if k.startswith(keep)})
true_beta = base.values(standard_parameters(truth).values)

# %% [markdown]
# ## An exciting motion
#
# A periodic Fourier series per motor, chosen so that the stacked regressor is as well
# conditioned as the limits allow, and the 5-bar stays in its assembly mode, well away from
# singular poses (`planar-sym excite` does the same from the command line).

# %%
limits = default_limits(robot, range_=0.3, speed=1.0, acceleration=5.0)
design = excite(robot, 8.0, 3, limits=limits, samples=60, starts=1, seed=1)
print(f"condition number {design.start_condition:.3g} (random start) -> "
      f"{design.condition:.3g} (designed)")

# %% [markdown]
# ## The experiment
#
# The true robot tracks the motion under a computed-torque loop built on the *drawing's*
# model (that is all the controller knows). We record what a real rig would: 16-bit encoder
# angles of the motors and their torques with 1 % noise.

# %%
def measure(period_start):
    fs = 500.0
    t = np.arange(0.0, 8.0 + 1e-12, 1 / fs) + period_start
    q, qd, qdd = design.fourier(t)
    from planar_sym.motion.closure import from_actuated

    jt = from_actuated(robot, t, q, qd, qdd)
    run = simulate_controlled(robot, controller("computed_torque", 400.0, 40.0),
                              (t[0], t[-1]), reference=jt, plant=truth, t_eval=t)
    step = 2 * np.pi / 2**16
    angles = np.round(run.q[:, list(robot.actuated)] / step) * step
    noise = 0.01 * np.sqrt(np.mean(run.tau**2, axis=0))
    torques = run.tau + np.random.default_rng(int(period_start)).normal(size=run.tau.shape) * noise
    return experiment(robot, t, angles, torques, cutoff_hz=10.0), noise


data, noise = measure(0.0)
for note in data.notes:
    print("note:", note)

# %% [markdown]
# ## Identification
#
# Weighted least squares on the stacked base regressor, with each estimate's standard
# deviation. Against the hidden truth, every estimate should lie within about three of them.

# %%
est = identify(robot, data, base)
z = (est.values - true_beta) / est.std
print(f"{'base parameter':16s} {'estimate':>12s} {'std':>9s} {'truth':>12s} {'z':>6s}")
for (name, value, std, _, unit), truth_value, zz in zip(est.table(), true_beta, z):
    print(f"{name:16s} {value:+12.5g} {std:9.2g} {truth_value:+12.5g} {zz:+6.2f}")
print(f"max |z| = {np.abs(z).max():.2f}")

# %% [markdown]
# ## Does the identified model predict a new experiment?
#
# A second run, one period later with new noise: the identified model's torques against the
# measured ones, and the drawing's.

# %%
check, noise2 = measure(8.0)
pred = predicted_torques(robot, est, check)
drawing, _ = robot.closed_chain_inverse_dynamics(check.q, check.qd, check.qdd)
err = np.sqrt(np.mean((pred - check.tau) ** 2, axis=0))
err_drawing = np.sqrt(np.mean((drawing - check.tau) ** 2, axis=0))
for k, joint in enumerate(robot.coordinates[i] for i in robot.actuated):
    print(f"{joint}: RMS error identified {err[k]:.3g} N*m, drawing {err_drawing[k]:.3g} N*m "
          f"(torque noise {noise2[k]:.3g} N*m before filtering)")

import matplotlib.pyplot as plt

fig, axes = plt.subplots(2, 1, figsize=(8, 5), sharex=True)
for k, ax in enumerate(axes):
    ax.plot(check.t_s, check.tau[:, k], lw=1, label="measured (filtered)")
    ax.plot(check.t_s, pred[:, k], "--", lw=1, label="identified")
    ax.plot(check.t_s, drawing[:, k], ":", lw=1, label="drawing")
    ax.set_ylabel(f"tau{robot.actuated[k] + 1} (N*m)")
    ax.grid(alpha=0.3)
axes[0].legend(fontsize=8)
axes[1].set_xlabel("time (s)")
plt.show()

# %% [markdown]
# ## A robot to simulate
#
# Base parameters do not give every mass; a simulation needs them all, physically: positive
# masses, positive inertias about the centres of gravity. The nearest such set (in the
# estimate's own standard deviations), and among those the one nearest the drawing:

# %%
fit = physical_parameters(robot, est)
print(f"{fit.distance:.2f} standard deviations from the estimate")
identified = identified_robot(robot, fit, est)
display(identified)

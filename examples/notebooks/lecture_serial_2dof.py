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
# # Lecture 1: the 2-DOF serial arm
#
# Two links in a vertical plane, each driven at its base joint; the elbow motor (0.292 kg) rides
# on the end of link 1. With the joint angles $q = (q_1, q_2)$ as generalised coordinates,
# Lagrange's equations $\frac{d}{dt}\frac{\partial L}{\partial \dot q} - \frac{\partial L}
# {\partial q} = \tau$ with $L = T - V$ give
#
# $$M(q)\,\ddot q + C(q, \dot q)\,\dot q + g(q) = \tau .$$
#
# `planar_sym` derived these equations once (SymPy, `make derive`) and compiled them to C; here
# we read them, use them, and check them three ways: energy conservation in a free swing, the
# motors' work against the energy gained, and the printed closed forms evaluated by hand.

# %%
import numpy as np
from _notebooks import energy_change, evaluate, joints, motor_work, namespace
from IPython.display import display

import planar_sym as ps

arm = ps.load("serial_2dof")
display(arm)

# %% [markdown]
# ## The equations
#
# Every entry of $M$ is collected into lumped parameters ($\alpha$, $\beta$, $\delta$): only
# these combinations of masses, lengths and inertias are visible in the motion, so they are what
# an identification experiment can measure. $\cos q_2$ couples the links; the elbow motor's mass
# enters $M_{11}$ as $m_{M2} a_1^2$.

# %%
ps.equations("serial_2dof")

# %% [markdown]
# ## S1: the free swing
#
# Released from $q_1 = -60°$ at rest with no torque, the arm swings under gravity alone. With no
# friction, $T + V$ must stay constant: the integrator's energy drift measures its accuracy.

# %%
swing = ps.run_study("serial_2dof_free_swing")
energy = swing.columns["energy_j"]
print(f"serial_2dof_free_swing: q(1 s) = ({np.degrees(swing.columns['q1_rad'][-1]):.6f}, "
      f"{np.degrees(swing.columns['q2_rad'][-1]):.6f}) deg")
print(f"serial_2dof_free_swing: max |E - E(0)| = {np.max(np.abs(energy - energy[0])):.3g} J "
      f"of E(0) = {energy[0]:.6f} J")
display(swing)

# %% [markdown]
# The same swing through `ps.simulate`, shown with its robot: the table, the coordinates and
# energies, and the arm moving.

# %%
sim = ps.simulate(arm, [np.radians(-60.0), 0.0], [0.0, 0.0], (0.0, 1.0))
ps.show(sim, arm)

# %% [markdown]
# ## S2: the torques of a slow joint move
#
# Joint 1 turns from 0 to 90° in 10 s on a cubic. So slowly, the torques are almost the
# gravity terms $g(q)$ alone: $\tau_1$ falls from holding the horizontal arm out to nothing
# once the arm stands upright at 90°.

# %%
move = ps.run_study("serial_2dof_joint_move")
for key, value in move.peak_torques().items():
    print(f"{move.name}: peak |{key}| = {value:.12g} N*m")
display(move)

# %% [markdown]
# ## Check 1: the printed equations are the compiled ones
#
# The text form of the equations is Python syntax. Evaluated with numpy over the whole move,
# lumped parameters, then gravity terms, then the Euler-Lagrange equations give $\tau$ once
# more, by a route that shares nothing with the generated C.

# %%
ns = namespace(arm, joints(arm, move), joints(arm, move, "qd"), joints(arm, move, "qdd"))
evaluate(arm, "Lumped parameters", ns)
evaluate(arm, "Gravity terms", ns)
by_hand = evaluate(arm, "Euler-Lagrange", ns)
for key, tau in by_hand.items():
    diff = np.max(np.abs(tau - move.columns[f"{key}_n_m"]))
    print(f"{move.name}: closed form vs compiled, max |{key} difference| = {diff:.3g} N*m")

# %% [markdown]
# ## Check 2: power balance
#
# The motors' power $\tau^T \dot q$, integrated over the move, is the work they do; with no
# friction it all goes into kinetic and potential energy:
# $\int_0^{t_f} \tau^T \dot q \, dt = \Delta (T + V)$. The energy comes from the compiled energy
# function, not from the torques.

# %%
for name in ("serial_2dof_joint_move", "serial_2dof_cartesian_move"):
    result = ps.run_study(name)
    print(f"{name}: motor work W = {motor_work(result):.12g} J, "
          f"energy change dE = {energy_change(arm, result):.12g} J")

# %% [markdown]
# ## A heavier elbow motor
#
# The same straight-line tool move (S3) with a 0.6 kg motor: a new parameter value, no new
# derivation.

# %%
t = np.linspace(0.0, 5.0, 201)
path = ps.inverse_kinematics(arm, ps.cubic([0.1, 0.1], [-0.2, 0.0], 5.0, t))
for mass in (0.292, 0.6):
    robot = arm.with_parameters(m_motor2=mass)
    tau = robot.inverse_dynamics(path.q, path.qd, path.qdd)
    print(f"S3 with a {mass} kg motor: peak |tau1| = {np.max(np.abs(tau[:, 0])):.6f} N*m")

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
# # Lecture 2: the 3-DOF serial arm
#
# A third link makes the arm redundant for a point but exactly determined for a tool pose
# $(x, y, \varphi)$: three coordinates for three task variables. The inverse kinematics is the
# two-link solution for the wrist point plus $q_3 = \varphi - q_1 - q_2$; the dynamics is again
# $M(q)\,\ddot q + C(q, \dot q)\,\dot q + g(q) = \tau$, now 3 x 3, with two motor masses riding
# on the links.

# %%
import numpy as np
from _notebooks import energy_change, evaluate, joints, motor_work, namespace
from IPython.display import display

import planar_sym as ps

arm = ps.load("serial_3dof")
display(arm)

# %% [markdown]
# ## The equations
#
# The wrist link appears in every row of $M$: moving the elbow also swings the tool.

# %%
ps.equations("serial_3dof")

# %% [markdown]
# ## S4: the tool along a line at a fixed orientation
#
# The tool point moves 200 mm in $-x$ in 5 s, keeping $\varphi = \pi/2$. The wrist makes up for
# the arm: $q_1 + q_2 + q_3 = \pi/2$ all along.

# %%
move = ps.run_study("serial_3dof_cartesian_move")
q = joints(arm, move)
for key, value in move.peak_torques().items():
    print(f"{move.name}: peak |{key}| = {value:.12g} N*m")
print(f"{move.name}: max |q1 + q2 + q3 - pi/2| = "
      f"{np.max(np.abs(q.sum(axis=1) - np.pi / 2)):.3g} rad")
display(move)

# %% [markdown]
# ## Check 1: the printed equations are the compiled ones
#
# The printed closed forms (lumped parameters, gravity terms, Euler-Lagrange equations),
# evaluated with numpy, against the torques of the compiled code.

# %%
ns = namespace(arm, q, joints(arm, move, "qd"), joints(arm, move, "qdd"))
evaluate(arm, "Lumped parameters", ns)
evaluate(arm, "Gravity terms", ns)
for key, tau in evaluate(arm, "Euler-Lagrange", ns).items():
    diff = np.max(np.abs(tau - move.columns[f"{key}_n_m"]))
    print(f"{move.name}: closed form vs compiled, max |{key} difference| = {diff:.3g} N*m")

# %% [markdown]
# ## Check 2: power balance
#
# With no friction, the motors' work $\int \tau^T \dot q\,dt$ is the change of $T + V$
# (here mostly potential energy: the arm is lowered and raised along the line).

# %%
print(f"{move.name}: motor work W = {motor_work(move):.12g} J, "
      f"energy change dE = {energy_change(arm, move):.12g} J")

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
# # Lecture 3: the 5-bar Type I closed chain
#
# Two two-link arms, driven at A and E, hold the end effector P between them at C. Cutting the
# loop at C leaves a tree of four coordinates $q = (A, B, E, D)$ whose Lagrangian is two serial
# arms'; the cut is closed again by two loop equations $\Phi(q) = 0$ (the two sides of C meet),
# and their reaction force $\lambda$ enters as
#
# $$M(q)\,\ddot q + C(q, \dot q)\,\dot q + g(q) = S^T \tau + \Phi_q^T \lambda ,$$
#
# $S$ picking the actuated joints A and E. Only two of the four coordinates are free: the
# passive B and D follow from $\Phi = 0$.

# %%
import numpy as np
from _notebooks import energy_change, evaluate, joints, motor_work, namespace
from IPython.display import display

import planar_sym as ps

robot = ps.load("five_bar_type1")
display(robot)

# %% [markdown]
# ## The equations
#
# The passive joints appear in $M$ and $g$ like any other; the loop-closure section at the end
# ties them to A and E.

# %%
ps.equations("five_bar_type1")

# %% [markdown]
# ## S5: P moved in x, then in y
#
# Each study solves the inverse kinematics of P, then torques and the cut force together. The
# reaction force at C is what the joint's bearing must carry.

# %%
results = [ps.run_study(name) for name in ("five_bar_type1_move_x", "five_bar_type1_move_y")]
for result in results:
    for key, value in result.peak_torques().items():
        print(f"{result.name}: peak |{key}| = {value:.12g} N*m")
    force = np.hypot(result.columns["fx_C_n"], result.columns["fy_C_n"])
    print(f"{result.name}: peak |force at cut joint C| = {force.max():.6g} N")
display(results[0])

# %%
display(results[1])

# %% [markdown]
# ## Check 1: the motion closes the loop
#
# The printed loop equations $\Phi_1, \Phi_2$ (m), evaluated with numpy at every sample of the
# move: both sides of C meet to rounding error.

# %%
for result in results:
    ns = namespace(robot, joints(robot, result))
    phi = evaluate(robot, "Loop closure", ns)
    print(f"{result.name}: max |Phi| = {max(np.max(np.abs(v)) for v in phi.values()):.3g} m")

# %% [markdown]
# ## Check 2: the loop forces do no work
#
# $\Phi_q \dot q = 0$ along any motion that keeps the loop closed, so the power of the cut force,
# $\lambda^T \Phi_q \dot q$, is zero: only the two motors' power $\tau_A \dot q_A + \tau_E
# \dot q_E$ changes the energy. Integrated over the move it must equal $\Delta(T + V)$ from the
# compiled energy function.

# %%
for result in results:
    print(f"{result.name}: motor work W = {motor_work(result):.12g} J, "
          f"energy change dE = {energy_change(robot, result):.12g} J")

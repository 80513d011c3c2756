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
# # Lecture 5: the 3-RRR parallel robot
#
# Three two-link legs, each driven at its base (A1, A2, A3), hold a triangular platform. The
# spanning tree keeps leg 1 and the platform as one serial chain and cuts legs 2 and 3 where
# they meet the platform (B2, B3): seven coordinates, four loop equations $\Phi(q) = 0$, so
# $7 - 4 = 3$ degrees of freedom, the platform's $(x, y, \varphi)$. As for the 5-bar,
#
# $$M(q)\,\ddot q + C(q, \dot q)\,\dot q + g(q) = S^T \tau + \Phi_q^T \lambda .$$

# %%
import numpy as np
from _notebooks import energy_change, evaluate, joints, motor_work, namespace
from IPython.display import display

import planar_sym as ps

robot = ps.load("parallel_3rrr")
display(robot)

# %% [markdown]
# ## The equations
#
# Leg 1 carries the platform in the tree, so the platform's inertia sits in leg 1's entries of
# $M$; legs 2 and 3 are plain two-link arms, joined to the platform only through $\Phi = 0$.

# %%
ps.equations("parallel_3rrr")

# %% [markdown]
# ## S7: the platform moved in x, then in y, at $\varphi = 0$

# %%
results = [ps.run_study(name) for name in ("parallel_3rrr_move_x", "parallel_3rrr_move_y")]
for result in results:
    for key, value in result.peak_torques().items():
        print(f"{result.name}: peak |{key}| = {value:.12g} N*m")
    for cut in robot.loops:
        force = np.hypot(result.columns[f"fx_{cut}_n"], result.columns[f"fy_{cut}_n"])
        print(f"{result.name}: peak |force at cut joint {cut}| = {force.max():.6g} N")
display(results[0])

# %%
display(results[1])

# %% [markdown]
# ## Checks: loop closure and power balance
#
# The four printed loop equations vanish along the motion; the three motors' work equals the
# change of $T + V$, the cut forces doing none.

# %%
for result in results:
    phi = evaluate(robot, "Loop closure", namespace(robot, joints(robot, result)))
    print(f"{result.name}: max |Phi| = {max(np.max(np.abs(v)) for v in phi.values()):.3g} m")
    print(f"{result.name}: motor work W = {motor_work(result):.12g} J, "
          f"energy change dE = {energy_change(robot, result):.12g} J")

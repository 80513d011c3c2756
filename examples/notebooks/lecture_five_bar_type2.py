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
# # Lecture 4: the 5-bar Type II closed chain
#
# The same mechanism as Type I, two arms driven at A and E meeting at C, with other link
# lengths and the other assembly mode. The equations have the same form,
#
# $$M(q)\,\ddot q + C(q, \dot q)\,\dot q + g(q) = S^T \tau + \Phi_q^T \lambda , \qquad
# \Phi(q) = 0 ,$$
#
# only the parameter values differ: one derivation serves both robots.

# %%
import numpy as np
from _notebooks import energy_change, evaluate, joints, motor_work, namespace
from IPython.display import display

import planar_sym as ps

robot = ps.load("five_bar_type2")
display(robot)

# %%
ps.equations("five_bar_type2")

# %% [markdown]
# ## S6: P moved in x, then in y
#
# Torques at A and E and the reaction force at the cut joint.

# %%
results = [ps.run_study(name) for name in ("five_bar_type2_move_x", "five_bar_type2_move_y")]
for result in results:
    for key, value in result.peak_torques().items():
        print(f"{result.name}: peak |{key}| = {value:.12g} N*m")
    cut = robot.loops[0]
    force = np.hypot(result.columns[f"fx_{cut}_n"], result.columns[f"fy_{cut}_n"])
    print(f"{result.name}: peak |force at cut joint {cut}| = {force.max():.6g} N")
display(results[0])

# %%
display(results[1])

# %% [markdown]
# ## Checks: loop closure and power balance
#
# The printed $\Phi(q)$ vanishes along the motion, and the motors' work equals the change of
# $T + V$ (the loop force does no work on a closed loop).

# %%
for result in results:
    phi = evaluate(robot, "Loop closure", namespace(robot, joints(robot, result)))
    print(f"{result.name}: max |Phi| = {max(np.max(np.abs(v)) for v in phi.values()):.3g} m")
    print(f"{result.name}: motor work W = {motor_work(result):.12g} J, "
          f"energy change dE = {energy_change(robot, result):.12g} J")

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
# # Exploring the 5-bar Type I by hand
#
# `ps.explore(robot)` puts a slider on each actuated joint (A and E, in degrees), draws the
# mechanism at that pose and shows what the motors and the bearings carry there: the actuated
# torques (N*m) and every joint's load (force in N, couple in N*m). The passive joints B and D
# follow through the loop, continued from the pose shown, so the mechanism never flips into
# its other assembly mode; a pose the loop cannot reach says so in the view instead.
#
# The rates and accelerations of A and E are set in the boxes below the sliders (deg/s,
# deg/s^2). At 0, the default, the torques are the static ones: gravity only.
#
# (The widgets need ipywidgets: `pip install 'planar-sym[notebook]'`.)

# %%
import numpy as np
from IPython.display import display

import planar_sym as ps

robot = ps.load("five_bar_type1")
view = ps.explore(robot)
display(view)

# %% [markdown]
# ## The numbers behind the view
#
# The view is a thin layer over plain functions: `pose_report` computes a pose from the actuated
# joints (passive joints through the loop, from a previous pose), its torques and its joint
# loads; `ExploreState` remembers the pose shown and moves it, as the sliders do. The same
# numbers, printed:

# %%
from planar_sym.outputs.explore import ExploreState

state = ExploreState(robot)
act = list(robot.actuated)
q_drawn_act = state.q[act]
print(state.report.text(robot))
tau = state.report.tau
print(f"static torques at the drawn pose: tau A = {tau[0]:.12g} N*m, tau E = {tau[1]:.12g} N*m")

# %% [markdown]
# Turn A by 10 degrees and accelerate it at 200 deg/s^2 (E at rest): the torque of A grows by
# what the links' inertia asks for, and the passive joints have moved with the loop.

# %%
state.set_rates(qd=[0.0, 0.0], qdd=np.radians([200.0, 0.0]))
report = state.move_actuated(q_drawn_act + np.radians([10.0, 0.0]))
print(f"moved: A = {np.degrees(report.q[0]):.6f} deg, B = {np.degrees(report.q[1]):.6f} deg, "
      f"E = {np.degrees(report.q[2]):.6f} deg, D = {np.degrees(report.q[3]):.6f} deg")
print(f"accelerated torques: tau A = {report.tau[0]:.12g} N*m, "
      f"tau E = {report.tau[1]:.12g} N*m")
print(f"loop residual: {report.loop_residual_m:.3g} m")

# %% [markdown]
# Too far, and the loop cannot close: the report says so and keeps the last pose reached.

# %%
far = state.move_actuated(report.q[act] + np.radians([170.0, 0.0]))
print(f"reached: {far.reached}")
print(far.message.split(" (Details")[0])

# %% [markdown]
# ## Moving the end effector instead
#
# With `task=True` the sliders move the task point P (x, y in mm); the joints follow by inverse
# kinematics from the pose shown, keeping its working mode.

# %%
display(ps.explore(robot, task=True))

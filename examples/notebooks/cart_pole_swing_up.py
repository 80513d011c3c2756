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
# # Swinging up a cart-pole, then balancing it
#
# The cart-pole of PyDy's n-link pendulum benchmark (n = 1): a cart of 0.01 kg on a level rail,
# pushed by a force $F$ (the only motor), and a 1 m massless rod with a 0.01 kg bob, free to
# turn on the cart. $q_1$ is the cart's position (m), $q_2$ the rod's angle from $+x$: the pole
# hangs at $q_2 = -\pi/2$ and stands up at $q_2 = \pi/2$.
#
# Three steps, each a function of planar-sym:
#
# 1. **Balance** near the top: linearise there, $\dot x = A x + B u$, and design an LQR gain.
# 2. **Plan** the swing-up: the least-effort move from hanging to upright in 2 s with
#    $|F| \le 0.2$ N, by direct collocation (CasADi and IPOPT on the generated equations).
# 3. **Track** the plan with a time-varying LQR (the gains along the plan, from the Riccati
#    differential equation), which hands over to the balancing LQR at the top: one run.

# %%
import numpy as np
from IPython.display import display

import planar_sym as ps

robot = ps.load("cart_pole")
display(robot)
print(ps.equations("cart_pole").text)

# %% [markdown]
# ## 1. Balance: the linearisation at the top and an LQR gain
#
# At the top ($q_2 = \pi/2$, at rest) the mass matrix is $\begin{pmatrix} m_c + m & -m l \\
# -m l & m l^2 \end{pmatrix}$ and gravity pushes the bob away with stiffness $m g l$: with
# $m_c = m$ and $l = 1$ m, $\ddot q_1 = g\, \delta q_2 + F / m_c$ and
# $\ddot q_2 = 2 g\, \delta q_2 + F / (m_c l)$.

# %%
UP = np.pi / 2
lin = ps.linearize(robot, [0.0, UP])
print("A =\n", np.round(lin.a, 6))
print("B =\n", np.round(lin.b, 6))
hold = ps.lqr(robot, [0.0, UP], q_weight=[100.0, 100.0, 1.0, 1.0], r_weight=1.0)
print("LQR gain K =", np.round(hold.gain, 6).tolist())
print("closed-loop poles:", ", ".join(f"{p:.6g}" for p in sorted(hold.poles, key=abs)))

# %% [markdown]
# ## 2. Plan the swing-up
#
# Least effort $\int F^2 dt$ over 2 s, rest to rest, $|F| \le 0.2$ N, on 100 intervals. The
# pole is passive: at every interval its torque is held at zero on average.

# %%
plan = ps.optimal_move(robot, [0.0, -UP], [0.0, UP], objective="effort", duration_s=2.0,
                       torque_limit=[0.2], intervals=100)
print(f"swing-up: T = {plan.duration_s:g} s, peak |F| = {np.abs(plan.tau).max():.6g} N, "
      f"effort = {plan.objective:.9g} N^2*s, IPOPT {plan.solver['iterations']} iterations")
x = plan.trajectory.q[:, 0]
print(f"the cart travels from {x.min():.3f} m to {x.max():.3f} m")

# %% [markdown]
# Played open loop, the planned force alone does not get the pole up: the plan is exact only
# to its grid, and the top is unstable.

# %%
from planar_sym.control import controller, from_table, simulate_controlled

t = np.linspace(0.0, 5.0, 501)
feed = from_table(plan.trajectory.t_s, plan.tau, "linear").hold_until(5.0)
alone = simulate_controlled(robot, controller("none"), (0.0, 5.0), q0=[0.0, -UP], qd0=[0, 0],
                            torque=feed, t_eval=t)
print(f"open loop: the pole ends {np.degrees(alone.q[-1, 1] - UP):.1f} deg from upright")

# %% [markdown]
# ## 3. Track it, then balance: a time-varying LQR
#
# Along the plan the robot is linearised at every sample and the Riccati equation is
# integrated backwards from the top's LQR solution: $K(t)$ feeds back the state's error from
# the plan, and after 2 s it is the balancing gain. The plant's bob is 10 % heavier than the
# plan's.

# %%
design = ps.tvlqr(robot, plan.trajectory, plan.tau, q_weight=[100.0, 100.0, 1.0, 1.0],
                  r_weight=1.0)
plant = robot.with_parameters(m_pole=0.011)
run = simulate_controlled(robot, design.controller(saturate=False), (0.0, 5.0), plant=plant,
                          q0=[0.0, -UP], qd0=[0.0, 0.0], t_eval=t)
ref = design.controller().schedule(t)[:, :2]
along = t <= 2.0
print(f"largest departure from the plan: {np.abs(run.q[along, 0] - ref[along, 0]).max():.3g} m,"
      f" {np.abs(run.q[along, 1] - ref[along, 1]).max():.3g} rad")
print(f"end: |q - q_up| = {np.abs(run.q[-1] - [0.0, UP]).max():.3g}, peak |F| = "
      f"{np.abs(run.tau).max():.4g} N")

# %%
import matplotlib.pyplot as plt

fig, ax = plt.subplots(3, 1, sharex=True, figsize=(7, 6), layout="constrained")
ax[0].plot(t, run.q[:, 0], label="cart")
ax[0].plot(t, ref[:, 0], "--", label="plan")
ax[0].set_ylabel("q1 (m)")
ax[1].plot(t, np.degrees(run.q[:, 1]), label="pole")
ax[1].plot(t, np.degrees(ref[:, 1]), "--", label="plan")
ax[1].set_ylabel("q2 (deg)")
ax[2].plot(t, run.tau[:, 0])
ax[2].set_ylabel("F (N)")
ax[2].set_xlabel("time t (s)")
for a in ax[:2]:
    a.legend()
plt.show()

# %% [markdown]
# The same run is the built-in study `cart_pole_swing_up` (`planar-sym run cart_pole_swing_up`
# writes its CSV, plot and animation):

# %%
result = ps.run_study("cart_pole_swing_up")
print(result.timing)
display(result)

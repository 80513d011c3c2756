/* _integrate: adaptive Dormand-Prince 5(4) in C over the compiled forward dynamics, with the
 * controller, the input tables and the event functions in the same loop.
 *
 * SciPy's integrators spend ~20 us of Python per step around a ~50 ns right-hand side; here
 * the whole integration is one C call. Error control as in Hairer, Norsett & Wanner (scaled
 * RMS norm, atol + rtol |y|), FSAL, steps shortened to land exactly on every output time, so
 * outputs carry the full 5th order. Right-hand sides:
 *
 *   tree:   y = [q, qd], qdd = forward_dynamics(q, qd, tau)      (generated batch function)
 *   closed: qdd from [[M, -Phi_q^T], [Phi_q, 0]] [qdd; lambda] = [S^T tau - h; gamma],
 *           M, h, Phi_q, gamma from the generated constrained_terms batch function.
 *
 * Without a Control the torques are constant over the call. With one (planar_sym_dopri5_ctl),
 * tau(t, q, qd) is an input table plus a controller built from the generated functions with
 * the controller's own (nominal) parameters, clipped at the actuator limits:
 *
 *   PD + gravity:     tau = Kp (q_r - q) + Kd (qd_r - qd) + g(q)
 *   computed torque:  tau = ID(q, qd, qdd_r + Kd (qd_r - qd) + Kp (q_r - q))
 *
 * (closed chains: on the actuated joints, g and ID the closed-chain ones, the passive
 * accelerations completed through Phi_q qdd = gamma). The state then carries two more
 * components, the actuator work W = int tau . qd dt and the friction loss int D(qd) . qd dt,
 * so the energy balance is checked to the integrator's accuracy. Events g_k(t, y) > 0 (joint
 * limits, actuator torque and speed limits) are located within a step on the 4th-order dense
 * output by bisection, logged, and stop the run where asked.
 */
#ifdef PLANAR_SYM_EXTENSION /* built at install by setup.py: Python.h first, as it asks */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#endif
#include <math.h>
#include <string.h>

#define MAXN 32            /* coordinates */
#define MAXK (2 * MAXN)    /* KKT size */
#define MAXD (2 * MAXN + 2)

typedef int (*fd_fn)(long long, const double *, const double *, const double *, const double *,
                     double *);
typedef int (*terms_fn)(long long, const double *, const double *, const double *, double *,
                        double *, double *, double *);
typedef int (*grav_fn)(long long, const double *, const double *, double *);
typedef int (*id_fn)(long long, const double *, const double *, const double *, const double *,
                     double *);
typedef int (*cid_fn)(long long, const double *, const double *, const double *, const double *,
                      double *, double *, double *, double *, double *, double *);
typedef int (*jac_fn)(long long, const double *, const double *, double *);
typedef int (*bias_fn)(long long, const double *, const double *, const double *, double *);
/* the fused controller and plant (derive/tracking.py): q, qd, q_ref, qd_ref[, qdd_ref], kp, kd,
 * tau_in, lo, hi, p, p_nom -> qdd, tau_cmd, tau_app */
typedef int (*pd_fn)(long long, const double *, const double *, const double *, const double *,
                     const double *, const double *, const double *, const double *,
                     const double *, const double *, const double *, double *, double *,
                     double *);
typedef int (*ct_fn)(long long, const double *, const double *, const double *, const double *,
                     const double *, const double *, const double *, const double *,
                     const double *, const double *, const double *, const double *, double *,
                     double *, double *);

/* A piecewise polynomial of n_ch channels: on [T[k], T[k+1]] channel c is
 * sum_j c[(k * n_ch + c) * (deg + 1) + j] (t - T[k])^j. Before T[0] or after T[n-1] the end
 * segments extend (the caller checks the span is covered). n_knots 0: no signal. */
typedef struct {
    int n_knots, n_ch, deg;
    const double *T, *c;
} Signal;

/* Mirrored by _CControl in planar_sym/dynamics/engine.py (ctypes); keep the two in step. */
typedef struct {
    int mode;                 /* 0 open loop, 1 PD + gravity, 2 computed torque, 3 LQR */
    int saturate;
    const double *kp, *kd;    /* n_act gains */
    const double *p_nom;      /* the controller's parameters (the plant's are System.p) */
    const double *tau_const;  /* n_act constant torques added, or 0 */
    const double *lo, *hi;    /* n_act joint-side torque bounds where saturate */
    const double *fv, *fc, *vs;  /* n: the plant's friction per coordinate (work integral) */
    void *gravity, *inverse, *closed_inverse, *jac, *bias;
    Signal ref, input;        /* n_act channels each */
    int n_ev;
    const int *ev_kind, *ev_index, *ev_stop;  /* kind 0 q >= v, 1 q <= v, 2 |tau| <= v, 3 |qd| <= v */
    const double *ev_value;
    int *armed;               /* n_ev; persists across calls (closed-chain segments) */
    int max_log, n_log;
    int *log_ev;
    double *log_t;
    int stopped;
    double t_stop;
    double *y_stop;           /* 2n + 2 */
    int hint_ref, hint_input;
    const double *gain;       /* mode 3: n_act x 2n, row-major */
    const double *x_ref;      /* mode 3: 2n, the state it holds */
    const double *u_ref;      /* mode 3: n_act, the torques that hold it there */
    Signal sched;             /* mode 3, time-varying (n_knots > 0): channels x_ref (2n),
                                 u_ref (n_act), gain (n_act x 2n), replacing the three above */
    double *sched_v;          /* its values at t (scratch, one per channel) */
    int hint_sched;
    void *tracking;           /* modes 1, 2 of a tree: the fused controller and plant, or 0 */
} Control;

typedef struct {
    int n, m, n_act;
    const int *act;       /* actuated coordinate indices */
    const double *tau;    /* without Control: tree n torques; closed n_act torques */
    const double *p;
    fd_fn fd;
    terms_fn terms;
    Control *ctl;
    double tau_cmd[MAXN], tau_app[MAXN];  /* of the last control() call */
    double q_ref[MAXN], qd_ref[MAXN];     /* its reference (modes 1 and 2) */
} System;

/* Gaussian elimination with partial pivoting; returns 1 if singular. */
static int solve(int k, double *a, double *b) {
    for (int c = 0; c < k; ++c) {
        int piv = c;
        for (int r = c + 1; r < k; ++r)
            if (fabs(a[r * k + c]) > fabs(a[piv * k + c])) piv = r;
        if (a[piv * k + c] == 0.0) return 1;
        if (piv != c) {
            for (int j = 0; j < k; ++j) { double t = a[c * k + j]; a[c * k + j] = a[piv * k + j]; a[piv * k + j] = t; }
            double t = b[c]; b[c] = b[piv]; b[piv] = t;
        }
        for (int r = c + 1; r < k; ++r) {
            double f = a[r * k + c] / a[c * k + c];
            if (f == 0.0) continue;
            for (int j = c; j < k; ++j) a[r * k + j] -= f * a[c * k + j];
            b[r] -= f * b[c];
        }
    }
    for (int r = k - 1; r >= 0; --r) {
        double s = b[r];
        for (int j = r + 1; j < k; ++j) s -= a[r * k + j] * b[j];
        b[r] = s / a[r * k + r];
    }
    return 0;
}

/* value, first and second derivative of every channel at t */
static void signal_eval(const Signal *s, double t, int *hint, double *v, double *d1, double *d2) {
    int nseg = s->n_knots - 1, k = *hint;
    if (k < 0 || k >= nseg) k = 0;
    if (!(s->T[k] <= t && (t < s->T[k + 1] || k == nseg - 1))) {
        if (k + 1 < nseg && s->T[k + 1] <= t && (t < s->T[k + 2] || k + 1 == nseg - 1)) ++k;
        else {  /* binary search: the last k with T[k] <= t, clamped to a segment */
            int lo = 0, hi = nseg - 1;
            while (lo < hi) { int mid = (lo + hi + 1) / 2; if (s->T[mid] <= t) lo = mid; else hi = mid - 1; }
            k = lo;
        }
    }
    *hint = k;
    double x = t - s->T[k];
    int dp = s->deg + 1;
    for (int c = 0; c < s->n_ch; ++c) {
        /* one Horner pass for the value and both derivatives (p2 is half the second): it
         * runs at every right-hand side of a tracking run */
        const double *a = s->c + ((long long)k * s->n_ch + c) * dp;
        double p0 = a[s->deg], p1 = 0, p2 = 0;
        for (int j = s->deg - 1; j >= 0; --j) {
            p2 = p2 * x + p1;
            p1 = p1 * x + p0;
            p0 = p0 * x + a[j];
        }
        v[c] = p0;
        if (d1) d1[c] = p1;
        if (d2) d2[c] = 2.0 * p2;
    }
}

/* The commanded torques (sys->tau_cmd) and the applied ones, clipped (sys->tau_app). */
/* The input torques at t (n_act): the constant ones plus the input table's. */
static void input_torques(Control *c, int na, double t, double *out) {
    for (int a = 0; a < na; ++a) out[a] = c->tau_const ? c->tau_const[a] : 0.0;
    if (c->input.n_knots) {
        double u[MAXN];
        signal_eval(&c->input, t, &c->hint_input, u, 0, 0);
        for (int a = 0; a < na; ++a) out[a] += u[a];
    }
}

static int control(System *sys, double t, const double *y) {
    Control *c = sys->ctl;
    int n = sys->n, na = sys->n_act, m = sys->m;
    const double *q = y, *qd = y + n;
    double *qr = sys->q_ref, *qdr = sys->qd_ref, qddr[MAXN];
    double *tc = sys->tau_cmd;
    input_torques(c, na, t, tc);
    if (c->mode == 1 || c->mode == 2) signal_eval(&c->ref, t, &c->hint_ref, qr, qdr, qddr);
    if (c->mode == 1) {  /* PD + gravity compensation */
        for (int a = 0; a < na; ++a) {
            int i = sys->act[a];
            tc[a] += c->kp[a] * (qr[a] - q[i]) + c->kd[a] * (qdr[a] - qd[i]);
        }
        if (m == 0) {
            double g[MAXN];
            if (((grav_fn)c->gravity)(1, q, c->p_nom, g)) return 1;
            for (int a = 0; a < na; ++a) tc[a] += g[sys->act[a]];
        } else {
            double z[MAXN] = {0}, tau[MAXN], lam[MAXK], cond, phi[MAXK], phv[MAXK], pha[MAXK];
            if (((cid_fn)c->closed_inverse)(1, q, z, z, c->p_nom, tau, lam, &cond, phi, phv, pha))
                return 1;
            for (int a = 0; a < na; ++a) tc[a] += tau[a];
        }
    } else if (c->mode == 2) {  /* computed torque */
        double qdd[MAXN] = {0}, v[MAXN];
        for (int a = 0; a < na; ++a) {
            int i = sys->act[a];
            v[a] = qddr[a] + c->kd[a] * (qdr[a] - qd[i]) + c->kp[a] * (qr[a] - q[i]);
            qdd[i] = v[a];
        }
        if (m == 0) {
            double tau[MAXN];
            if (((id_fn)c->inverse)(1, q, qd, qdd, c->p_nom, tau)) return 1;
            for (int a = 0; a < na; ++a) tc[a] += tau[sys->act[a]];
        } else {
            /* passive accelerations from Phi_p qdd_p = gamma - Phi_a v (the nominal loops) */
            double J[MAXN * MAXK], gam[MAXK], A[MAXK * MAXK], b[MAXK];
            int pas[MAXN], np = 0, isact[MAXN] = {0};
            if (((jac_fn)c->jac)(1, q, c->p_nom, J)) return 1;
            if (((bias_fn)c->bias)(1, q, qd, c->p_nom, gam)) return 1;
            for (int a = 0; a < na; ++a) isact[sys->act[a]] = 1;
            for (int i = 0; i < n; ++i) if (!isact[i]) pas[np++] = i;
            if (np != m) return 3;
            for (int r = 0; r < m; ++r) {
                b[r] = gam[r];
                for (int a = 0; a < na; ++a) b[r] -= J[sys->act[a] * m + r] * v[a];
                for (int j = 0; j < np; ++j) A[r * m + j] = J[pas[j] * m + r];
            }
            if (solve(m, A, b)) return 2;
            for (int j = 0; j < np; ++j) qdd[pas[j]] = b[j];
            double tau[MAXN], lam[MAXK], cond, phi[MAXK], phv[MAXK], pha[MAXK];
            if (((cid_fn)c->closed_inverse)(1, q, qd, qdd, c->p_nom, tau, lam, &cond, phi, phv, pha))
                return 1;
            for (int a = 0; a < na; ++a) tc[a] += tau[a];
        }
    }
    if (c->mode == 3) {  /* LQR: full-state feedback about x_ref (of time: a TVLQR) */
        const double *xr = c->x_ref, *ur = c->u_ref, *gain = c->gain;
        if (c->sched.n_knots) {
            signal_eval(&c->sched, t, &c->hint_sched, c->sched_v, 0, 0);
            xr = c->sched_v;
            ur = xr + 2 * n;
            gain = ur + na;
        }
        for (int a = 0; a < na; ++a) {
            const double *k = gain + (long long)a * 2 * n;
            double v = ur[a];
            for (int j = 0; j < n; ++j)
                v += k[j] * (xr[j] - q[j]) + k[n + j] * (xr[n + j] - qd[j]);
            tc[a] += v;
        }
    }
    for (int a = 0; a < na; ++a) {
        double v = tc[a];
        if (c->saturate) v = fmin(fmax(v, c->lo[a]), c->hi[a]);
        sys->tau_app[a] = v;
    }
    return 0;
}

/* Modes 1 and 2 of a tree in one generated call (derive/tracking.py): the controller's
 * torques and the plant's accelerations, sharing every sine; writes qdd to dy + n. */
static int tracked(System *sys, double t, const double *y, double *dy) {
    Control *c = sys->ctl;
    int n = sys->n, na = sys->n_act;
    double tin[MAXN], qddr[MAXN], lo[MAXN], hi[MAXN];
    input_torques(c, na, t, tin);
    for (int a = 0; a < na; ++a) {
        lo[a] = c->saturate ? c->lo[a] : -INFINITY;
        hi[a] = c->saturate ? c->hi[a] : INFINITY;
    }
    signal_eval(&c->ref, t, &c->hint_ref, sys->q_ref, sys->qd_ref, qddr);
    if (c->mode == 1)
        return ((pd_fn)c->tracking)(1, y, y + n, sys->q_ref, sys->qd_ref, c->kp, c->kd, tin, lo,
                                    hi, sys->p, c->p_nom, dy + n, sys->tau_cmd, sys->tau_app);
    return ((ct_fn)c->tracking)(1, y, y + n, sys->q_ref, sys->qd_ref, qddr, c->kp, c->kd, tin,
                                lo, hi, sys->p, c->p_nom, dy + n, sys->tau_cmd, sys->tau_app);
}

static int rhs(System *sys, double t, const double *y, double *dy) {
    int n = sys->n, m = sys->m, k = n + m, na = sys->n_act;
    const double *tau_act = sys->tau;  /* n_act torques (closed) or n (tree) */
    double tau_full[MAXN];
    memcpy(dy, y + n, sizeof(double) * n);
    int fused = sys->ctl && sys->ctl->tracking && sys->fd;
    if (sys->ctl) {
        int rc = fused ? (tracked(sys, t, y, dy) ? 1 : 0) : control(sys, t, y);
        if (rc) return rc == 2 ? 2 : 1;
        tau_act = sys->tau_app;
        if (sys->fd && !fused) {  /* (the fused call has its accelerations already) */
            for (int i = 0; i < n; ++i) tau_full[i] = 0.0;
            for (int a = 0; a < na; ++a) tau_full[sys->act[a]] = sys->tau_app[a];
            tau_act = tau_full;
        }
        /* the work integrals: actuators in, friction out */
        const Control *c = sys->ctl;
        double w = 0.0, f = 0.0;
        for (int a = 0; a < na; ++a) w += sys->tau_app[a] * y[n + sys->act[a]];
        for (int i = 0; i < n; ++i) {
            double v = y[n + i];
            if (c->fv[i] != 0.0 || c->fc[i] != 0.0) f += (c->fv[i] * v + c->fc[i] * tanh(v / c->vs[i])) * v;
        }
        dy[2 * n] = w;
        dy[2 * n + 1] = f;
        if (fused) return 0;
    }
    if (sys->fd) return sys->fd(1, y, y + n, tau_act, sys->p, dy + n);
    double M[MAXN * MAXN], h[MAXN], J[MAXN * MAXN], g[MAXN], A[MAXK * MAXK], b[MAXK];
    if (sys->terms(1, y, y + n, sys->p, M, h, J, g)) return 1;
    /* CasADi matrices are column-major: M[j*n + i] = M(i, j); J is (m x n): J[j*m + i] */
    for (int i = 0; i < k * k; ++i) A[i] = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) A[i * k + j] = M[j * n + i];
    for (int r = 0; r < m; ++r)
        for (int j = 0; j < n; ++j) {
            A[(n + r) * k + j] = J[j * m + r];
            A[j * k + n + r] = -J[j * m + r];
        }
    for (int i = 0; i < n; ++i) b[i] = -h[i];
    for (int a = 0; a < na; ++a) b[sys->act[a]] += tau_act[a];
    for (int r = 0; r < m; ++r) b[n + r] = g[r];
    if (solve(k, A, b)) return 2;
    memcpy(dy + n, b, sizeof(double) * n);
    return 0;
}

/* event k at a state whose control() has just been evaluated */
static double event_value(const System *sys, int k, const double *y) {
    const Control *c = sys->ctl;
    int i = c->ev_index[k];
    double v = c->ev_value[k];
    switch (c->ev_kind[k]) {
    case 0: return y[i] - v;
    case 1: return v - y[i];
    case 2: return v - fabs(sys->tau_cmd[i]);
    default: return v - fabs(y[sys->n + i]);
    }
}

static double err_norm(int d, const double *y, const double *yn, const double *e, double rtol,
                       double atol) {
    double s = 0.0;
    for (int i = 0; i < d; ++i) {
        double sc = atol + rtol * fmax(fabs(y[i]), fabs(yn[i]));
        s += (e[i] / sc) * (e[i] / sc);
    }
    return sqrt(s / d);
}

/* Hairer's dense output of DOPRI5 (dopri5.f, CONTD5): y(t + theta h) from one step */
static void dense(int d, double theta, const double *y0, const double *y1, double h,
                  const double *k1, const double *k3, const double *k4, const double *k5,
                  const double *k6, const double *k7, double *out) {
    static const double d1 = -12715105075.0 / 11282082432.0, d3 = 87487479700.0 / 32700410799.0,
        d4 = -10690763975.0 / 1880347072.0, d5 = 701980252875.0 / 199316789632.0,
        d6 = -1453857185.0 / 822651844.0, d7 = 69997945.0 / 29380423.0;
    double th1 = 1.0 - theta;
    for (int i = 0; i < d; ++i) {
        double r2 = y1[i] - y0[i], r3 = h * k1[i] - r2, r4 = r2 - h * k7[i] - r3;
        double r5 = h * (d1 * k1[i] + d3 * k3[i] + d4 * k4[i] + d5 * k5[i] + d6 * k6[i] + d7 * k7[i]);
        out[i] = y0[i] + theta * (r2 + th1 * (r3 + theta * (r4 + th1 * r5)));
    }
}

/* Evaluate the controller and the events at n samples (t, y), y rows of 2n: commanded and
 * applied torques (n x n_act each), event values (n x n_ev) and, for a tracking law (modes 1
 * and 2), the reference and its rate (n x n_act each). Returns 0, or 1 + the sample the
 * controller failed on. */
int planar_sym_control_eval(int n, int m, int n_act, const int *act, const double *p,
                            Control *ctl, long long ns, const double *t, const double *y,
                            double *tau_cmd, double *tau_app, double *ev, double *q_ref,
                            double *qd_ref) {
    System sys = {n, m, n_act, act, 0, p, 0, 0, ctl};
    int tracks = ctl->mode == 1 || ctl->mode == 2;
    for (long long s = 0; s < ns; ++s) {
        const double *ys = y + s * 2 * n;
        if (control(&sys, t[s], ys)) return (int)(s + 1);
        memcpy(tau_cmd + s * n_act, sys.tau_cmd, sizeof(double) * n_act);
        memcpy(tau_app + s * n_act, sys.tau_app, sizeof(double) * n_act);
        if (tracks) {
            memcpy(q_ref + s * n_act, sys.q_ref, sizeof(double) * n_act);
            memcpy(qd_ref + s * n_act, sys.qd_ref, sizeof(double) * n_act);
        }
        for (int k = 0; k < ctl->n_ev; ++k) ev[s * ctl->n_ev + k] = event_value(&sys, k, ys);
    }
    return 0;
}

/* Returns 0 on success; 1 RHS failed, 2 step size underflow or singular matrix, 3 too many
 * steps, 4 too large. stats: [rhs evaluations, accepted steps, rejected steps, outputs
 * written]; *t_fail: where it stopped. With a Control the state has 2n + 2 components. */
int planar_sym_dopri5_ctl(int kind, int n, int m, int n_act, const int *act, const double *tau,
                          const double *p, void *fn, Control *ctl, double t0, const double *y0,
                          int n_out, const double *t_out, double rtol, double atol,
                          long long max_steps, double *y_out, long long *stats, double *t_fail) {
    static const double c2 = 1. / 5, c3 = 3. / 10, c4 = 4. / 5, c5 = 8. / 9;
    static const double a21 = 1. / 5, a31 = 3. / 40, a32 = 9. / 40, a41 = 44. / 45,
        a42 = -56. / 15, a43 = 32. / 9, a51 = 19372. / 6561, a52 = -25360. / 2187,
        a53 = 64448. / 6561, a54 = -212. / 729, a61 = 9017. / 3168, a62 = -355. / 33,
        a63 = 46732. / 5247, a64 = 49. / 176, a65 = -5103. / 18656, a71 = 35. / 384,
        a73 = 500. / 1113, a74 = 125. / 192, a75 = -2187. / 6784, a76 = 11. / 84;
    static const double e1 = 71. / 57600, e3 = -71. / 16695, e4 = 71. / 1920,
        e5 = -17253. / 339200, e6 = 22. / 525, e7 = -1. / 40;
    System sys = {n, m, n_act, act, tau, p, kind == 0 ? (fd_fn)fn : 0,
                  kind == 1 ? (terms_fn)fn : 0, ctl};
    int d = 2 * n + (ctl ? 2 : 0);
    double y[MAXD], yn[MAXD], yt[MAXD], er[MAXD];
    double k1[MAXD], k2[MAXD], k3[MAXD], k4[MAXD], k5[MAXD], k6[MAXD], k7[MAXD];
    double gv[64];
    if (n > MAXN || n + m > MAXK || (ctl && ctl->n_ev > 64)) return 4;
    stats[0] = stats[1] = stats[2] = stats[3] = 0;
    memcpy(y, y0, sizeof(double) * d);
    double t = t0;
    *t_fail = t;
    int rc = rhs(&sys, t, y, k1);
    if (rc) return rc;
    stats[0]++;
    /* initial step (Hairer's heuristic, simplified): a small fraction of y / y' */
    double d0 = 0, d1 = 0;
    for (int i = 0; i < d; ++i) {
        double sc = atol + rtol * fabs(y[i]);
        d0 += (y[i] / sc) * (y[i] / sc);
        d1 += (k1[i] / sc) * (k1[i] / sc);
    }
    double span = t_out[n_out - 1] - t0;
    double hh = (d0 < 1e-10 || d1 < 1e-10) ? 1e-6 : 0.01 * sqrt(d0 / d1);
    hh = fmin(hh, span);
    int o = 0;
    while (o < n_out && t_out[o] <= t0) { memcpy(y_out + (long long)o * d, y, sizeof(double) * d); ++o; }
    while (o < n_out) {
        if (stats[1] + stats[2] >= max_steps) { *t_fail = t; stats[3] = o; return 3; }
        double target = t_out[o];
        int lands = 0;
        double h = hh;
        if (t + h >= target) { h = target - t; lands = 1; }
        if (h <= 1e-14 * fmax(1.0, fabs(t))) { *t_fail = t; stats[3] = o; return 2; }
#define RHS(tt, yy, kk) do { int r_ = rhs(&sys, (tt), (yy), (kk)); if (r_) { *t_fail = t; stats[3] = o; return r_; } } while (0)
        for (int i = 0; i < d; ++i) yt[i] = y[i] + h * a21 * k1[i];
        RHS(t + c2 * h, yt, k2);
        for (int i = 0; i < d; ++i) yt[i] = y[i] + h * (a31 * k1[i] + a32 * k2[i]);
        RHS(t + c3 * h, yt, k3);
        for (int i = 0; i < d; ++i) yt[i] = y[i] + h * (a41 * k1[i] + a42 * k2[i] + a43 * k3[i]);
        RHS(t + c4 * h, yt, k4);
        for (int i = 0; i < d; ++i)
            yt[i] = y[i] + h * (a51 * k1[i] + a52 * k2[i] + a53 * k3[i] + a54 * k4[i]);
        RHS(t + c5 * h, yt, k5);
        for (int i = 0; i < d; ++i)
            yt[i] = y[i] + h * (a61 * k1[i] + a62 * k2[i] + a63 * k3[i] + a64 * k4[i] + a65 * k5[i]);
        RHS(t + h, yt, k6);
        for (int i = 0; i < d; ++i)
            yn[i] = y[i] + h * (a71 * k1[i] + a73 * k3[i] + a74 * k4[i] + a75 * k5[i] + a76 * k6[i]);
        double tn = lands ? target : t + h;
        RHS(tn, yn, k7);
        stats[0] += 6;
        for (int i = 0; i < d; ++i)
            er[i] = h * (e1 * k1[i] + e3 * k3[i] + e4 * k4[i] + e5 * k5[i] + e6 * k6[i] + e7 * k7[i]);
        double err = err_norm(d, y, yn, er, rtol, atol);
        double fac = err == 0.0 ? 5.0 : fmin(5.0, fmax(0.2, 0.9 * pow(err, -0.2)));
        if (err > 1.0) {
            stats[2]++;
            hh = h * fmax(0.2, 0.9 * pow(err, -0.2));
            continue;
        }
        stats[1]++;
        if (ctl && ctl->n_ev) {  /* control() last ran at (tn, yn): the events there */
            double first_stop = 2.0;
            for (int k = 0; k < ctl->n_ev; ++k) gv[k] = event_value(&sys, k, yn);
            for (int k = 0; k < ctl->n_ev; ++k) {
                if (!ctl->armed[k] || gv[k] > 0.0) continue;
                /* bisect on the dense output: g > 0 at theta = 0 (armed), <= 0 at 1 */
                double lo = 0.0, hi = 1.0, ys[MAXD];
                for (int it = 0; it < 60 && (hi - lo) * h > 1e-15 * fmax(1.0, fabs(t)); ++it) {
                    double mid = 0.5 * (lo + hi);
                    dense(d, mid, y, yn, h, k1, k3, k4, k5, k6, k7, ys);
                    if (ctl->ev_kind[k] == 2 && control(&sys, t + mid * h, ys)) break;
                    if (event_value(&sys, k, ys) > 0.0) lo = mid; else hi = mid;
                }
                ctl->armed[k] = 0;
                if (ctl->n_log < ctl->max_log) {
                    ctl->log_ev[ctl->n_log] = k;
                    ctl->log_t[ctl->n_log] = t + hi * h;
                    ctl->n_log++;
                }
                if (ctl->ev_stop[k] && hi < first_stop) first_stop = hi;
            }
            if (first_stop <= 1.0) {
                ctl->stopped = 1;
                ctl->t_stop = first_stop == 1.0 ? tn : t + first_stop * h;
                if (first_stop == 1.0) memcpy(ctl->y_stop, yn, sizeof(double) * d);
                else dense(d, first_stop, y, yn, h, k1, k3, k4, k5, k6, k7, ctl->y_stop);
                while (o < n_out && t_out[o] < ctl->t_stop) ++o;  /* (never: steps land on outputs) */
                *t_fail = ctl->t_stop;
                stats[3] = o;
                return 0;
            }
            /* re-arm the events whose function is positive again (after a "continue") */
            for (int k = 0; k < ctl->n_ev; ++k) if (!ctl->armed[k] && gv[k] > 0.0) ctl->armed[k] = 1;
        }
        t = tn;
        *t_fail = t;  /* the time reached, read by a progress thread while the loop runs */
        memcpy(y, yn, sizeof(double) * d);
        memcpy(k1, k7, sizeof(double) * d);  /* FSAL */
        while (o < n_out && t_out[o] <= t) { memcpy(y_out + (long long)o * d, y, sizeof(double) * d); ++o; }
        /* a step cut short to land on an output says nothing about the next one */
        hh = lands ? fmax(hh, h * fac) : h * fac;
    }
    *t_fail = t;
    stats[3] = o;
    return 0;
}

/* Without a controller: constant torques (zero or given). */
int planar_sym_dopri5(int kind, int n, int m, int n_act, const int *act, const double *tau,
                      const double *p, void *fn, double t0, const double *y0, int n_out,
                      const double *t_out, double rtol, double atol, long long max_steps,
                      double *y_out, long long *stats, double *t_fail) {
    long long st[4];
    int rc = planar_sym_dopri5_ctl(kind, n, m, n_act, act, tau, p, fn, 0, t0, y0, n_out, t_out,
                                   rtol, atol, max_steps, y_out, st, t_fail);
    stats[0] = st[0]; stats[1] = st[1]; stats[2] = st[2];
    return rc;
}

#ifdef PLANAR_SYM_EXTENSION
/* Installed as an (empty) extension module so that setuptools builds it with the package; the
 * runtime loads the file with ctypes, after comparing the source hash it was built from. */
const char *planar_sym_source_hash(void) { return PLANAR_SYM_SOURCE_HASH; }

static struct PyModuleDef planar_sym_module = {PyModuleDef_HEAD_INIT, "_integrate", NULL, -1, NULL};

PyMODINIT_FUNC PyInit__integrate(void) { return PyModule_Create(&planar_sym_module); }
#endif

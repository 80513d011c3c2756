/* _integrate: adaptive Dormand-Prince 5(4) in C over the compiled forward dynamics.
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
 * Torques are constant over the call (zero or given); time-varying torques use SciPy.
 */
#include <math.h>
#include <string.h>

#define MAXN 32            /* coordinates */
#define MAXK (2 * MAXN)    /* KKT size */

typedef int (*fd_fn)(long long, const double *, const double *, const double *, const double *,
                     double *);
typedef int (*terms_fn)(long long, const double *, const double *, const double *, double *,
                        double *, double *, double *);

typedef struct {
    int n, m, n_act;
    const int *act;       /* actuated coordinate indices (closed chains) */
    const double *tau;    /* tree: n torques; closed: n_act torques */
    const double *p;
    fd_fn fd;
    terms_fn terms;
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

static int rhs(const System *sys, const double *y, double *dy) {
    int n = sys->n, m = sys->m, k = n + m;
    memcpy(dy, y + n, sizeof(double) * n);
    if (sys->fd) return sys->fd(1, y, y + n, sys->tau, sys->p, dy + n);
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
    for (int a = 0; a < sys->n_act; ++a) b[sys->act[a]] += sys->tau[a];
    for (int r = 0; r < m; ++r) b[n + r] = g[r];
    if (solve(k, A, b)) return 2;
    memcpy(dy + n, b, sizeof(double) * n);
    return 0;
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

/* Returns 0 on success; 1 RHS failed, 2 step size underflow, 3 too many steps.
 * stats: [rhs evaluations, accepted steps, rejected steps]; *t_fail: where it stopped. */
int planar_sym_dopri5(int kind, int n, int m, int n_act, const int *act, const double *tau,
                      const double *p, void *fn, double t0, const double *y0, int n_out,
                      const double *t_out, double rtol, double atol, long long max_steps,
                      double *y_out, long long *stats, double *t_fail) {
    static const double c2 = 1. / 5, c3 = 3. / 10, c4 = 4. / 5, c5 = 8. / 9;
    static const double a21 = 1. / 5, a31 = 3. / 40, a32 = 9. / 40, a41 = 44. / 45,
        a42 = -56. / 15, a43 = 32. / 9, a51 = 19372. / 6561, a52 = -25360. / 2187,
        a53 = 64448. / 6561, a54 = -212. / 729, a61 = 9017. / 3168, a62 = -355. / 33,
        a63 = 46732. / 5247, a64 = 49. / 176, a65 = -5103. / 18656, a71 = 35. / 384,
        a73 = 500. / 1113, a74 = 125. / 192, a75 = -2187. / 6784, a76 = 11. / 84;
    static const double e1 = 71. / 57600, e3 = -71. / 16695, e4 = 71. / 1920,
        e5 = -17253. / 339200, e6 = 22. / 525, e7 = -1. / 40;
    System sys = {n, m, n_act, act, tau, p, kind == 0 ? (fd_fn)fn : 0,
                  kind == 1 ? (terms_fn)fn : 0};
    int d = 2 * n;
    double y[2 * MAXN], yn[2 * MAXN], yt[2 * MAXN], er[2 * MAXN];
    double k1[2 * MAXN], k2[2 * MAXN], k3[2 * MAXN], k4[2 * MAXN], k5[2 * MAXN],
        k6[2 * MAXN], k7[2 * MAXN];
    if (n > MAXN || n + m > MAXK) return 4;
    stats[0] = stats[1] = stats[2] = 0;
    memcpy(y, y0, sizeof(double) * d);
    double t = t0;
    *t_fail = t;
    if (rhs(&sys, y, k1)) return 1;
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
        if (stats[1] + stats[2] >= max_steps) { *t_fail = t; return 3; }
        double target = t_out[o];
        int lands = 0;
        double h = hh;
        if (t + h >= target) { h = target - t; lands = 1; }
        if (h <= 1e-14 * fmax(1.0, fabs(t))) { *t_fail = t; return 2; }
        for (int i = 0; i < d; ++i) yt[i] = y[i] + h * a21 * k1[i];
        if (rhs(&sys, yt, k2)) { *t_fail = t; return 1; }
        for (int i = 0; i < d; ++i) yt[i] = y[i] + h * (a31 * k1[i] + a32 * k2[i]);
        if (rhs(&sys, yt, k3)) { *t_fail = t; return 1; }
        for (int i = 0; i < d; ++i) yt[i] = y[i] + h * (a41 * k1[i] + a42 * k2[i] + a43 * k3[i]);
        if (rhs(&sys, yt, k4)) { *t_fail = t; return 1; }
        for (int i = 0; i < d; ++i)
            yt[i] = y[i] + h * (a51 * k1[i] + a52 * k2[i] + a53 * k3[i] + a54 * k4[i]);
        if (rhs(&sys, yt, k5)) { *t_fail = t; return 1; }
        for (int i = 0; i < d; ++i)
            yt[i] = y[i] + h * (a61 * k1[i] + a62 * k2[i] + a63 * k3[i] + a64 * k4[i] + a65 * k5[i]);
        if (rhs(&sys, yt, k6)) { *t_fail = t; return 1; }
        for (int i = 0; i < d; ++i)
            yn[i] = y[i] + h * (a71 * k1[i] + a73 * k3[i] + a74 * k4[i] + a75 * k5[i] + a76 * k6[i]);
        if (rhs(&sys, yn, k7)) { *t_fail = t; return 1; }
        stats[0] += 6;
        for (int i = 0; i < d; ++i)
            er[i] = h * (e1 * k1[i] + e3 * k3[i] + e4 * k4[i] + e5 * k5[i] + e6 * k6[i] + e7 * k7[i]);
        double err = err_norm(d, y, yn, er, rtol, atol);
        double fac = err == 0.0 ? 5.0 : fmin(5.0, fmax(0.2, 0.9 * pow(err, -0.2)));
        if (err <= 1.0) {
            stats[1]++;
            t = lands ? target : t + h;
            memcpy(y, yn, sizeof(double) * d);
            memcpy(k1, k7, sizeof(double) * d);  /* FSAL */
            while (o < n_out && t_out[o] <= t) { memcpy(y_out + (long long)o * d, y, sizeof(double) * d); ++o; }
            /* a step cut short to land on an output says nothing about the next one */
            hh = lands ? fmax(hh, h * fac) : h * fac;
        } else {
            stats[2]++;
            hh = h * fmax(0.2, 0.9 * pow(err, -0.2));
        }
    }
    *t_fail = t;
    return 0;
}

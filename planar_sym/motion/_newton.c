/* _newton: generic inverse kinematics, Newton continued sample to sample, in C.
 *
 * Solves F(q) = [Phi(q); x(q) - x*(t_k)] = 0 at every sample k with the robot's generated batch
 * functions called one sample at a time (n = 1) through function pointers:
 *
 *   task(n, q, qd, p, x, J, jdot_qd)      x (nt), J (nt x n, column-major)
 *   constraint(n, q, p, phi)              phi (m)            (closed chains only)
 *   constraint_jacobian(n, q, p, phi_q)   phi_q (m x n, column-major)
 *
 * or, where the robot was derived with it, all in one call that computes every sine once:
 *
 *   ik_terms(n, q, p, F, dF_dq)           F = [phi; x] (n), dF_dq = [phi_q; J] (n x n,
 *                                         column-major)
 *
 * The system is square (m + nt = n; checked by the caller) and solved by Gaussian elimination
 * with partial pivoting. Continuation keeps the working and assembly modes of the start pose:
 * sample 0 is reached from the start pose, sample k + 1 from sample k, each along the straight
 * line between the two targets in task space, as one step if Newton accepts it, else as
 * shorter steps (interval halving, then doubling again after each success). A step is refused
 * when a Newton correction exceeds dq_max (a branch change starts with a large correction),
 * the corrections stop contracting (|dq_i| > theta |dq_{i-1}|: outside Newton's quadratic
 * basin) or an iterate has det [Phi_q; J] of the other sign than the start pose (beyond a
 * singular pose), so coarse sampling cannot make Newton jump to another branch.
 *
 * Predictor: extrapolation in time of the last solutions (see predict).
 */
#ifdef PLANAR_SYM_EXTENSION /* built at install by setup.py: Python.h first, as it asks */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#endif
#include <math.h>
#include <string.h>

#define MAXN 32

typedef int (*task_fn)(long long, const double *, const double *, const double *, double *,
                       double *, double *);
typedef int (*phi_fn)(long long, const double *, const double *, double *);
typedef int (*terms_fn)(long long, const double *, const double *, double *, double *);

enum { OK = 0, NO_CONVERGENCE = 1, SINGULAR = 2, FUNCTION_FAILED = 3, TOO_LARGE = 4,
       CROSSED = 5 };

typedef struct {
    int n, m, nt;
    const double *p;
    task_fn task;
    phi_fn phi, phiq;
    terms_fn terms;  /* the fused call, or NULL: task, phi and phiq one by one */
    double tol, dq_max, theta, min_fraction, step_tol;
    int max_iter;
    int sign;  /* of det [Phi_q; J] at the start pose: the branch to stay on */
    long long iterations, evaluations, halvings;
    double residual; /* |F|_inf of the last evaluation */
} Problem;

/* Gaussian elimination with partial pivoting on the k x k row-major a (k <= MAXN); b becomes
 * the solution and *sign the sign of det a. Returns 1 on an exactly zero pivot. */
static inline __attribute__((always_inline)) int solve_k(const int k, double *a, double *b,
                                                           int *sign) {
    int s = 1;
    double inv[MAXN];  /* reciprocal pivots: multiplications in the back substitution */
    for (int c = 0; c < k; ++c) {
        int piv = c;
        double best = fabs(a[c * k + c]);
        for (int r = c + 1; r < k; ++r) {
            double v = fabs(a[r * k + c]);
            if (v > best) best = v, piv = r;
        }
        if (best == 0.0) return 1;
        if (piv != c) {  /* columns left of c are eliminated: only c.. move */
            s = -s;
            for (int j = c; j < k; ++j) { double t = a[c * k + j]; a[c * k + j] = a[piv * k + j]; a[piv * k + j] = t; }
            double t = b[c]; b[c] = b[piv]; b[piv] = t;
        }
        double d = a[c * k + c];
        inv[c] = 1.0 / d;
        if (d < 0.0) s = -s;
        for (int r = c + 1; r < k; ++r) {
            double f = a[r * k + c] * inv[c];
            for (int j = c + 1; j < k; ++j) a[r * k + j] -= f * a[c * k + j];
            b[r] -= f * b[c];
        }
    }
    for (int r = k - 1; r >= 0; --r) {
        double t = b[r];
        for (int j = r + 1; j < k; ++j) t -= a[r * k + j] * b[j];
        b[r] = t * inv[r];
    }
    *sign = s;
    return 0;
}

/* solve_k with k a constant for the common sizes: gcc then unrolls the loops completely
 * (measured 1.2-1.3x faster for the 3-RRR's 7 x 7 system, which is latency-bound at ~200 ns) */
static int solve(int k, double *a, double *b, int *sign) {
    switch (k) {
    case 2: return solve_k(2, a, b, sign);
    case 3: return solve_k(3, a, b, sign);
    case 4: return solve_k(4, a, b, sign);
    case 5: return solve_k(5, a, b, sign);
    case 6: return solve_k(6, a, b, sign);
    case 7: return solve_k(7, a, b, sign);
    case 8: return solve_k(8, a, b, sign);
    default: return solve_k(k, a, b, sign);
    }
}

static double norm_inf(int k, const double *v) {
    double s = 0.0;
    for (int i = 0; i < k; ++i) {
        double a = fabs(v[i]);
        if (a > s || a != a) s = a;  /* a NaN stays */
    }
    return s;
}

/* F = [phi; x - target], and J from the same call: J (nt x n, column-major) of the task, or
 * with the fused call the whole [phi_q; J] (n x n, column-major). */
static int residual(Problem *pr, const double *q, const double *target, double *F, double *J) {
    int m = pr->m, nt = pr->nt;
    double zero[MAXN] = {0}, x[MAXN], jd[MAXN];
    pr->evaluations++;
    if (pr->terms) {
        if (pr->terms(1, q, pr->p, F, J)) return FUNCTION_FAILED;
        for (int i = 0; i < nt; ++i) F[m + i] -= target[i];
        pr->residual = norm_inf(pr->n, F);
        return OK;
    }
    if (pr->task(1, q, zero, pr->p, x, J, jd)) return FUNCTION_FAILED;
    if (m && pr->phi(1, q, pr->p, F)) return FUNCTION_FAILED;
    for (int i = 0; i < nt; ++i) F[m + i] = x[i] - target[i];
    pr->residual = norm_inf(pr->n, F);
    return OK;
}

/* A = [phi_q; J] row-major. */
static int jacobian(Problem *pr, const double *q, const double *J, double *A) {
    int n = pr->n, m = pr->m, nt = pr->nt;
    double pq[MAXN * MAXN];
    if (pr->terms) {  /* J holds the whole [phi_q; J] already */
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) A[i * n + j] = J[j * n + i];
        return OK;
    }
    if (m && pr->phiq(1, q, pr->p, pq)) return FUNCTION_FAILED;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < n; ++j) A[i * n + j] = pq[j * m + i];  /* CasADi: column-major */
    for (int i = 0; i < nt; ++i)
        for (int j = 0; j < n; ++j) A[(m + i) * n + j] = J[j * nt + i];
    return OK;
}

/* Newton from q (in: predictor, out: solution) to F(q; target) = 0.
 *
 * Converged when the residual is below tol, or when a correction is below step_tol: Newton
 * converges quadratically, so the error left after a correction dq is about K |dq|^2 with
 * K = |A^-1| |A'| / 2 (~10 /rad at these robots' well-conditioned poses), far below rounding for
 * |dq| <= 1e-9 rad; this spares the evaluation that would only confirm it (the caller checks
 * every solution's residual afterwards, in one batch).
 *
 * Every evaluated iterate must keep the sign of det [Phi_q; J] of the start pose: the sign
 * changes only across a singular pose, where working or assembly modes meet (the 2-DOF arm's
 * det J = a1 a2 sin q2), and near one the two branches are closer than any step limit, so this
 * is what keeps Newton on its branch there. (A solution accepted on a small correction lies
 * within step_tol of an evaluated iterate: a singular pose that close has a condition number
 * far above COND_LIMIT, which the caller refuses.) */
static int newton(Problem *pr, double *q, const double *target) {
    int n = pr->n, sign;
    double F[MAXN], J[MAXN * MAXN], A[MAXN * MAXN], prev = INFINITY;
    /* the residual is converged at tol times the size of the target (m, rad): rounding in x(q)
     * grows with the coordinates' size */
    double tol = pr->tol * (1.0 + norm_inf(pr->nt, target));
    for (int it = 0; it <= pr->max_iter; ++it) {
        if (residual(pr, q, target, F, J) || jacobian(pr, q, J, A)) return FUNCTION_FAILED;
        for (int i = 0; i < n; ++i) F[i] = -F[i];
        if (solve(n, A, F, &sign)) return SINGULAR;
        if (sign != pr->sign) return CROSSED;
        if (pr->residual <= tol) return OK;
        if (it == pr->max_iter) break;
        pr->iterations++;
        double step = norm_inf(n, F);
        if (!(step <= pr->dq_max)) return NO_CONVERGENCE;  /* NaN too */
        /* not contracting: outside Newton's basin (a correction this small ends the loop) */
        if (step > pr->step_tol && step > pr->theta * prev) return NO_CONVERGENCE;
        prev = step;
        for (int i = 0; i < n; ++i) q[i] += F[i];
        if (step <= pr->step_tol) return OK;
    }
    return NO_CONVERGENCE;
}

/* From the solution q (in/out) of target xa to the target xb along the straight line between
 * them; pred is the predictor for the whole step. *reached: the fraction of the line solved. */
static int advance(Problem *pr, double *q, const double *pred, const double *xa,
                   const double *xb, double *reached) {
    int n = pr->n, nt = pr->nt;
    double q0[MAXN], qprev[MAXN], qt[MAXN], target[MAXN];
    double s = 0.0, sprev = 0.0, h = 1.0;
    int have_prev = 0, rc = OK;
    memcpy(q0, q, sizeof(double) * n);
    while (s < 1.0) {
        double sn = fmin(1.0, s + h);
        for (int i = 0; i < nt; ++i) target[i] = xa[i] + sn * (xb[i] - xa[i]);
        for (int i = 0; i < n; ++i)
            qt[i] = have_prev ? q[i] + (q[i] - qprev[i]) * (sn - s) / (s - sprev)
                              : q0[i] + sn * (pred[i] - q0[i]);
        rc = newton(pr, qt, target);
        if (rc == FUNCTION_FAILED) break;
        if (rc == OK) {
            memcpy(qprev, q, sizeof(double) * n);
            memcpy(q, qt, sizeof(double) * n);
            sprev = s;
            s = sn;
            have_prev = 1;
            h *= 2.0;
        } else {
            h *= 0.5;
            pr->halvings++;
            if (h < pr->min_fraction) break;
        }
    }
    *reached = s;
    return s >= 1.0 ? OK : rc;
}

/* Predictor for sample k from the solutions before it (q: sample k - 1; q_out: all of them):
 * the polynomial through the last three (or two) solutions in time, extrapolated to t[k]. Its
 * error is O(dt^3) instead of O(dt) for the last solution alone, which saves about one Newton
 * iteration per sample. Times that do not increase, or weights that would amplify rounding
 * (a very uneven grid), fall back to a lower order. */
static void predict(int n, long long k, const double *t, const double *q, const double *q_out,
                    double *pred) {
    double w0 = 1.0, w1 = 0.0, w2 = 0.0;  /* weights of q_k-1, q_k-2, q_k-3 */
    if (k >= 3 && t[k] >= t[k - 1] && t[k - 1] > t[k - 2] && t[k - 2] > t[k - 3]) {
        double a = t[k - 1], b = t[k - 2], c = t[k - 3], s = t[k];
        w0 = (s - b) * (s - c) / ((a - b) * (a - c));
        w1 = (s - a) * (s - c) / ((b - a) * (b - c));
        w2 = (s - a) * (s - b) / ((c - a) * (c - b));
        if (!(fabs(w0) + fabs(w1) + fabs(w2) <= 16.0)) w0 = 1.0, w1 = w2 = 0.0;
    }
    if (w0 == 1.0 && k >= 2 && t[k] >= t[k - 1] && t[k - 1] > t[k - 2]) {
        double r = (t[k] - t[k - 1]) / (t[k - 1] - t[k - 2]);
        if (r <= 4.0) w0 = 1.0 + r, w1 = -r;
    }
    for (int i = 0; i < n; ++i) {
        pred[i] = w0 * q[i];
        if (w1 != 0.0) pred[i] += w1 * q_out[(k - 2) * n + i];
        if (w2 != 0.0) pred[i] += w2 * q_out[(k - 3) * n + i];
    }
}

/* Solves every sample in order. Returns 0, or the failure code with *k_fail the sample (its row
 * of q_out then holds the closest pose found on the way to it).
 * opts: [tol, dq_max, theta, max_iter, min_fraction, step_tol].
 * info: [|F|_inf at the closest pose to the failing sample's target, fraction of the last
 *        step solved, Newton iterations, F evaluations, step halvings]. */
int planar_sym_ik_newton(int n, int m, int nt, const double *p, void *task, void *phi,
                         void *phiq, void *terms, long long N, const double *t, const double *x,
                         const double *q_start, const double *opts, double *q_out,
                         long long *k_fail, double *info) {
    Problem pr = {n, m, nt, p, (task_fn)task, (phi_fn)phi, (phi_fn)phiq, (terms_fn)terms,
                  opts[0], opts[1], opts[2], opts[4], opts[5], (int)opts[3], 1, 0, 0, 0, 0.0};
    double q[MAXN], pred[MAXN], F[MAXN], J[MAXN * MAXN], A[MAXN * MAXN], xs[MAXN];
    double reached = 1.0;
    int rc = OK;
    *k_fail = -1;
    memset(info, 0, 5 * sizeof(double));
    if (n > MAXN || m + nt != n || (m && !terms && (!phi || !phiq))) return TOO_LARGE;
    memcpy(q, q_start, sizeof(double) * n);
    /* the start pose's own task coordinates: sample 0 is reached from there */
    *k_fail = 0;
    if (residual(&pr, q, x, F, J) || jacobian(&pr, q, J, A)) return FUNCTION_FAILED;
    for (int i = 0; i < nt; ++i) xs[i] = F[m + i] + x[i];
    if (solve(n, A, F, &pr.sign)) return SINGULAR;
    *k_fail = -1;
    for (long long k = 0; k < N && rc == OK; ++k) {
        const double *xa = k ? x + (k - 1) * nt : xs, *xb = x + k * nt;
        predict(n, k, t, q, q_out, pred);
        rc = advance(&pr, q, pred, xa, xb, &reached);
        if (rc == OK) memcpy(q_out + k * n, q, sizeof(double) * n);
        else {
            *k_fail = k;
            memcpy(q_out + k * n, q, sizeof(double) * n);  /* the closest pose found */
            if (rc != FUNCTION_FAILED && residual(&pr, q, xb, F, J) == OK)
                info[0] = pr.residual;  /* ... against the full target */
        }
    }
    info[1] = reached;
    info[2] = (double)pr.iterations;
    info[3] = (double)pr.evaluations;
    info[4] = (double)pr.halvings;
    return rc;
}

#ifdef PLANAR_SYM_EXTENSION
/* Installed as an (empty) extension module so that setuptools builds it with the package; the
 * runtime loads the file with ctypes, after comparing the source hash it was built from. */
const char *planar_sym_source_hash(void) { return PLANAR_SYM_SOURCE_HASH; }

static struct PyModuleDef planar_sym_module = {PyModuleDef_HEAD_INIT, "_newton", NULL, -1, NULL};

PyMODINIT_FUNC PyInit__newton(void) { return PyModule_Create(&planar_sym_module); }
#endif

/* Inverse dynamics of the 2-DOF serial arm from the generated C alone, as a controller calls it:
 * no Python, no heap, fixed-size stack buffers.
 *
 *   make                                   # or: cc -O3 -std=c99 -I../../generated/serial_2dof \
 *                                          #       main.c ../../generated/serial_2dof/serial_2dof.c -lm
 *   ./serial_2dof_tau q1 q2 qd1 qd2 qdd1 qdd2      (rad, rad/s, rad/s^2)
 *
 * prints the torques tau1, tau2 (N*m), one per line, with %.17g (every digit of the double).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h> /* strtod */

#include "serial_2dof.h"

/* Exported by serial_2dof.c (CasADi's generated API) but not declared in serial_2dof.h. */
int serial_2dof_inverse_dynamics_work(casadi_int *sz_arg, casadi_int *sz_res, casadi_int *sz_iw,
                                      casadi_int *sz_w);
const casadi_int *serial_2dof_inverse_dynamics_sparsity_in(casadi_int i);

#define N_Q 2  /* joints: q[2] = joint1, joint2 (rad) */
#define N_P 11 /* parameters */

/* The parameter vector p in SI units, in the generated order: copied from
 * generated/serial_2dof/manifest.json ("parameters"); tests/test_standalone_c.py checks that it
 * still matches the manifest, and main() checks its length against the compiled function. */
static const casadi_real P[N_P] = {
    9.81,        /* p[0] g (m/s^2) */
    0.071,       /* p[1] m_link1 (kg) */
    8.9395e-05,  /* p[2] izz_link1 (kg*m^2) */
    0.0373,      /* p[3] cgx_link1 (m) */
    0.292,       /* p[4] m_motor2 (kg) */
    0.0,         /* p[5] izz_motor2 (kg*m^2) */
    0.075,       /* p[6] m_link2 (kg) */
    0.000109864, /* p[7] izz_link2 (kg*m^2) */
    0.04168,     /* p[8] cgx_link2 (m) */
    0.1,         /* p[9] px_link1_CS2 (m) */
    0.1,         /* p[10] px_link2_CS2 (m) */
};

/* Work space: fixed sizes, checked against serial_2dof_inverse_dynamics_work() at start-up (it
 * says 4 inputs, 1 output, no integer or real work for this function). */
enum { MAX_ARG = 8, MAX_RES = 4, MAX_IW = 16, MAX_W = 64 };

static int parse(const char *text, casadi_real *out) {
    char *end;
    errno = 0;
    *out = strtod(text, &end);
    return errno == 0 && end != text && *end == '\0';
}

int main(int argc, char **argv) {
    casadi_real x[3 * N_Q]; /* q, qd, qdd */
    casadi_real tau[N_Q];
    const casadi_real *arg[MAX_ARG];
    casadi_real *res[MAX_RES];
    casadi_int iw[MAX_IW], sz_arg, sz_res, sz_iw, sz_w;
    casadi_real w[MAX_W];
    int i;

    if (argc != 1 + 3 * N_Q) {
        fprintf(stderr, "usage: %s q1 q2 qd1 qd2 qdd1 qdd2   (rad, rad/s, rad/s^2)\n", argv[0]);
        return 2;
    }
    for (i = 0; i < 3 * N_Q; ++i) {
        if (!parse(argv[1 + i], &x[i])) {
            fprintf(stderr, "argument %d (%s) is not a number\n", i + 1, argv[1 + i]);
            return 2;
        }
    }
    serial_2dof_inverse_dynamics_work(&sz_arg, &sz_res, &sz_iw, &sz_w);
    if (sz_arg > MAX_ARG || sz_res > MAX_RES || sz_iw > MAX_IW || sz_w > MAX_W) {
        fprintf(stderr, "work space too small: raise MAX_* to %lld %lld %lld %lld\n",
                (long long)sz_arg, (long long)sz_res, (long long)sz_iw, (long long)sz_w);
        return 3;
    }
    /* sparsity_in(i)[0] is the number of rows of input i: q and p must match this file */
    if (serial_2dof_inverse_dynamics_sparsity_in(0)[0] != N_Q ||
        serial_2dof_inverse_dynamics_sparsity_in(3)[0] != N_P) {
        fprintf(stderr, "serial_2dof.c was re-derived: update N_Q, N_P and P from manifest.json\n");
        return 3;
    }
    arg[0] = x;           /* q */
    arg[1] = x + N_Q;     /* qd */
    arg[2] = x + 2 * N_Q; /* qdd */
    arg[3] = P;           /* p */
    res[0] = tau;
    if (serial_2dof_inverse_dynamics(arg, res, iw, w, 0) != 0) {
        fprintf(stderr, "serial_2dof_inverse_dynamics failed\n");
        return 1;
    }
    for (i = 0; i < N_Q; ++i) printf("%.17g\n", tau[i]);
    return 0;
}

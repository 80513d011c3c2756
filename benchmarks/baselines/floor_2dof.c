/* The plain-C floor for the 2-DOF arm's inverse dynamics: the textbook closed form, written by
 * hand, structure-of-arrays (q1[N], q2[N], ...), one call for all N samples.
 *
 * Compiled by benchmarks/baselines/cfloor.py with `cc -O3 -march=native -ffast-math -fPIC
 * -shared`, so that gcc vectorises the loop and calls glibc's libmvec for sin/cos. It is the
 * "how fast could a hand-written kernel be" reference, not a general solution: the arm's
 * structure (gravity along -y, centres of gravity on the link axes, motor point mass welded
 * at the elbow) is hard-coded; only the numbers come from the description.
 *
 *   M11 = alpha + 2 beta cos q2,  M12 = delta + beta cos q2,  M22 = delta
 *   c1  = -beta sin q2 (qd2^2 + 2 qd1 qd2),  c2 = beta sin q2 qd1^2
 *   g1  = gam1 cos q1 + gam2 cos(q1 + q2),   g2 = gam2 cos(q1 + q2)
 *
 * sin q2 is computed in its own loop over a block of samples: when sin and cos of one angle sit
 * in the same loop, gcc fuses them into a scalar sincos, which libmvec cannot vectorise, and
 * the whole loop stays scalar (about 3x slower here).
 *
 * p: g, m_1, I_1, l_c1, m_M2, I_M2, m_2, I_2, l_c2, a_1 (SI), the parameters of the same names
 * in generated/serial_2dof/manifest.json.
 */
#include <math.h>

#define BLOCK 256

void floor_2dof(long n, const double *restrict p,
                const double *restrict q1, const double *restrict q2,
                const double *restrict qd1, const double *restrict qd2,
                const double *restrict qdd1, const double *restrict qdd2,
                double *restrict tau1, double *restrict tau2)
{
    const double g = p[0], m1 = p[1], I1 = p[2], lc1 = p[3], mM2 = p[4], IM2 = p[5];
    const double m2 = p[6], I2 = p[7], lc2 = p[8], a1 = p[9];
    const double alpha = I1 + I2 + IM2 + m1 * lc1 * lc1 + (m2 + mM2) * a1 * a1 + m2 * lc2 * lc2;
    const double beta = a1 * lc2 * m2;
    const double delta = I2 + m2 * lc2 * lc2;
    const double gam1 = g * (a1 * (m2 + mM2) + lc1 * m1);
    const double gam2 = g * lc2 * m2;
    double sin2[BLOCK];
    for (long k0 = 0; k0 < n; k0 += BLOCK) {
        const long m = n - k0 < BLOCK ? n - k0 : BLOCK;
        for (long i = 0; i < m; ++i)
            sin2[i] = sin(q2[k0 + i]);
        for (long i = 0; i < m; ++i) {
            const long k = k0 + i;
            const double c2 = cos(q2[k]), s2 = sin2[i];
            const double c1 = cos(q1[k]), c12 = cos(q1[k] + q2[k]);
            const double m11 = alpha + 2.0 * beta * c2, m12 = delta + beta * c2;
            tau1[k] = m11 * qdd1[k] + m12 * qdd2[k]
                      - beta * s2 * (qd2[k] * qd2[k] + 2.0 * qd1[k] * qd2[k])
                      + gam1 * c1 + gam2 * c12;
            tau2[k] = m12 * qdd1[k] + delta * qdd2[k] + beta * s2 * qd1[k] * qd1[k]
                      + gam2 * c12;
        }
    }
}

/* The plain-C floor for the 3-DOF arm's inverse dynamics: planar Newton-Euler unrolled by hand
 * for three links, structure-of-arrays (q1[N], q2[N], q3[N], ...), one call for all N samples.
 * Compiled like floor_2dof.c (-O3 -march=native -ffast-math: vectorised, libmvec sin/cos).
 *
 * Hard-coded structure (only the numbers come from the description): gravity along -y, centres
 * of gravity on the link axes, motor point masses welded at the tips of links 1 and 2 (merged
 * into those links before the loop). Per sample, with absolute angles th_i, rates w_i, al_i,
 * e_i = (cos th_i, sin th_i), n_i = (-sin th_i, cos th_i) and r x f = r_x f_y - r_y f_x:
 *
 *   a_O1 = (0, g)                        (gravity as a base acceleration)
 *   a_ci = a_Oi + c_i (al_i n_i - w_i^2 e_i),   a_O(i+1) = a_Oi + a_i (al_i n_i - w_i^2 e_i)
 *   F_i  = M_i a_ci + F_(i+1)
 *   tau_i = I_i al_i + tau_(i+1) + (c_i e_i) x (M_i a_ci) + (a_i e_i) x F_(i+1)
 *
 * The sines are computed in their own loop over a block of samples (see floor_2dof.c: sin and
 * cos of one angle in the same loop become a scalar sincos and nothing is vectorised).
 *
 * p: g, m_1, I_1, l_c1, m_M2, I_M2, m_2, I_2, l_c2, m_M3, I_M3, m_3, I_3, l_c3, a_1, a_2 (SI).
 */
#include <math.h>

#define BLOCK 256

void floor_3dof(long n, const double *restrict p,
                const double *restrict q1, const double *restrict q2,
                const double *restrict q3, const double *restrict qd1,
                const double *restrict qd2, const double *restrict qd3,
                const double *restrict qdd1, const double *restrict qdd2,
                const double *restrict qdd3, double *restrict tau1,
                double *restrict tau2, double *restrict tau3)
{
    const double g = p[0], a1 = p[14], a2 = p[15];
    /* link 1 + motor 2 at its tip, link 2 + motor 3 at its tip, link 3 */
    const double M1 = p[1] + p[4], M2 = p[6] + p[9], M3 = p[11];
    const double c1 = (p[1] * p[3] + p[4] * a1) / M1, c2 = (p[6] * p[8] + p[9] * a2) / M2;
    const double c3 = p[13];
    const double I1 = p[2] + p[5] + p[1] * (p[3] - c1) * (p[3] - c1)
                      + p[4] * (a1 - c1) * (a1 - c1);
    const double I2 = p[7] + p[10] + p[6] * (p[8] - c2) * (p[8] - c2)
                      + p[9] * (a2 - c2) * (a2 - c2);
    const double I3 = p[12];
    double sn1[BLOCK], sn2[BLOCK], sn3[BLOCK];
    for (long k0 = 0; k0 < n; k0 += BLOCK) {
        const long m = n - k0 < BLOCK ? n - k0 : BLOCK;
        for (long i = 0; i < m; ++i) {
            const long k = k0 + i;
            sn1[i] = sin(q1[k]);
            sn2[i] = sin(q1[k] + q2[k]);
            sn3[i] = sin(q1[k] + q2[k] + q3[k]);
        }
        for (long i = 0; i < m; ++i) {
            const long k = k0 + i;
            const double t1 = q1[k], t2 = t1 + q2[k], t3 = t2 + q3[k];
            const double w1 = qd1[k], w2 = w1 + qd2[k], w3 = w2 + qd3[k];
            const double b1 = qdd1[k], b2 = b1 + qdd2[k], b3 = b2 + qdd3[k];
            const double ex1 = cos(t1), ey1 = sn1[i], ex2 = cos(t2), ey2 = sn2[i];
            const double ex3 = cos(t3), ey3 = sn3[i];
            /* (al n - w^2 e) per link: the acceleration of a unit length along the link */
            const double ux1 = -b1 * ey1 - w1 * w1 * ex1, uy1 = b1 * ex1 - w1 * w1 * ey1;
            const double ux2 = -b2 * ey2 - w2 * w2 * ex2, uy2 = b2 * ex2 - w2 * w2 * ey2;
            const double ux3 = -b3 * ey3 - w3 * w3 * ex3, uy3 = b3 * ex3 - w3 * w3 * ey3;
            const double ox1 = 0.0, oy1 = g;
            const double ox2 = ox1 + a1 * ux1, oy2 = oy1 + a1 * uy1;
            const double ox3 = ox2 + a2 * ux2, oy3 = oy2 + a2 * uy2;
            const double fx3 = M3 * (ox3 + c3 * ux3), fy3 = M3 * (oy3 + c3 * uy3);
            const double n3 = I3 * b3 + c3 * (ex3 * fy3 - ey3 * fx3);
            const double gx2 = M2 * (ox2 + c2 * ux2), gy2 = M2 * (oy2 + c2 * uy2);
            const double n2 = I2 * b2 + n3 + c2 * (ex2 * gy2 - ey2 * gx2)
                              + a2 * (ex2 * fy3 - ey2 * fx3);
            const double fx2 = gx2 + fx3, fy2 = gy2 + fy3;
            const double gx1 = M1 * (ox1 + c1 * ux1), gy1 = M1 * (oy1 + c1 * uy1);
            const double n1 = I1 * b1 + n2 + c1 * (ex1 * gy1 - ey1 * gx1)
                              + a1 * (ex1 * fy2 - ey1 * fx2);
            tau1[k] = n1;
            tau2[k] = n2;
            tau3[k] = n3;
        }
    }
}

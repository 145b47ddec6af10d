/* bond_order.c — global bond-orientational order Q6 (see bond_order.h).
 *
 * Y_6m(theta, phi) = N_m P_6^m(cos theta) e^{i m phi} with P_6^m(z) = (-1)^m (1 - z^2)^{m/2}
 * D_m(z), D_m = d^m P_6/dz^m, and N_m^2 = 13/(4 pi) (6 - m)!/(6 + m)!. For a unit vector
 * (x, y, z), (1 - z^2)^{m/2} e^{i m phi} = (x + i y)^m, so no angle is needed:
 *   4 pi/13 sum_m |<Y_6m>|^2 = sum_{m=0..6} w_m |<D_m(z) (x + i y)^m>|^2,
 *   w_0 = 1, w_m = 2 (6 - m)!/(6 + m)! (m and -m together).
 */
#include "bond_order.h"

#include <math.h>

void lub_q6_zero(lub_q6_accum *a)
{
    for (int m = 0; m < 7; ++m)
        a->re[m] = a->im[m] = 0.0;
    a->n = 0;
}

void lub_q6_add(lub_q6_accum *a, vec3 d)
{
    const double len = v3_norm(d);
    if (!(len > 0.0) || !isfinite(len))
        return;
    const double x = d.x / len, y = d.y / len, z = d.z / len, z2 = z * z;
    /* derivatives of P_6(z) = (231 z^6 - 315 z^4 + 105 z^2 - 5)/16 */
    const double dm[7] = {
        (((231.0 * z2 - 315.0) * z2 + 105.0) * z2 - 5.0) / 16.0,
        ((1386.0 * z2 - 1260.0) * z2 + 210.0) * z / 16.0,
        ((6930.0 * z2 - 3780.0) * z2 + 210.0) / 16.0,
        (27720.0 * z2 - 7560.0) * z / 16.0,
        (83160.0 * z2 - 7560.0) / 16.0,
        166320.0 * z / 16.0,
        166320.0 / 16.0,
    };
    double pr = 1.0, pi = 0.0; /* (x + i y)^m */
    for (int m = 0; m < 7; ++m) {
        a->re[m] += dm[m] * pr;
        a->im[m] += dm[m] * pi;
        const double nr = pr * x - pi * y;
        pi = pr * y + pi * x;
        pr = nr;
    }
    a->n++;
}

double lub_q6_value(const lub_q6_accum *a)
{
    if (a->n <= 0)
        return NAN;
    /* w_m = 2 (6 - m)!/(6 + m)! for m > 0 */
    static const double w[7] = {1.0,
                                2.0 / 42.0,
                                2.0 / 1680.0,
                                2.0 / 60480.0,
                                2.0 / 1814400.0,
                                2.0 / 39916800.0,
                                2.0 / 479001600.0};
    const double inv_n = 1.0 / (double)a->n;
    double s = 0.0;
    for (int m = 0; m < 7; ++m) {
        const double re = a->re[m] * inv_n, im = a->im[m] * inv_n;
        s += w[m] * (re * re + im * im);
    }
    return sqrt(s);
}

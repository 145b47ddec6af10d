/* bond_order.h — global bond-orientational order Q6 (Steinhardt, Nelson & Ronchetti 1983) of a
 * set of bond directions: an indicator of crystal-like ordering of a sheared packing.
 *
 *   Q6 = sqrt( 4 pi / 13 * sum_{m=-6..6} |<Y_6m(n)>|^2 ),  <.> the mean over the bonds,
 *
 * with Y_6m the orthonormal spherical harmonics. Q6 is invariant under rotations, 1 for bonds
 * all along one direction, 0.5745 for the 12 nearest-neighbour bonds of fcc, 0.3536 for the 6
 * of simple cubic, 0.6285 for the 8 of bcc, and about 1/sqrt(number of bonds) for random
 * directions. A bond and its reverse contribute alike (l = 6 is even).
 * Pure functions on a caller-owned accumulator; no allocation, no globals.
 */
#ifndef LUBDEM_BOND_ORDER_H
#define LUBDEM_BOND_ORDER_H

#include "vec3.h"

typedef struct {
    /* sums over the bonds of D_m(z) (x + i y)^m, m = 0..6, D_m = d^m P_6/dz^m (the m < 0
     * terms are the complex conjugates of the m > 0 ones up to sign) */
    double re[7], im[7];
    long n; /* bonds added */
} lub_q6_accum;

void lub_q6_zero(lub_q6_accum *a);
/* Adds the bond direction d (any length > 0; a zero or non-finite vector is ignored). */
void lub_q6_add(lub_q6_accum *a, vec3 d);
/* Q6 of the bonds added; NaN when there are none. */
double lub_q6_value(const lub_q6_accum *a);

#endif

/* velocity_gradient.h — the background flow w(x) = L x of a velocity gradient L (row-major,
 * L[i][j] = d w_i / d x_j; simple shear: L[0][1] = gamma-dot). Pure inline helpers shared by
 * the few-body scenes, the periodic shear cell and the resuspension cell. */
#ifndef LUBDEM_VELOCITY_GRADIENT_H
#define LUBDEM_VELOCITY_GRADIENT_H

#include "vec3.h"

/* m x for a 3x3 matrix (row-major m[i][j]). */
static inline vec3 lub_mat_vec(const double m[3][3], vec3 x)
{
    return v3(m[0][0] * x.x + m[0][1] * x.y + m[0][2] * x.z,
              m[1][0] * x.x + m[1][1] * x.y + m[1][2] * x.z,
              m[2][0] * x.x + m[2][1] * x.y + m[2][2] * x.z);
}

/* Spin of the fluid, half the vorticity: (1/2) curl(L x), curl_i = eps_ijk L_kj.
 * Simple shear L[0][1] = gd gives (0, 0, -gd/2). */
static inline vec3 lub_flow_spin(const double L[3][3])
{
    return v3(0.5 * (L[2][1] - L[1][2]), 0.5 * (L[0][2] - L[2][0]), 0.5 * (L[1][0] - L[0][1]));
}

#endif

/* periodic_cell.h — a tri-periodic, homogeneously deforming cell (notes §9).
 *
 * The cell matrix H has the cell vectors as COLUMNS: h[r][c] is component r of cell vector c.
 * A point x has fractional coordinates s = H^-1 x; the image of x shifted by the integer
 * vector c is x + H c. The cell deforms with the imposed velocity gradient L (units 1/time):
 * H <- (I + dt L) H every step. Simple shear is L = gd e_x (x) e_y (v_x = gd y) and shears
 * cell vector 1 (the gradient direction) along x; imposed-pressure runs add L_yy (dilation
 * of the gradient direction).
 *
 * Velocities are ABSOLUTE (mean flow L x included). Hence:
 *  - the image of a particle at x + H c moves with v + L H c (lub_cell_image_velocity);
 *  - wrapping a particle by x -> x - H k changes its velocity by -L H k (lub_cell_wrap).
 * Flips (lub_cell_flip) replace H by the lattice-equivalent H (I + F) (F integer, det 1) when a
 * tilt exceeds one half, so that the cell never degenerates; a pair's image shift c must then
 * become (I + F)^-1 c (lub_cell_flip_shift). The shear system recomputes every pair's c from
 * the positions at each neighbour-list rebuild, and wraps/flips only at rebuilds.
 *
 * Units: lengths and times of the caller. Pure value type; no allocation; no errors except
 * lub_cell_update's return value (-1 when det H <= 0).
 */
#ifndef LUBDEM_PERIODIC_CELL_H
#define LUBDEM_PERIODIC_CELL_H

#include "vec3.h"
#include "velocity_gradient.h"

typedef struct {
    double h[3][3];    /* cell matrix, columns = cell vectors */
    double hinv[3][3]; /* its inverse (kept in sync by every function here) */
    double L[3][3];    /* velocity gradient, L[i][j] = d v_i / d x_j */
    double volume;     /* det H */
} lub_cell;

/* Orthorhombic box lx*ly*lz (> 0), L = 0. */
void lub_cell_init_box(lub_cell *c, double lx, double ly, double lz);
/* Recomputes hinv and volume after a direct edit of h. Returns -1 if det H <= 0. */
int lub_cell_refresh(lub_cell *c);
/* H <- (I + dt L) H. Returns -1 if the cell degenerates (det <= 0). */
int lub_cell_update(lub_cell *c, double dt);

vec3 lub_cell_to_frac(const lub_cell *c, vec3 x);
vec3 lub_cell_to_cart(const lub_cell *c, vec3 s);
/* H k for an integer shift k (inline: used per pair and per step). */
static inline vec3 lub_cell_shift(const lub_cell *c, const int k[3])
{
    return lub_mat_vec(c->h, v3((double)k[0], (double)k[1], (double)k[2]));
}
/* Mean-flow velocity L x at point x. */
static inline vec3 lub_cell_mean_velocity(const lub_cell *c, vec3 x)
{
    return lub_mat_vec(c->L, x);
}
/* Velocity offset of the image shifted by k: L H k. */
static inline vec3 lub_cell_image_velocity(const lub_cell *c, const int k[3])
{
    return lub_mat_vec(c->L, lub_cell_shift(c, k));
}

/* Wraps *x into the primary cell (fractional coordinates in [0,1)), applying the matching
 * mean-flow jump to *v (may be NULL). Writes the integer shift k removed (x_new = x - H k)
 * into k_out (may be NULL). */
void lub_cell_wrap(const lub_cell *c, vec3 *x, vec3 *v, int k_out[3]);

/* Perpendicular widths of the cell (distance between opposite faces), per cell vector. */
void lub_cell_widths(const lub_cell *c, double w[3]);

/* If cell vector 1 or 2 is tilted along cell vector 0 by more than 1/2 of it (fractional
 * x-component of h_j outside [-1/2, 1/2]), subtracts the nearest integer multiple of h_0:
 * H <- H (I + F) with F[0][j] = -m_j. Writes m[3] (m[0] = 0) and returns 1 if the cell
 * changed, 0 otherwise. */
int lub_cell_flip(lub_cell *c, int m[3]);
/* Image shift of a pair after a flip with multiples m: c_new = (I + F)^-1 c, i.e.
 * c_new[0] = c[0] + m[1] c[1] + m[2] c[2]. */
void lub_cell_flip_shift(const int m[3], int shift[3]);
/* lub_cell_wrap of a body whose images are counted: img (the cell images removed from it so
 * far) is first carried into the cell flipped by m (flipped 0: no flip since the last call),
 * then the wrap's shift is added, so that the unwrapped position x + H img does not change. */
void lub_cell_wrap_counted(const lub_cell *c, const int m[3], int flipped, vec3 *x, vec3 *v,
                           int img[3]);

#endif

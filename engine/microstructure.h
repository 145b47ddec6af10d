/* microstructure.h — pair distribution functions on the unit sphere (notes §10).
 *
 * Orientation of a pair normal n (1 -> 2): theta = arccos(n_y) in [0, pi] (gradient axis at
 * theta = 0), phi = atan2(n_x, n_z) (vorticity z at phi = 0, flow x at phi = pi/2). Central
 * symmetry: pairs with phi < 0 are mapped to (pi - theta, phi + pi) and flagged "inversed";
 * only phi in [0, pi) is binned. n_theta x n_phi bins uniform in angle, solid angle
 * dS = (cos(i dtheta) - cos((i + 1) dtheta)) dphi, the bin's exact area (the midpoint rule
 * until 2026-12-06). Indices are clamped (theta = pi exactly goes to the
 * last bin, notes §11 P15).
 * Accumulated per snapshot (the interacting pairs: inside the cut-off, and in the Delaunay set
 * when the system uses one):
 *   interaction density  P   = sum 1/(N dS)      (integral over the hemisphere = Z/2)
 *   contact density      P_c = same, contact pairs only
 *   pair count           number of pairs summed over the snapshots
 *   mean gap             sum u_n/a_ij (geometric gap u_n over the pair's mean radius; 1)
 *   mean relative velocity sum w (contact-point relative velocity, sign flipped if inversed)
 *   mean centre relative velocity sum v_2 - v_1 (centre-of-mass relative velocity, the image's
 *                        mean-flow velocity included; sign flipped if inversed; thesis Fig. 3.9)
 *   stress densities     sum F_part (x) l / (V dS) for NC, SC, NL, SL
 * lub_pdf_finish() divides by the number of snapshots (densities) and by the pair counts (mean
 * gap and velocities; a bin no pair fell in gets NaN there, not 0, which would read as a
 * touching pair at rest). Memory: lub_pdf_init allocates once; no allocation afterwards.
 */
#ifndef LUBDEM_MICROSTRUCTURE_H
#define LUBDEM_MICROSTRUCTURE_H

#include "contact_law.h"
#include "vec3.h"

typedef struct {
    int nt, np;
    double *density, *contact_density; /* [nt*np] */
    double *gap_sum, *count;           /* [nt*np] */
    double *vel_sum;                   /* [nt*np*3] contact-point relative velocity */
    double *vel_com_sum;               /* [nt*np*3] centre-of-mass relative velocity */
    double *stress;                    /* [4][nt*np][9] NC, SC, NL, SL */
    long snapshots;
    double strain_first, strain_last; /* strain of the first and last snapshot (set by the
                                         scene; NaN: none or not known) */
} lub_pdf;

int lub_pdf_init(lub_pdf *p, int n_theta, int n_phi); /* 0 or -1 (no memory) */
void lub_pdf_free(lub_pdf *p);
void lub_pdf_clear(lub_pdf *p);
/* Bin index of a unit normal; *inversed set to 1 if the central symmetry was applied. */
int lub_pdf_bin(const lub_pdf *p, vec3 n, int *inversed);
double lub_pdf_solid_angle(const lub_pdf *p, int bin);
/* Bytes lub_pdf_init allocates for n_theta x n_phi bins. */
double lub_pdf_bytes(int n_theta, int n_phi);
/* Adds one pair of one snapshot. n_particles, volume: for normalisation. a: pair mean radius,
 * w: contact-point relative velocity, wc: centre-of-mass relative velocity, branch: l. */
void lub_pdf_add_pair(lub_pdf *p, const lub_pair_output *o, vec3 branch, vec3 w, vec3 wc, double a,
                      int n_particles, double volume);
/* a += b (same shape) */
void lub_pdf_accumulate(lub_pdf *a, const lub_pdf *b);
/* Normalises in place (call once, after the last snapshot). */
void lub_pdf_finish(lub_pdf *p);

#endif

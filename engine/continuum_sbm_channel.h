/* continuum_sbm_channel.h — steady shear-induced migration in a pressure-driven pipe or plane
 * channel, with the congestion cap of Ozenda's chapter 5 (psi <= psi*, contact pressure p_c).
 *
 * Steady reduction of the dimensional (5.19) (note §2.6, derived there, not in the thesis; the
 * eps scalings of (5.18)/(5.20) are inconsistent, erratum E12, and the drag, E8, drops out at
 * steady state since w_r = 0; w_z is taken as 0 in the flux-weighted inventory): w_r = 0; rate
 * independence makes A_r(psi) = tau_rr/(eta_app |gd|) and A_th(psi) = tau_thth/(eta_app |gd|)
 * functions of psi only; the axial balance gives |sigma_rz| = eta_app |gd| = G r/2 (pipe) or
 * G y (channel, y from the mid-plane). Outside the plug (p_c = 0):
 *     pipe:    d(r^2 A_r(psi))/dr = r A_th(psi),   i.e. d ln|Q|/d ln r = A_th/A_r, Q = r^2 A_r;
 *     channel: A_r(psi(y)) y = const (no hoop term).
 * |A_r| is bounded as psi -> 1, so a central plug psi = psi* always forms; there
 *     pipe: dp_c/dr = G (A_r* - A_th* / 2),  channel: dp_c/dy = G A_r*,  p_c = 0 at its edge.
 * The one free constant (|Q| at the wall) is fixed by the inventory: the area mean of psi or the
 * flux-weighted mean (5.19h), by bisection (monotone). Closures:
 *     M4:  A_r = N2/sigma_xy of the chapter-4 texture model with laws (4.9), A_th = 0 (tau_rr from
 *          (4.5b), i.e. with beta3 |gd| (g_rz^2 + g_rr^2), not the printed (5.14e): erratum E9);
 *     MM:  Miller & Morris: A_r = -lambda_grad eta_n/(1+eta_p), A_th = -lambda_vort
 * eta_n/(1+eta_p); DEM: A_r = -eta_22/eta_r, A_th = -lambda_33 eta_22/eta_r (physics-reference
 * §2-3). Lengths in units of R (pipe radius or channel half-width); velocities in units of the mean
 * velocity; G in eta0 U/R^2; p_c in eta0 U/R. Grid: n cell midpoints x_i = (i + 1/2)/n.
 * Pure: the caller owns every array; no allocation.
 */
#ifndef LUBDEM_CONTINUUM_SBM_CHANNEL_H
#define LUBDEM_CONTINUUM_SBM_CHANNEL_H

#include <signal.h>

#include "continuum_normal_laws.h"

typedef enum { LUB_CLOSURE_M4 = 0, LUB_CLOSURE_MM = 1, LUB_CLOSURE_DEM = 2 } lub_closure_kind;
typedef enum { LUB_GEOM_PIPE = 0, LUB_GEOM_CHANNEL = 1 } lub_geom;

typedef struct {
    lub_closure_kind kind;
    lub_m4_laws m4;     /* M4 */
    double m4_phi_m;    /* M4: phi_m of the Einstein term */
    lub_mm_params mm;   /* MM */
    double dem_phi_m;   /* DEM */
    double dem_phi_rcp; /* DEM */
} lub_closure;

/* A_r (< 0), A_th (<= 0) and eta_app/eta0 at psi in ]0,1[. */
void lub_closure_eval(const lub_closure *c, double psi, double *A_r, double *A_th, double *eta_rel);
/* phi_m of the closure (to convert psi to phi). */
double lub_closure_phi_m(const lub_closure *c);

typedef struct {
    lub_geom geom;
    double psi_star;                   /* congestion cap, 0 < psi* < 1 */
    double psi_mean;                   /* inventory, 0 < psi_mean < psi* */
    int flux_weighted;                 /* 0: area mean of psi; 1: flux-weighted mean (5.19h) */
    int n;                             /* cells */
    const volatile sig_atomic_t *stop; /* optional (NULL: never): once non-zero,
                                          lub_channel_solve gives up at its next iteration */
} lub_channel_setup;

typedef struct {
    double q;           /* |Q| (pipe) or |A_r| y (channel) at the wall: the free constant */
    double x_plug;      /* plug edge r_c/R or y_c/H */
    double psi_wall;    /* psi at x = 1 */
    double psi_centre;  /* psi at the axis (= psi* in the plug) */
    double G;           /* pressure gradient for unit mean velocity, eta0 U/R^2 */
    double G_newtonian; /* the same for the pure fluid: 8 (pipe), 3 (channel) */
    double psi_area;    /* area mean of psi */
    double psi_flux;    /* flux-weighted mean of psi */
    double pc_centre;   /* contact pressure at the axis */
} lub_channel_result;

/* Tolerance on the achieved inventory (area or flux-weighted mean of psi) */
#define LUB_CHANNEL_INVENTORY_TOL 1e-9

/* Arrays of length setup->n: x (midpoints), psi, u, pc, eta_rel (eta_app/eta0). Returns 0, or
 * -1 with a static reason (closure not monotone, inventory outside ]0, psi*[, ...), or -2 when
 * *setup->stop asked it to stop (the arrays are then not a solution), or -3 when no wall
 * constant meets the inventory within LUB_CHANNEL_INVENTORY_TOL (res holds the closest profile's
 * numbers: psi_area, psi_flux, q). */
int lub_channel_solve(const lub_closure *c, const lub_channel_setup *setup, double *x, double *psi,
                      double *u, double *pc, double *eta_rel, lub_channel_result *res,
                      const char **why);

#endif

/* continuum_sbm_resuspension.h — steady viscous resuspension by the suspension balance model
 * (the SBM "predictor" of the DEM resuspension scenes).
 *
 * Zero particle flux at steady state, (div tau_p + phi drho g).n = 0 with the sign of
 * (2.40)/(2.41c) (erratum E11: the printed (2.41e) has -div tau_p), gives d sigma^p_ii/dx_i = phi
 * drho g, i.e. (seed 000 eqs (3), (6); physics-reference §4) eta_ii(phi(y)) = (1/Sh) Phi(y), Phi(y)
 * = int_y^inf phi dy',   Sh = eta0 gd/(drho g a), lengths in units of the particle radius a, Phi(0)
 * = the inventory int phi dy / a (= phi0 h0/a). The profile is exact given the law: phi_b =
 * eta_ii^{-1}(inventory/Sh) at the floor and, writing the law in s = psi/(1-psi) (phi = phi_m
 * s/(1+s)) and integrating by parts, y(s) = inventory/phi_b - Sh eta(s)/phi(s) + (Sh/phi_m)
 * int_s^{s_b} eta(s')/s'^2 ds', a derivative-free, monotone quadrature (adaptive Gauss–Legendre in
 * v with s = s_b v^m, which removes the s^{n-2} endpoint singularity; note §5 N12 — no ODE in phi,
 * no Lipschitz issue at the free surface). The resuspended height is y(0) (finite iff eta ~ s^n
 * with n > 1). Power law n = 2 has the closed form h = (2 lambda Sh/phi_m)(s0 + s0^2/2), s0 =
 * sqrt(inventory
 * /(Sh lambda)). Pure functions; no allocation.
 */
#ifndef LUBDEM_CONTINUUM_SBM_RESUSPENSION_H
#define LUBDEM_CONTINUUM_SBM_RESUSPENSION_H

#include <signal.h>

#include "continuum_normal_laws.h"

/* The work of the quadrature, bounded (optional: lub_resusp_solve_bounded). Where the law's
 * values underflow (eta ~ s^9 of the DEM-seed law at an inventory/Sh of 1e-260, or the power
 * v^(m-1) of a power law with n near 1) the adaptive refinement never meets its tolerance and
 * would take tens of minutes; with a bound it gives up and says so. */
enum { LUB_RESUSP_OK = 0, LUB_RESUSP_BUDGET = 1, LUB_RESUSP_STOPPED = 2 };
typedef struct {
    long long panels;                  /* 5-point Gauss-Legendre panels evaluated so far */
    long long max_panels;              /* the quadrature gives up beyond this (<= 0: no bound) */
    const volatile sig_atomic_t *stop; /* optional (NULL: never): non-zero gives up too */
    int status;    /* LUB_RESUSP_*: once not OK every integral returns 0 at once, and the
                      heights and profiles computed since are not valid */
    int underflow; /* 1 when s = s_b v^m or the law's eta(s) underflowed to 0 or a subnormal
                      at v > 0 (the usual reason for the bound) */
} lub_resusp_work;

typedef struct {
    double shields;        /* Sh = eta0 gd/(drho g a) > 0 */
    double inventory;      /* int phi dy / a > 0 */
    double s_bottom;       /* s = psi/(1-psi) at the floor */
    double phi_bottom;     /* phi at the floor */
    double height;         /* resuspended height / a (where phi reaches 0) */
    int m;                 /* substitution exponent used by the quadrature */
    lub_resusp_work *work; /* the bound of every quadrature on this profile (NULL: none) */
} lub_resusp;

/* Solves the floor state and the height. Returns 0, or -1 with a static reason (law not
 * increasing, n <= 1, zero normal viscosity as for OZENDA_M4 along the vorticity). No bound on
 * the work (work NULL). */
int lub_resusp_solve(const lub_normal_law *L, double shields, double inventory, lub_resusp *out,
                     const char **why);
/* The same with the quadratures of the height and of every later lub_resusp_y_of_s,
 * lub_resusp_phi_at and lub_resusp_profile on *out bounded by *work (kept in out->work; the
 * caller owns it and reads work->status after each call: not LUB_RESUSP_OK means the results
 * are not valid). -1 with why also when the bound stops the height. */
int lub_resusp_solve_bounded(const lub_normal_law *L, double shields, double inventory,
                             lub_resusp_work *work, lub_resusp *out, const char **why);

/* Height y/a at which the profile has the value s (0 <= s <= s_bottom). */
double lub_resusp_y_of_s(const lub_normal_law *L, const lub_resusp *r, double s);
/* phi at height y (0 above the resuspended height). */
double lub_resusp_phi_at(const lub_normal_law *L, const lub_resusp *r, double y);

/* Fills n >= 2 points of the profile on the s-grid s_k = s_b v_k^m, v_k = 1 - k/(n-1), from the
 * floor (y = 0) to the top (y = height, phi = 0): y[k], phi[k] (caller-owned arrays). */
void lub_resusp_profile(const lub_normal_law *L, const lub_resusp *r, int n, double *y,
                        double *phi);

/* Closed form for eta = lambda s^2. */
double lub_resusp_height_n2(double lambda, double phi_m, double shields, double inventory);

#endif

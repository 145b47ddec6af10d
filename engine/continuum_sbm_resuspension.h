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

#include "continuum_normal_laws.h"

typedef struct {
    double shields;    /* Sh = eta0 gd/(drho g a) > 0 */
    double inventory;  /* int phi dy / a > 0 */
    double s_bottom;   /* s = psi/(1-psi) at the floor */
    double phi_bottom; /* phi at the floor */
    double height;     /* resuspended height / a (where phi reaches 0) */
    int m;             /* substitution exponent used by the quadrature */
} lub_resusp;

/* Solves the floor state and the height. Returns 0, or -1 with a static reason (law not
 * increasing, n <= 1, zero normal viscosity as for OZENDA_M4 along the vorticity). */
int lub_resusp_solve(const lub_normal_law *L, double shields, double inventory, lub_resusp *out,
                     const char **why);

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

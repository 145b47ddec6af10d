/* continuum_steady_curves.h — steady simple-shear rheology against psi = phi/phi_m for the
 * continuum models and the DEM-seed laws, side by side (job "continuum_steady_curves").
 *
 *  M4 (chapter 4): closed form (4.7) with the laws (4.9), Table 4.1; every reduced output is
 *      independent of eta0 and depends on phi_m only through the Einstein term.
 *  M3 (chapter 3): (3.8) with the laws (3.10), (3.16), Table 3.3 (phi = psi * 0.571; eta_e_bar is
 *      dimensional, tied to eta0 = 1.03 Pa.s); N2 = 0 and p_p = -N1/3 < 0 (wrong sign, [L1808]).
 *  MM: Miller & Morris SBM closure: alpha1 = -(1 - lambda_grad) eta_n/(1+eta_p), alpha2 =
 *      -(lambda_grad - lambda_vort) eta_n/(1+eta_p), p_p/sigma = (1 + lambda_grad + lambda_vort)
 *      eta_n/(3 (1+eta_p)).
 *  DEM: eta_r(phi), eta_22, lambda_33 (physics-reference §2-3); alpha2 = -(1-lambda_33)
 *      eta_22/eta_r; N1 is not given by the seed laws (lambda_11 depends on mu_m).
 *
 * Reduced quantities: alpha1 = N1/sigma_xy, alpha2 = N2/sigma_xy, pp_rel = p_p/sigma_xy (all
 * for gd > 0), eta_rel = sigma_xy/(eta0 gd), eta_n2 = -N2/(eta0 gd). Pure functions.
 */
#ifndef LUBDEM_CONTINUUM_STEADY_CURVES_H
#define LUBDEM_CONTINUUM_STEADY_CURVES_H

#include "continuum_normal_laws.h"

typedef struct {
    double psi, phi;
    double theta_e; /* depletion angle, rad (texture models; NAN-free: 0 for MM/DEM) */
    double eta_rel;
    double alpha1, alpha2, pp_rel;
    double eta_n2; /* -N2/(eta0 gd) */
} lub_steady_row;

typedef struct {
    double psi, phi;
    double eta_r, eta22, lambda33;
    double alpha2; /* -(1 - lambda_33) eta_22/eta_r */
    double eta_n2; /* (1 - lambda_33) eta_22 = -N2/(eta0 gd) */
    double mu;     /* eta_r/eta_22 = sigma_xy/P with P = -sigma_22 */
} lub_steady_dem_row;

/* psi in ]0,1[; return 0 or -1 with *why. */
int lub_steady_m4(const lub_m4_laws *L, double psi, double phi_m, lub_steady_row *row,
                  const char **why);
int lub_steady_m3(const lub_m3_laws *L, double psi, double eta0, lub_steady_row *row,
                  const char **why);
int lub_steady_mm(const lub_mm_params *m, double psi, lub_steady_row *row, const char **why);
int lub_steady_dem(double psi, double phi_m, double phi_rcp, lub_steady_dem_row *row,
                   const char **why);

/* psi -> 1 limits of M4 with the laws (4.9), (4.12): eta_app (1-psi)^2/eta0 -> eta1_bar,
 * alpha2 -> eta_e_bar (d1 d2 + b3)/(eta1_bar d1^2), p_p/sigma -> -2/3 of that. */
void lub_steady_m4_limits(const lub_m4_laws *L, double *eta1_bar, double *alpha2_lim,
                          double *pp_lim);
/* Small-psi coefficient of psi^2 in eta_app/eta0 (erratum E7: 3 omega, not 3 omega/2). */
double lub_steady_m4_c2(const lub_m4_laws *L);

#endif

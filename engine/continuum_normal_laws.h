/* continuum_normal_laws.h — particle normal-stress and viscosity laws used by the
 * suspension-balance (SBM) solvers and the steady-curve comparisons.
 *
 * Convention of the DEM seed (physics-reference §3): sigma^p_ii = -eta0 gd eta_ii(phi), i = 2
 * (gradient) or 3 (vorticity); psi = phi/phi_m; all laws are written in s = psi/(1-psi) so
 * that nothing cancels near phi_m.
 *
 *  POWER      eta_ii = lambda s^n (form (5) of seed 000). Presets, seed 000 [L1450]:
 *             Zarraga: n = 3, phi_m = 0.62, lambda_22 = 1.36, lambda_33 = 0.62;
 *             Boyer: n = 2, phi_m = 0.585, lambda_33 = 0.6, lambda_22 = 1 (eta_n = (phi/(phi_m -
 *               phi))^2 of Boyer et al. 2011; the seed quotes only lambda_33);
 *             Morris–Boulay: n = 2, phi_m = 0.68, lambda_33 = 0.38, lambda_22 = 0.6 (= K_n
 *               lambda_2 = 0.75 x 0.8, values commonly quoted for Morris & Boulay 1999 /
 *               Miller & Morris 2006; external, not in the seeds).
 *  DEM_SEED   eta_22 = psi^9/(1-psi)^2 + 150 psi^10, eta_33 = lambda_33 eta_22 with lambda_33 =
 *             (phi/phi_rcp)^7.5/(1e-3 + (phi/phi_rcp)^6), phi_rcp = 0.64 (physics-reference §3),
 *             phi_m = phi_m(mu_m) = 0.6301 - 0.0794 (1 - exp(-mu_m/0.4032)) (§2).
 *  OZENDA_M4  eta_22 = -N2/(eta0 gd) of the chapter-4 texture model with the laws (4.9) and
 *             Table 4.1; eta_33 = 0 identically (tau_zz = 0 in that model, note §4.1).
 *
 * Also: the DEM-seed shear viscosity eta_r(phi) (§2) and the Miller & Morris (2006) SBM closure
 * (2.41f–i) of the thesis (Q-diagonal entries named lambda_grad / lambda_vort, erratum E10: the
 * thesis mixes lambda1/lambda2/lambda3 for the gradient and vorticity entries), whose constants are
 * not in any seed (defaults K_s = 0.1, K_n = 0.75, lambda_grad = 0.8, lambda_vort = 0.5, phi_m =
 * 0.68 are the values usually quoted; note §2.4). Pure functions; no state.
 */
#ifndef LUBDEM_CONTINUUM_NORMAL_LAWS_H
#define LUBDEM_CONTINUUM_NORMAL_LAWS_H

#include "continuum_texture_laws.h"

typedef enum { LUB_NLAW_POWER = 0, LUB_NLAW_DEM_SEED = 1, LUB_NLAW_OZENDA_M4 = 2 } lub_nlaw_kind;

typedef struct {
    lub_nlaw_kind kind;
    int direction;  /* 2 = gradient (eta_22), 3 = vorticity (eta_33) */
    double phi_m;   /* divergence fraction (all kinds) */
    double lambda;  /* POWER */
    double n;       /* POWER, > 1 for a finite resuspended height */
    double phi_rcp; /* DEM_SEED (lambda_33 law) */
    lub_m4_laws m4; /* OZENDA_M4 */
} lub_normal_law;

/* Presets by name ("boyer", "zarraga", "morris_boulay") for direction 2 or 3; -1 if unknown. */
int lub_normal_law_preset(const char *name, int direction, lub_normal_law *out);

/* eta_ii as a function of s = psi/(1-psi) >= 0 (0 at s = 0; increasing for every law here). */
double lub_normal_law_eta_s(const lub_normal_law *L, double s);
/* Same as a function of phi in [0, phi_m[. */
double lub_normal_law_eta(const lub_normal_law *L, double phi);

/* DEM seed (physics-reference §2-3). */
double lub_dem_phi_m(double mu_m);
double lub_dem_eta_r(double phi, double phi_m); /* sigma_xy/(eta0 gd), 0 < phi < phi_m */
/* mu(Iv) = sigma_xy/P at imposed particle pressure (§2: mu_c + mu_h with phi = phi_m/(1 +
 * Iv^0.5)), Iv > 0; fitted for mu_m >= 0.36 */
double lub_dem_mu(double Iv, double phi_m);
double lub_dem_eta22(double psi); /* 0 <= psi < 1 */
double lub_dem_lambda33(double phi, double phi_rcp);

/* Miller & Morris (2006) SBM closure (2.41h,i). */
typedef struct {
    double K_s, K_n, lambda_grad, lambda_vort, phi_m;
} lub_mm_params;
lub_mm_params lub_mm_default(void);
double lub_mm_eta_p(const lub_mm_params *m, double psi); /* particle shear viscosity */
double lub_mm_eta_n(const lub_mm_params *m, double psi); /* eta_n = K_n (psi/(1-psi))^2 */

#endif

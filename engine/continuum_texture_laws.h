/* continuum_texture_laws.h — parameters of the texture models as functions of the volume
 * fraction (Ozenda thesis, seed 003), and the per-phi fits of the thesis tables.
 *
 *  M3 laws: depletion angle (3.10) -> alpha = tan(2 theta_e) and material laws (3.16), with
 *           the constants of Table 3.3 (phi_m = 0.571, delta_e = 0.661 rad, beta_bar = 0.152,
 *           eta_e_bar = 0.0213 Pa.s, omega = 0.652). eta_e_bar is dimensional and belongs to
 *           the thesis's eta0 = 1.03 Pa.s; eta(phi) scales with the eta0 given.
 *           Erratum E3: the printed (3.11) alpha = tan(1.32 phi + 2.48 phi^2) rounds the
 *           exact coefficients 2 delta_e = 1.322 and 2(pi/4 - delta_e phi_m)/phi_m^2 = 2.503;
 *           we evaluate (3.10) itself.
 *  M4 laws: (4.9) in psi = phi/phi_m with Table 4.1 (a = 0.6, b = 2, omega = 0.28,
 *           eta_e_bar = 0.21, delta1_bar = 0.27, delta2_bar = -0.8, beta_bar = 0.05, 0.45,
 *           -0.19). phi_m only enters the Einstein term of eta. The singular factors are
 *           evaluated as psi/(1-psi) (+ b psi) to avoid cancellation (note §5 N4).
 *  Tables: Table 3.2 (M3 per-phi fits, eta0 = 1.03) and Table 4.2 (M4 per-phi fits, a = 0.6,
 *           Blanc phi_m = 0.535, eta0 = 1.02), rows phi = 0.30, 0.40, 0.44, 0.47, 0.50.
 *
 * Functions return 0, or -1 with a static message in *why for arguments outside the domain
 * (phi or psi must be in ]0,1[ of the divergence, table rows must exist). Pure.
 */
#ifndef LUBDEM_CONTINUUM_TEXTURE_LAWS_H
#define LUBDEM_CONTINUUM_TEXTURE_LAWS_H

#include "continuum_texture.h"

typedef struct {
    double phi_m, delta_e, beta_bar, eta_e_bar, omega;
} lub_m3_laws;

typedef struct {
    double a, b, omega, eta_e_bar, delta1_bar, delta2_bar, beta1_bar, beta2_bar, beta3_bar;
} lub_m4_laws;

lub_m3_laws lub_m3_laws_thesis(void); /* Table 3.3 */
lub_m4_laws lub_m4_laws_thesis(void); /* Table 4.1 */

/* alpha(phi) = tan(2 theta_e(phi)) from (3.10). Requires 0 <= phi < phi_m. */
double lub_m3_alpha(const lub_m3_laws *L, double phi);

/* The range of phi on which the thesis fitted the M3 laws (3.10), (3.16): its Table 3.2 rows
 * 0.30 ... 0.50 (Fig. 3.11). Outside they are an extrapolation, and a poor one towards phi -> 0:
 * beta(0) = beta_bar while alpha -> 0, so eta_app - eta ~ eta_e beta/alpha^2 ~ 1/phi^2 and the
 * steady eta_app is not monotone in phi (58.4 eta0 at psi = 0.01, 1.80 at 0.21, 2.13 at 0.31). */
#define LUB_M3_LAWS_PHI_FIT_MIN 0.30
#define LUB_M3_LAWS_PHI_FIT_MAX 0.50

/* M3 parameters at phi (0 < phi < phi_m), eta0 in Pa.s. */
int lub_m3_from_laws(const lub_m3_laws *L, double phi, double eta0, lub_texture_params *out,
                     const char **why);
/* M4 parameters at psi (0 < psi < 1); phi_m for the Einstein term; eta0 in Pa.s. */
int lub_m4_from_laws(const lub_m4_laws *L, double psi, double phi_m, double eta0,
                     lub_texture_params *out, const char **why);

/* Table rows (phi must equal one of the tabulated fractions to 1e-9). torque_mNm: the
 * imposed torque T_m of the experiment, 1e-3 N.m (may be NULL). */
int lub_m3_table32(double phi, lub_texture_params *out, double *torque_mNm, const char **why);
int lub_m4_table42(double phi, lub_texture_params *out, double *torque_mNm, const char **why);

/* The tabulated fractions: i = 0..4 -> 0.30, 0.40, 0.44, 0.47, 0.50 (NAN outside). */
double lub_texture_table_phi(int i);

#endif

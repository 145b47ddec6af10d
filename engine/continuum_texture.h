/* continuum_texture.h — the texture-tensor rheology of Ozenda (thesis seed 003) in simple shear.
 *
 * One kernel covers both models of the thesis:
 *   M4 (chapter 4): Gordon–Schowalter derivative with slip parameter a in ]0,1], stress with all
 *       Hand terms (delta1, delta2, beta1, beta2, beta3), eqs (4.4)–(4.7);
 *   M3 (chapter 3): the special case a = 1, delta1 = alpha, beta1 = beta, beta2 = beta3 =
 *       delta2 = 0 (thesis [L1912]), eqs (3.7), (3.8), (3.14), (3.15).
 *
 * Simple shear u = (gd y, 0, 0), s = sgn(gd), strain gamma = int |gd| dt. The cage deformation
 * gamma_e has only the in-plane components (xx, yy, xy) for an isotropic initial state.
 * The model is rate-independent: in the strain variable the evolution is linear with constant
 * coefficients for a constant sign s, and every stress is |gd| times a function of the state and
 * s. All functions here are pure (no allocation, no global state).
 *
 * Errata of the note continuum-models.md §6 applied here:
 *   E5 — (4.4c) is printed with "-((1-a)/2) gd gamma_xx"; the Gordon–Schowalter derivative and
 *        the thesis's own stationary solution (4.6) need "+((1-a)/2) gd gamma_xx" (with the
 *        printed sign (4.6) is not a fixed point). We use the corrected sign.
 *   E1 — (3.14) (strain solution of M3) lacks gamma_xy(0) and has a spurious gamma_xx(0) factor;
 *        we use the closed form of the corrected linear system (a = 1 limit of the M4 solution).
 *   E2 — the depletion-angle formula along a transient needs 2 gamma_xy in the denominator; we
 *        use the equivalent principal-axis form theta_e = atan2(2 g_xy, g_xx - g_yy)/2.
 *   E4 — p(theta) amplitude: we return the fabric eigenvalue gap mu+ - mu- (= the printed (3.19)
 *        amplitude 1/sqrt(1+alpha^2) at steady state); the literal derivation gives twice that.
 *
 * Units: stresses in Pa, viscosities in Pa.s, rates in 1/s; delta*, beta*, a dimensionless.
 */
#ifndef LUBDEM_CONTINUUM_TEXTURE_H
#define LUBDEM_CONTINUUM_TEXTURE_H

typedef struct {
    double a;      /* Gordon–Schowalter parameter, 0 < a <= 1 (a = 1: upper convected, M3) */
    double delta1; /* > 0: relaxation per unit strain (M3: alpha); depletion angle atan(delta1)/2 */
    double delta2; /* dimensionless (M3: 0) */
    double beta1;  /* dimensionless (M3: beta) */
    double beta2;  /* dimensionless (M3: 0) */
    double beta3;  /* dimensionless (M3: 0) */
    double eta;    /* Pa.s, viscous (instantaneous) part, > 0 */
    double eta_e;  /* Pa.s, elastic-cage viscosity, >= 0 */
} lub_texture_params;

/* In-plane components of the cage deformation gamma_e (gamma_zz = gamma_xz = gamma_yz = 0). */
typedef struct {
    double xx, yy, xy;
} lub_texture_state;

/* Stresses per unit |gd| (rate independence): sigma = |gd| * (these). eta_app = sigma_xy/gd. */
typedef struct {
    double eta_app; /* sigma_xy / gd, Pa.s (includes the viscous part eta) */
    double n1;      /* N1 / |gd| = (tau_xx - tau_yy)/|gd|, Pa.s */
    double n2;      /* N2 / |gd| = (tau_yy - tau_zz)/|gd|, Pa.s (tau_zz = 0 in this model) */
    double pp;      /* particle pressure p_p / |gd| = -(tau_xx + tau_yy + tau_zz)/(3|gd|), Pa.s */
} lub_texture_stress;

/* Microstructure descriptors of a state (no NaN for any finite state, including 0). */
typedef struct {
    double theta_e;    /* depletion angle, rad: principal direction of gamma_e (E2) */
    double fabric_gap; /* mu+ - mu- of <n n> = b_e^{-1}/tr(b_e^{-1}) in the shear plane (E4) */
    double b_min;      /* smallest eigenvalue of b_e = I/a + gamma_e (SPD monitor, must stay > 0) */
} lub_texture_micro;

/* Returns NULL if p is inside the model's domain, else a static message naming the field
 * ("a must be in ]0,1]", ...). */
const char *lub_texture_check(const lub_texture_params *p);

/* M3 parameters (alpha, beta, eta_e, eta) expressed as the equivalent M4 set. */
lub_texture_params lub_texture_m3(double alpha, double beta, double eta_e, double eta);

/* Stationary state (4.6) for the sign s (+1 or -1). */
lub_texture_state lub_texture_steady_state(const lub_texture_params *p, int s);

/* Stationary stresses per |gd| (closed form (4.7); (3.8) for M3). */
lub_texture_stress lub_texture_steady_stress(const lub_texture_params *p);

/* d(gamma_e)/d(gamma) for constant sign s (corrected (4.4), E5). */
lub_texture_state lub_texture_rhs(const lub_texture_params *p, int s, lub_texture_state g);

/* Exact state after a strain increment dgamma >= 0 at constant sign s, from g0 (closed form of
 * the linear system: eigenvalues -delta1 and -delta1 +- i sqrt(1-a^2); the a -> 1 limit is the
 * chapter-3 Jordan-block solution). Evaluated as the free decay of g0 (lub_texture_free) plus the
 * response from 0, the latter by a power series when sqrt(delta1^2 + 1 - a^2) dgamma <= 1 and by
 * expm1-type closed forms otherwise: no cancellation for any delta1 > 0 and a in ]0,1] (until
 * 2026-12-07 it was steady state + decaying deviation, which lost every digit of the O(gamma^2)
 * g_xx at a = 1, delta1 = 1e-8, where the steady g_xx is 2e16). */
lub_texture_state lub_texture_advance(const lub_texture_params *p, int s, lub_texture_state g0,
                                      double dgamma);

/* The homogeneous part of the same system (the source 1 of d g_xy/d gamma removed): the
 * evolution of the difference d0 between two solutions over dgamma >= 0 at sign s. Linear in
 * d0; 0 once e^{-delta1 dgamma} underflows. */
lub_texture_state lub_texture_free(const lub_texture_params *p, int s, lub_texture_state d0,
                                   double dgamma);

/* Stresses per |gd| in state g when shearing with sign s (4.5); for a pause report with the
 * sign of the last motion (the values the stress jumps back to on restart). */
lub_texture_stress lub_texture_stress_of(const lub_texture_params *p, int s, lub_texture_state g);

lub_texture_micro lub_texture_micro_of(const lub_texture_params *p, lub_texture_state g);

#endif

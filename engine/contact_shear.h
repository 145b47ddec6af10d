/* contact_shear.h — internal interface of the tangential part of the lubricated contact law
 * (notes §1.7, §1.8, §3; paper eq. 23-33). Forces are on body 1, in the caller's units.
 * Pure functions, no allocation, no global state. */
#ifndef LUBDEM_CONTACT_SHEAR_H
#define LUBDEM_CONTACT_SHEAR_H

#include "vec3.h"

/* Carry the stored shear force fs_prev (tangential to n_prev) into the current pair frame
 * (notes §1.8): tilt by the exact minimal rotation n_prev -> n (axis theta1 = n_prev x n),
 * then twist about n by tau = dt/2 (w1 + w2).n (theta2; Cayley form, angle tau + O(tau^3)),
 * then project onto the plane normal to n and rescale to |fs_prev| (round-off clean-up).
 * Differs from Yade (two first-order rotations F <- F - F x theta, no re-projection, notes
 * §11 P11): the map is an exact isometry, a rigidly rotating pair keeps |F_s| to round-off,
 * and the direction follows the rigid rotation to O(theta^3) per step (Yade: O(theta^2)). */
vec3 lub_shear_rotate(vec3 fs_prev, vec3 n_prev, vec3 n, vec3 w1, vec3 w2, double dt);

/* Objective shear displacement increment over dt (notes §1.7):
 *   alpha_r = (r1 + r2)/(r1 + r2 + un),  w = alpha_r (v2 - v1) - (r1 w1 + r2 w2) x n,
 *   du_s = [w - (w.n) n] dt.  Zero for any rigid-body motion of the pair. */
vec3 lub_shear_increment(vec3 v1, vec3 v2, vec3 w1, vec3 w2, double r1, double r2, double un,
                         vec3 n, double dt);

/* nu_t(u) from delta = ln(u/a) and x = e^delta (x must equal exp(delta)), notes §3.1:
 * (pi eta a / 2)[-2 + (2 + x)(ln(2 + x) - delta)], evaluated without cancellation for every
 * gap (log1p for x >= 1, a series for x > 1e5). Any finite delta: for a compressed contact
 * x may be subnormal or 0 (delta < -745) and nu_t ~ (pi eta a)(ln 2 - 1 - delta) grows like
 * -delta, finite (e.g. 3.1e5 pi eta a at delta = -1e5). */
double lub_shear_viscosity_x(double eta, double a, double delta, double x);

typedef struct {
    vec3 fs;         /* total shear force on body 1 = fs_contact + fs_lub (summed here) */
    vec3 fs_contact; /* Coulomb (slider/spring) part */
    vec3 fs_lub;     /* dashpot part */
    int slip;        /* 1 in the slipping branch */
} lub_shear_result;

/* Backward-Euler update of the tangential element (notes §3.2, paper eq. 27, 29, 32) given
 * the trial force Ft = F_r + k_t du_s, nu_t >= 0, kt_dt = k_t dt >= 0, and the Coulomb
 * limit f_limit = mu |F_c| (friction_active = 0: no slider, i.e. the Maxwell branch).
 *  - no friction: F+ = nu_t Ft / (nu_t + k_t dt); contact part 0 (F+ = 0 if both are 0);
 *  - stick (|Ft| <= limit): F+ = Ft, lubrication part 0;
 *  - slip (|Ft| > limit, strict): F_sl = limit Ft / |Ft|, lubrication part
 *    nu_t (Ft - F_sl) / (nu_t + k_t dt) (= F+ - F_sl, the consistent split of notes §3.2.5),
 *    F+ = F_sl + lubrication part (eq. 32). If nu_t + k_t dt = 0, F+ = F_sl. */
void lub_shear_update(vec3 f_trial, double nu_t, double kt_dt, int friction_active, double f_limit,
                      lub_shear_result *out);

#endif

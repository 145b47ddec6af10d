/* contact_shear.c — tangential part of the lubricated contact law (see contact_shear.h).
 *
 * Sign convention (notes §3.3): F_s = k_t v_e is the force on body 1, v_e the elastic part of
 * the displacement of 2 relative to 1. The paper writes F_s = -k_t v_e, so its eq. 26 and 31
 * carry a spurious overall minus sign on v_e+; the force equations 27, 29, 32 are right and
 * are the ones implemented. Eq. 33 (division by |F*|) is not used (notes §11 P6). */
#include "contact_shear.h"

#include "contact_law.h"

#include <math.h>

vec3 lub_shear_rotate(vec3 fs_prev, vec3 n_prev, vec3 n, vec3 w1, vec3 w2, double dt)
{
    const double m0 = v3_norm2(fs_prev);
    if (m0 == 0.0)
        return fs_prev;
    /* tilt: exact minimal rotation n_prev -> n, R = I + [w]x + [w]x^2 / (1 + c),
     * w = n_prev x n (= theta1 of notes §1.8), c = n_prev . n */
    vec3 f = fs_prev;
    const vec3 w = v3_cross(n_prev, n);
    const double c1 = 1.0 + v3_dot(n_prev, n);
    if (c1 > 1e-12) {
        const vec3 wf = v3_cross(w, f);
        f = v3_add(f, v3_axpy(wf, 1.0 / c1, v3_cross(w, wf)));
    }
    /* twist: rotation about n by tau = dt/2 (w1 + w2).n (theta2 of notes §1.8), in the
     * rational (Cayley) form, an exact isometry with angle 2 atan(tau/2) = tau + O(tau^3) */
    const double tau = 0.5 * dt * v3_dot(v3_add(w1, w2), n);
    const double q = 0.25 * tau * tau;
    f = v3_scale(v3_axpy(v3_scale(f, 1.0 - q), tau, v3_cross(n, f)), 1.0 / (1.0 + q));
    /* clean-up of round-off: back onto the tangent plane of n, norm of fs_prev */
    f = v3_axpy(f, -v3_dot(f, n), n);
    const double m1 = v3_norm2(f);
    if (!(m1 > 0.0))
        return v3(0.0, 0.0, 0.0); /* fs_prev was (numerically) along n: no tangential part */
    const double r = m1 / m0;
    if (fabs(r - 1.0) < 1e-8)
        return v3_scale(f, 1.5 - 0.5 * r); /* 1/sqrt(r) to O((r-1)^2): round-off only */
    return v3_scale(f, 1.0 / sqrt(r));
}

vec3 lub_shear_increment(vec3 v1, vec3 v2, vec3 w1, vec3 w2, double r1, double r2, double un,
                         vec3 n, double dt)
{
    const double alpha_r = (r1 + r2) / (r1 + r2 + un);
    vec3 w = v3_scale(v3_sub(v2, v1), alpha_r);
    w = v3_sub(w, v3_cross(v3_axpy(v3_scale(w1, r1), r2, w2), n));
    w = v3_axpy(w, -v3_dot(w, n), n);
    return v3_scale(w, dt);
}

double lub_shear_viscosity_x(double eta, double a, double delta, double x)
{
    double br; /* -2 + (2 + x) ln((2 + x)/x) */
    if (x < 1e-3) {
        /* ln(2 + x) = ln 2 + x/2 - x^2/8 + x^3/24 - ..., truncation < x^4/64 < 2e-14 */
        const double l2x = 0.69314718055994530942 + x * (0.5 - x * (0.125 - x / 24.0));
        br = (2.0 + x) * (l2x - delta) - 2.0;
    } else if (delta < 0.0) {
        br = (2.0 + x) * (log(2.0 + x) - delta) - 2.0; /* no cancellation for x < 1 */
    } else if (x < 1e5) {
        br = (2.0 + x) * log1p(2.0 / x) - 2.0; /* ~2/x: relative error ~ x eps */
    } else {
        const double y = 2.0 / x; /* (2+x)ln(1+y) - 2 = y (1 - y/3 + y^2/6 - ...) */
        br = y * (1.0 - y / 3.0 + y * y / 6.0);
    }
    return 0.5 * LUB_PI * eta * a * br;
}

void lub_shear_update(vec3 f_trial, double nu_t, double kt_dt, int friction_active, double f_limit,
                      lub_shear_result *out)
{
    const vec3 zero = v3(0.0, 0.0, 0.0);
    const double den = nu_t + kt_dt;
    out->slip = 0;
    if (!friction_active) {
        /* Maxwell element, backward Euler (eq. 27). */
        out->fs_contact = zero;
        out->fs_lub = (den > 0.0) ? v3_scale(f_trial, nu_t / den) : zero;
        out->fs = out->fs_lub;
        return;
    }
    const double lim = (f_limit > 0.0) ? f_limit : 0.0;
    const double ft2 = v3_norm2(f_trial);
    if (!(ft2 > lim * lim)) {
        /* Stick (eq. 29): the dashpot is blocked. */
        out->fs_contact = f_trial;
        out->fs_lub = zero;
        out->fs = f_trial;
        return;
    }
    /* Slip (eq. 32), strict test so that |F*| > 0 here. */
    out->slip = 1;
    const vec3 f_sl = v3_scale(f_trial, lim / sqrt(ft2));
    out->fs_contact = f_sl;
    out->fs_lub = (den > 0.0) ? v3_scale(v3_sub(f_trial, f_sl), nu_t / den) : zero;
    out->fs = v3_add(f_sl, out->fs_lub);
}

double lub_shear_viscosity(double eta, double a, double delta)
{
    return lub_shear_viscosity_x(eta, a, delta, exp(delta));
}

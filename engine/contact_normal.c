/* contact_normal.c — normal part of the lubricated contact law: backward Euler (theta = 1)
 * of the visco-elastic coupling of Chèvremont, Bodiguel & Chareyre.
 *
 * Dimensionless equation (notes §2.2, paper eq. 14 with tau = 3 pi eta a / (2 g), notes
 * §2.11.2 — the printed tau = eta a / g lacks the factor 3 pi / 2):
 *     dx/dt* = x R(x, s),   R = s + a_c e - (1 + a_c) x,   a_c = alpha if x < e else 0.
 * Backward Euler (paper eq. 16-17, notes §2.3):
 *     A x^2 + B x - C = 0,  A = 1 + a_c,  B = 1/h - s - a_c e,  C = x_prev / h.
 *
 * Design (notes §2.6, §11 P1, P5, P7, P21):
 *  - the branch (contact or not) is decided BEFORE solving, exactly, from the sign of the
 *    (monotone, continuous) objective at x = e — no trial-and-retry and no step splitting;
 *  - the root is computed in a scaled, cancellation-free closed form: multiplying by h,
 *        b = h B = 1 - h (s + a_c e),   q = 4 A h x_prev,   sqrt(b^2 + q) = h sqrt(D),
 *        b > 0 :  x = 2 x_prev / (b + sqrt(b^2 + q))     -> delta = delta_prev + ln(2/(b+..))
 *        b <= 0:  x = (|b| + sqrt(b^2 + q)) / (2 A h)
 *    Neither form subtracts nearly equal numbers. In the b > 0 form x_prev enters only as a
 *    factor, so delta_prev may be -1000 (x_prev = 0 in double) and the result is still
 *    exact in log form (q underflowing is harmless when b^2 >> q);
 *  - the bracketed log-space solve is the fallback when the closed form cannot be trusted
 *    (|b| < 1e-140 and q < 1e-290: both terms of the root underflow; non-finite b, q; b <= 0
 *    with x underflowing), and the reference solver of the tests;
 *  - the result is clamped to [LUB_DELTA_MIN, LUB_DELTA_MAX] so that x = exp(delta) is a
 *    normal double: forces, nu_t and torques stay finite (notes §11 P5).
 */
#include "contact_law.h"
#include "contact_normal.h"

#include <float.h>
#include <math.h>

/* The branch test and the closed form are exact as long as one of the two terms of the root
 * is representable (see header comment). */
#define B_TINY 1e-140
#define Q_TINY 1e-290

static double clamp_delta(double d)
{
    if (d < LUB_DELTA_MIN)
        return LUB_DELTA_MIN;
    if (d > LUB_DELTA_MAX)
        return LUB_DELTA_MAX;
    return d;
}

double lub_normal_rate(double delta, double s, double e, double alpha)
{
    double x = exp(delta);
    double ac = (x < e) ? alpha : 0.0; /* e = 0: never (x >= 0) */
    return s + ac * e - (1.0 + ac) * x;
}

/* Objective of the log-space solve, divided by x+ (notes §2.4 with theta = 1):
 *   f(d) = R(e^d, s) + (1/h) (e^{d_prev - d} - 1),   strictly decreasing in d.
 * Two groupings, chosen so that the only cancellation left is the one of the problem data:
 *  - E = e^{d_prev - d} >= 1/2: (s + a_c e - A x) + (1/h) expm1(d_prev - d) — expm1 keeps full
 *    precision when d ~ d_prev (small h);
 *  - E < 1/2: (s + a_c e - 1/h) + (1/h) E - A x — when s + a_c e ~ 1/h the first bracket is
 *    the small number the root depends on (same rounding as b = 1 - h (s + a_c e) in the
 *    closed form); grouping it with expm1 ~ -1 would cancel to zero. */
static double objective(double d, double dprev, double s, double hinv, double e, double alpha)
{
    const double x = exp(d);
    const double ac = (x < e) ? alpha : 0.0;
    const double A = 1.0 + ac;
    if (!(hinv > 0.0))
        return s + ac * e - A * x;
    const double E = exp(dprev - d);
    if (E >= 0.5)
        return (s + ac * e - A * x) + hinv * expm1(dprev - d);
    return ((s + ac * e) - hinv) + hinv * E - A * x;
}

static double objective_slope(double d, double dprev, double hinv, double e, double alpha)
{
    double x = exp(d);
    double ac = (x < e) ? alpha : 0.0;
    double fp = -(1.0 + ac) * x;
    if (hinv > 0.0)
        fp -= hinv * exp(dprev - d);
    return fp;
}

double lub_normal_solve_bracketed(double delta_prev, double s, double h, double e, double alpha)
{
    const double hinv = isinf(h) ? 0.0 : 1.0 / h;
#define F(d) objective((d), delta_prev, s, hinv, e, alpha)
    /* 1. Bracket: march from the (clamped) previous value in steps doubling from 1. */
    double c = clamp_delta(delta_prev);
    double fc = F(c);
    double lo, hi;
    if (fc == 0.0)
        return c;
    if (fc > 0.0) { /* root above c */
        lo = c;
        double step = 1.0;
        for (;;) {
            hi = c + step;
            if (hi >= LUB_DELTA_MAX) {
                hi = LUB_DELTA_MAX;
                double fh = F(hi);
                if (fh >= 0.0)
                    return LUB_DELTA_MAX; /* root beyond the clamp */
                break;
            }
            double fh = F(hi);
            if (fh == 0.0)
                return hi;
            if (fh < 0.0)
                break;
            lo = hi;
            step *= 2.0;
        }
    } else { /* root below c */
        hi = c;
        double step = 1.0;
        for (;;) {
            lo = c - step;
            if (lo <= LUB_DELTA_MIN) {
                lo = LUB_DELTA_MIN;
                double fl = F(lo);
                if (fl <= 0.0)
                    return LUB_DELTA_MIN; /* root below the clamp */
                break;
            }
            double fl = F(lo);
            if (fl == 0.0)
                return lo;
            if (fl > 0.0)
                break;
            hi = lo;
            step *= 2.0;
        }
    }
    /* 2. Safeguarded Newton inside [lo, hi] with F(lo) > 0 > F(hi): the Newton step is
     *    rejected for a bisection when it leaves the bracket or does not at least halve the
     *    previous step. Stop on a certified bracket width <= 1e-14 (plus a few ulps of
     *    |delta|, the finest width representable around delta = -700). */
    double d = 0.5 * (lo + hi);
    double dx = hi - lo, dx_old = dx;
    for (int it = 0; it < 400; ++it) {
        const double tol = 1e-14 + 4.0 * DBL_EPSILON * fmax(fabs(lo), fabs(hi));
        double fd = F(d);
        if (fd == 0.0)
            return d;
        if (fd > 0.0)
            lo = d;
        else
            hi = d;
        if (hi - lo <= tol)
            break;
        double fp = objective_slope(d, delta_prev, hinv, e, alpha);
        double dn = d - fd / fp;
        if (!(dn > lo && dn < hi) || fabs(2.0 * fd) > fabs(dx_old * fp)) {
            dx_old = dx;
            dx = 0.5 * (hi - lo);
            d = lo + dx;
            continue;
        }
        dx_old = dx;
        dx = dn - d;
        d = dn;
        if (fabs(dx) < 0.25 * tol) {
            /* Newton has converged: certify by evaluating on both sides of d. */
            double l2 = d - 0.5 * tol, h2 = d + 0.5 * tol;
            if (l2 > lo) {
                double f2 = F(l2);
                if (f2 == 0.0)
                    return l2;
                if (f2 > 0.0)
                    lo = l2;
                else
                    hi = l2;
            }
            if (h2 < hi) {
                double f2 = F(h2);
                if (f2 == 0.0)
                    return h2;
                if (f2 > 0.0)
                    lo = h2;
                else
                    hi = h2;
            }
            if (hi - lo <= tol)
                break;
            d = 0.5 * (lo + hi);
            dx = dx_old = hi - lo;
        }
    }
#undef F
    return 0.5 * (lo + hi);
}

double lub_normal_solve_ex(double delta_prev, double s, double h, double e, double alpha,
                           int *contact, double *x_out)
{
    if (!(e > 0.0))
        e = 0.0; /* e <= 0 or NaN: smooth spheres, contact never (notes §2.8) */
    if (!(alpha >= 0.0))
        alpha = 0.0;
    if (isinf(h)) {
        /* No normal lubrication (or eta = 0): quasi-static balance R = 0. */
        const double x_floor = exp(LUB_DELTA_MIN); /* constant-folded */
        double x;
        if (s >= e && s > 0.0) {
            x = s;
            *contact = 0;
        } else {
            x = (e > 0.0) ? (s + alpha * e) / (1.0 + alpha) : s;
            *contact = 1;
        }
        if (!(x >= x_floor)) {
            /* No positive static gap: (1+alpha) x = s + alpha e <= 0. Asperities fully
             * crushed (or smooth spheres overlapping): the gap is held at the floor and the
             * whole normal force g a (s - x) is a contact force ("hard-core" regime). */
            *contact = 1;
            *x_out = x_floor;
            return LUB_DELTA_MIN;
        }
        if (x > exp(LUB_DELTA_MAX)) {
            *x_out = exp(LUB_DELTA_MAX);
            return LUB_DELTA_MAX;
        }
        *x_out = x;
        return log(x);
    }

    const double xp = exp(delta_prev); /* may underflow to 0 (delta_prev < -745) */

    /* Exact branch choice (notes §2.6, §2.7): the no-contact objective is decreasing and
     * equals the contact one at x = e, so the root is >= e iff f0(ln e) >= 0, i.e.
     * h (s - e) - 1 + x_prev/e >= 0. */
    int c = 0;
    if (e > 0.0) {
        double r = (xp >= DBL_MIN) ? xp / e : exp(delta_prev - log(e));
        c = (h * (s - e) - 1.0 + r < 0.0);
    }
    const double ac = c ? alpha : 0.0;
    const double A = 1.0 + ac;
    const double b = 1.0 - h * (s + ac * e);
    const double q = 4.0 * A * h * xp;

    double d = NAN, x = NAN;
    if (isfinite(b) && isfinite(q) && (fabs(b) >= B_TINY || q >= Q_TINY)) {
        const double sq = sqrt(b * b + q);
        if (isfinite(sq)) {
            if (b > 0.0) {
                const double den = b + sq;
                x = 2.0 * xp / den;
                if (x >= DBL_MIN) {
                    d = log(x);
                } else {
                    d = delta_prev + log(2.0 / den); /* scaled: x_prev may be e^-1000 */
                    x = NAN;
                }
            } else {
                x = (sq - b) / (2.0 * A * h);
                if (x >= DBL_MIN && isfinite(x))
                    d = log(x);
            }
        }
    }
    if (!isfinite(d)) {
        /* Fallback: bracketed log-space solve (rare: both terms of the root underflow). */
        d = lub_normal_solve_bracketed(delta_prev, s, h, e, alpha);
        x = NAN;
    }
    if (d < LUB_DELTA_MIN || d > LUB_DELTA_MAX || !(x == x)) {
        d = clamp_delta(d);
        x = exp(d);
    }
    /* The flag means x+ < e exactly (the branch formula and the flag can only disagree by
     * round-off when x+ = e to the last bits, where both branches give the same root). */
    *contact = (e > 0.0) && (x < e);
    *x_out = x;
    return d;
}

double lub_normal_solve(double delta_prev, double s, double h, double e, double alpha,
                        int *contact)
{
    int c = 0;
    double x;
    double d = lub_normal_solve_ex(delta_prev, s, h, e, alpha, &c, &x);
    if (contact)
        *contact = c;
    return d;
}

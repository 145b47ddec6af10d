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
 *    factor: whenever x_prev or x+ is not a normal double (delta_prev < ln DBL_MIN ~ -708)
 *    the root is taken in log form, delta = delta_prev + ln(2/(b + sqrt(b^2 + q))), so
 *    delta_prev may be -1e5 (x_prev = 0 in double) and the result is still exact; q is then
 *    formed as exp(delta_prev + ln(4 A h)) (never from a subnormal x_prev, which has lost
 *    digits) and underflowing to 0 is harmless when b^2 >> q;
 *  - the bracketed log-space solve is the fallback when the closed form cannot be trusted
 *    (|b| < 1e-140 and q < 1e-290: both terms of the root underflow; non-finite b, q; b <= 0
 *    with x underflowing), and the reference solver of the tests. Its objective uses only
 *    differences of delta (e^{delta_prev - delta}), so it works at any depth;
 *  - NO floor on the gap (notes §2.6 item 4, §11 P5): a permanently compressed pair keeps
 *    decaying in delta; x = exp(delta) may be subnormal or 0, which the forces tolerate, and
 *    nu_t and the torques are evaluated from delta. The result is only clamped to the guard
 *    range [LUB_DELTA_MIN, LUB_DELTA_MAX] = [-1e7, 700] (finite under pathological input,
 *    exp(delta) never overflows). Without normal lubrication (h = +inf) there is no gap
 *    dynamics and the hard-core case is held at the fixed LUB_DELTA_STATIC_FLOOR = -700.
 */
#include "contact_law.h"
#include "contact_normal.h"

#include <float.h>
#include <stddef.h>
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
 * Evaluated only through differences of delta (e^{d_prev - d}), never through x_prev. Two
 * groupings, chosen so that the only cancellation left is the one of the problem data:
 *  - E = e^{d_prev - d} >= 1/2: (s + a_c e - A x) + (1/h) expm1(d_prev - d) — expm1 keeps full
 *    precision when d ~ d_prev (small h);
 *  - E < 1/2: (s + a_c e - 1/h) + (1/h) E - A x — when s + a_c e ~ 1/h the first bracket is
 *    the small number the root depends on (same rounding as b = 1 - h (s + a_c e) in the
 *    closed form); grouping it with expm1 ~ -1 would cancel to zero.
 * Deep gaps: when both exponential terms A x = e^{L2} and E/h = e^{L1} are below 1e-250
 * (x and/or E underflowing, e.g. d_prev = -1e5 with s + a_c e = 1/h, where the root is
 * d_prev/2), f is returned scaled by the positive factor e^{-m}, m = max(L1, L2): the sign
 * (all the bisection needs) is exact instead of an underflowed 0, and *fp (the slope, same
 * scale) keeps the Newton ratio f/f' exact. The constant term is capped at e^700 in that
 * scale (sign kept). fp may be NULL. */
#define TERM_TINY 1e-250
static double objective(double d, double dprev, double s, double hinv, double e, double alpha,
                        double *fp)
{
    const double x = exp(d);
    const double ac = (x < e) ? alpha : 0.0;
    const double A = 1.0 + ac;
    if (!(hinv > 0.0)) {
        if (fp)
            *fp = -A * x;
        return s + ac * e - A * x;
    }
    const double E = exp(dprev - d);
    const double t1 = hinv * E, t2 = A * x;
    if (t1 < TERM_TINY && t2 < TERM_TINY) {
        const double L1 = log(hinv) + (dprev - d), L2 = log(A) + d;
        const double m = fmax(L1, L2);
        const double C = (s + ac * e) - hinv;
        const double t0 = (C == 0.0) ? 0.0 : copysign(exp(fmin(log(fabs(C)) - m, 700.0)), C);
        const double u1 = exp(L1 - m), u2 = exp(L2 - m);
        if (fp)
            *fp = -(u1 + u2);
        return t0 + u1 - u2;
    }
    if (fp)
        *fp = -t2 - t1;
    if (E >= 0.5)
        return (s + ac * e - t2) + hinv * expm1(dprev - d);
    return ((s + ac * e) - hinv) + t1 - t2;
}

double lub_normal_solve_bracketed(double delta_prev, double s, double h, double e, double alpha)
{
    const double hinv = isinf(h) ? 0.0 : 1.0 / h;
    /* lowest delta searched: the guard LUB_DELTA_MIN, or the static floor when there are no
     * dynamics (h = +inf, same convention as lub_normal_solve_ex) */
    const double dmin = isinf(h) ? LUB_DELTA_STATIC_FLOOR : LUB_DELTA_MIN;
#define F(d) objective((d), delta_prev, s, hinv, e, alpha, NULL)
    /* 1. Bracket: march from the (clamped) previous value in steps doubling from 1 (a root at
     *    delta ~ -1e5 below delta_prev ~ 0 is bracketed after ~17 doublings). */
    double c = clamp_delta(delta_prev);
    if (c < dmin)
        c = dmin;
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
            if (lo <= dmin) {
                lo = dmin;
                double fl = F(lo);
                if (fl <= 0.0)
                    return dmin; /* root below the guard (or the static floor) */
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
     *    previous step (objective() scales f and f' alike when its terms underflow).
     *    Stop on a certified bracket width <= 1e-14 plus a few ulps of |delta| (the finest
     *    width representable: 1e-13 at delta = -700, 6e-11 at -1e5). */
    double d = 0.5 * (lo + hi);
    double dx = hi - lo, dx_old = dx;
    for (int it = 0; it < 400; ++it) {
        const double tol = 1e-14 + 4.0 * DBL_EPSILON * fmax(fabs(lo), fabs(hi));
        double fp;
        double fd = objective(d, delta_prev, s, hinv, e, alpha, &fp);
        if (fd == 0.0)
            return d;
        if (fd > 0.0)
            lo = d;
        else
            hi = d;
        if (hi - lo <= tol)
            break;
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
        /* No normal lubrication (or eta = 0): quasi-static balance R = 0, no gap dynamics. */
        const double x_floor = exp(LUB_DELTA_STATIC_FLOOR); /* 9.9e-305, constant-folded */
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
             * crushed (or smooth spheres overlapping): the gap is held at the fixed static
             * floor and the whole normal force g a (s - x) is a contact force ("hard-core"
             * regime). A fixed floor is exact here: nothing depends on the gap history. */
            *contact = 1;
            *x_out = x_floor;
            return LUB_DELTA_STATIC_FLOOR;
        }
        if (x > exp(LUB_DELTA_MAX)) {
            *x_out = exp(LUB_DELTA_MAX);
            return LUB_DELTA_MAX;
        }
        *x_out = x;
        return log(x);
    }

    /* x_prev as a double: subnormal for delta_prev in (-745, -708) (digits lost), 0 below.
     * It is used directly only when it is a normal double. */
    const double xp = exp(delta_prev);
    const int xp_normal = (xp >= DBL_MIN);

    /* Exact branch choice (notes §2.6, §2.7): the no-contact objective is decreasing and
     * equals the contact one at x = e, so the root is >= e iff f0(ln e) >= 0, i.e.
     * h (s - e) - 1 + x_prev/e >= 0. */
    int c = 0;
    if (e > 0.0) {
        double r = xp_normal ? xp / e : exp(delta_prev - log(e));
        c = (h * (s - e) - 1.0 + r < 0.0);
    }
    const double ac = c ? alpha : 0.0;
    const double A = 1.0 + ac;
    const double b = 1.0 - h * (s + ac * e);
    /* q = 4 A h x_prev; in log form when x_prev is not normal (exp of a sum: relative error
     * ~ ulp(delta_prev), as good as delta_prev itself) */
    const double q = xp_normal ? 4.0 * A * h * xp : exp(delta_prev + log(4.0 * A * h));

    double d = NAN, x = NAN;
    if (isfinite(b) && isfinite(q) && (fabs(b) >= B_TINY || q >= Q_TINY)) {
        const double sq = sqrt(b * b + q);
        if (isfinite(sq)) {
            if (b > 0.0) {
                const double den = b + sq;
                x = 2.0 * xp / den;
                if (xp_normal && x >= DBL_MIN) {
                    d = log(x);
                } else {
                    /* scaled (log) form: x_prev may be e^-1e5 (0 in double); x+ is recomputed
                     * below as exp(d), subnormal or 0 */
                    d = delta_prev + log(2.0 / den);
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
        x = exp(d); /* subnormal or 0 for d < -708: harmless in R+ and the forces */
    }
    /* The flag means x+ < e exactly, i.e. delta+ < ln e (the branch formula and the flag can
     * only disagree by round-off when x+ = e to the last bits, where both branches give the
     * same root). x+ = 0 after underflow gives contact for e > 0, never for e = 0. */
    *contact = (e > 0.0) && (x < e);
    *x_out = x;
    return d;
}

double lub_normal_solve(double delta_prev, double s, double h, double e, double alpha, int *contact)
{
    int c = 0;
    double x;
    double d = lub_normal_solve_ex(delta_prev, s, h, e, alpha, &c, &x);
    if (contact)
        *contact = c;
    return d;
}

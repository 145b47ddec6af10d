/* test_law_normal.c — normal part of the lubricated contact law (engine/contact_normal.c).
 *  1. closed form vs bracketed log-space solve over 2e5 random inputs (x_prev down to 1e-300,
 *     delta_prev = -700 / -720 (subnormal x_prev) / -1000 / -1e4 / -1e5 and log-uniform in
 *     [-1e5, -700] (x_prev = 0 in double), s in [-0.5, 2], h in [1e-12, 1e12], eps in
 *     [0, 0.2], alpha in [1e-3, 1e3]): |delta_closed - delta_bracketed| <= 1e-12 + 8 ulp(delta)
 *     (the spacing of doubles is 1.5e-11 at delta = -1e5) + the conditioning allowance;
 *  2. contact flag exact (x+ < e) away from the boundary; never with eps = 0;
 *  3. incremental stiffness 0 <= dx+/ds <= 1 (|dF_n/du_n| <= g, the time-step argument of
 *     notes §7) on random inputs;
 *  4. quasi-static (h = inf) branches and their static floor, deep (no floor) decay, the
 *     fallback at any depth, the guard clamp, and the analytic sedimentation limit;
 *  5. many steps of a compressed pair (s < -alpha e; smooth s < 0): delta decreases by
 *     exactly -ln(1 - h (s + alpha_c e)) per step once x << |s|, across the subnormal range
 *     of x (delta in (-745, -708)) and down to delta < -1e4 (no floor at -700).
 * Prints name=value lines; exits non-zero on failure. */
#include "contact_law.h"
#define LAW_CHECK_PRINT_LIMIT 20
#include "law_check.h"
#include "law_rng.h"

#include <float.h>
#include <math.h>
#include <stdio.h>

static void random_inputs(law_rng *r, int i, double *dprev, double *s, double *h, double *e,
                          double *alpha)
{
    if (i % 50 == 0)
        *dprev = -700.0;
    else if (i % 50 == 1)
        *dprev = -1000.0;
    else if (i % 50 == 2)
        *dprev = -1.0e4;
    else if (i % 50 == 3)
        *dprev = -1.0e5;
    else if (i % 50 == 4)
        *dprev = -720.0; /* x_prev subnormal */
    else if (i % 50 == 5)
        *dprev = -law_rng_logrange(r, 700.0, 1.0e5);
    else
        *dprev = log(law_rng_logrange(r, 1e-300, 10.0));
    *s = law_rng_range(r, -0.5, 2.0);
    *h = law_rng_logrange(r, 1e-12, 1e12);
    *e = (law_rng_uniform(r) < 0.2) ? 0.0 : law_rng_range(r, 0.0, 0.2);
    *alpha = law_rng_logrange(r, 1e-3, 1e3);
}

static void test_closed_vs_bracketed(void)
{
    law_rng r = {12345};
    const int N = 200000;
    double max_err = 0.0;
    int n_contact = 0, n_flag_mismatch = 0, n_eps0_contact = 0, n_floor = 0;
    int n_illcond = 0, n_illcond_used = 0, n_deep = 0;
    double max_err_rel = 0.0; /* max |ddelta| / (1e-12 + 8 ulp(delta)) */
    for (int i = 0; i < N; ++i) {
        double dprev, s, h, e, alpha;
        random_inputs(&r, i, &dprev, &s, &h, &e, &alpha);
        int c = -1;
        double dc = lub_normal_solve(dprev, s, h, e, alpha, &c);
        double db = lub_normal_solve_bracketed(dprev, s, h, e, alpha);
        CHECK(isfinite(dc) && isfinite(db), "non-finite dc=%g db=%g", dc, db);
        double err = fabs(dc - db);
        if (err > max_err)
            max_err = err;
        /* Condition number of the root in delta w.r.t. rounding of the terms of f: sum of the
         * term magnitudes over the slope. Where the problem itself is ill-conditioned (the
         * linear coefficient 1 - h (s + a_c e) cancels) no double-precision solver can agree
         * to 1e-12; allow 4 eps kappa there and count such cases. */
        double x = exp(db), xp = exp(dprev);
        double ac = (x < e) ? alpha : 0.0;
        double slope = (1.0 + ac) * x + exp(dprev - db) / h;
        double kappa = (fabs(s) + ac * e + (1.0 + ac) * x + (1.0 + exp(dprev - db)) / h) / slope;
        /* + 8 ulp(delta): both solvers return delta to a few ulps of |delta| (the bracketed
         * solve certifies 1e-14 + 4 eps |delta|) */
        double tol = 1e-12 + 8.0 * DBL_EPSILON * fabs(db) + 4.0 * DBL_EPSILON * kappa;
        (void)xp;
        const double base = 1e-12 + 8.0 * DBL_EPSILON * fabs(db);
        if (4.0 * DBL_EPSILON * kappa > base)
            ++n_illcond;
        if (err > base && err <= tol)
            ++n_illcond_used;
        if (err / base > max_err_rel)
            max_err_rel = err / base;
        CHECK(err <= tol,
              "closed %.17g vs bracketed %.17g (dprev=%g s=%.17g h=%.17g e=%.17g "
              "alpha=%.17g)",
              dc, db, dprev, s, h, e, alpha);
        CHECK(dc >= LUB_DELTA_MIN && dc <= LUB_DELTA_MAX, "delta out of range %g", dc);
        n_contact += c;
        n_floor += (dc == LUB_DELTA_MIN);
        n_deep += (dc < -700.0);
        if (e == 0.0)
            n_eps0_contact += c;
        else if (fabs(db - log(e)) > 1e-12 && c != (db < log(e)))
            ++n_flag_mismatch;
    }
    /* near-critical deep cases: the linear coefficient b = 1 - h s tiny or 0 with x_prev = 0
     * in double, so both terms of the closed form underflow (b = 0) and the bracketed solve
     * (scaled objective) answers; the root is then (delta_prev - ln h)/2. The problem is
     * ill-conditioned in b (d delta/d b = -1/b), so the data are chosen with b exact in both
     * solvers: h = 2^k, s = (1 + j 2^-40)/h, b = -j 2^-40 (smooth pairs, no branch choice).
     * Closed form / fallback vs bracketed, and the exact root for b = 0. */
    int n_crit = 0;
    double max_crit = 0.0;
    for (int i = 0; i < 20000; ++i) {
        double dprev = -law_rng_logrange(&r, 800.0, 1.0e5);
        double h = ldexp(1.0, (int)law_rng_range(&r, -10.0, 10.999));
        double j =
            (i % 4 == 0) ? 0.0 : ((i & 1) ? 1.0 : -1.0) * floor(law_rng_logrange(&r, 1.0, 1e9));
        double s = (1.0 + ldexp(j, -40)) / h;
        double dc = lub_normal_solve(dprev, s, h, 0.0, 1.0, NULL);
        double db = lub_normal_solve_bracketed(dprev, s, h, 0.0, 1.0);
        double err = fabs(dc - db);
        double tol = 1e-12 + 8.0 * DBL_EPSILON * fabs(db);
        CHECK(isfinite(dc) && err <= tol,
              "critical: closed %.17g vs bracketed %.17g "
              "(dprev=%.17g s=%.17g h=%.17g)",
              dc, db, dprev, s, h);
        if (err > max_crit)
            max_crit = err;
        if (1.0 - h * s == 0.0) { /* b = 0 exactly: x = sqrt(x_prev / h) */
            ++n_crit;
            double want = 0.5 * (dprev - log(h));
            CHECK(fabs(db - want) <= tol, "critical b = 0: %.17g vs %.17g", db, want);
        }
    }
    CHECK(n_crit > 4000, "too few b = 0 cases: %d", n_crit);
    printf("normal_critical_deep_cases=20000\nnormal_critical_deep_b0_cases=%d\n", n_crit);
    printf("normal_critical_deep_max_abs_ddelta=%.3e\n", max_crit);
    CHECK(n_flag_mismatch == 0, "contact flag mismatches: %d", n_flag_mismatch);
    CHECK(n_eps0_contact == 0, "contact with eps = 0: %d", n_eps0_contact);
    CHECK(n_contact > N / 10, "too few contact cases sampled: %d", n_contact);
    CHECK(n_floor == 0, "guard clamp reached by ordinary inputs: %d", n_floor);
    CHECK(n_deep > N / 20, "too few deep (< -700) results sampled: %d", n_deep);
    printf("normal_random_cases=%d\n", N);
    printf("normal_closed_vs_bracketed_max_abs_ddelta=%.3e\n", max_err);
    printf("normal_contact_cases=%d\n", n_contact);
    printf("normal_closed_vs_bracketed_max_ddelta_over_1e-12_plus_8ulp=%.3f\n", max_err_rel);
    printf("normal_illconditioned_cases=%d\n", n_illcond);
    printf("normal_cases_beyond_1e-12_plus_8ulp_within_condition_bound=%d\n", n_illcond_used);
    printf("normal_guard_clamp_cases=%d\n", n_floor);
    printf("normal_cases_below_minus700=%d\n", n_deep);
    printf("normal_contact_flag_mismatches=%d\n", n_flag_mismatch);
}

/* Independent check of both solvers: the objective f(d) = R(e^d) + expm1(d_prev - d)/h
 * (notes §2.4) changes sign across the returned delta within +-(1e-12 + 8 ulp). */
static double f_ref(double d, double dprev, double s, double h, double e, double alpha)
{
    /* long double, grouped so that s + a_c e - 1/h (the data's own cancellation) is formed
     * first when e^{dprev-d} is not close to 1 */
    long double x = expl((long double)d);
    long double ac = (x < e) ? alpha : 0.0L;
    long double base = (long double)s + ac * e;
    if (isinf(h))
        return (double)(base - (1.0L + ac) * x);
    long double E = expl((long double)dprev - (long double)d);
    long double hinv = 1.0L / (long double)h;
    if (E > 0.5L)
        return (double)(base - (1.0L + ac) * x +
                        hinv * expm1l((long double)dprev - (long double)d));
    return (double)((base - hinv) + hinv * E - (1.0L + ac) * x);
}

static void test_sign_change(void)
{
    law_rng r = {777};
    int n_checked = 0, n_bad = 0;
    for (int i = 0; i < 50000; ++i) {
        double dprev, s, h, e, alpha;
        random_inputs(&r, i + 2, &dprev, &s, &h, &e, &alpha);
        for (int which = 0; which < 2; ++which) {
            double d = which ? lub_normal_solve_bracketed(dprev, s, h, e, alpha)
                             : lub_normal_solve(dprev, s, h, e, alpha, NULL);
            double tau = 1e-12 + 16.0 * DBL_EPSILON * fabs(d);
            if (d - tau > LUB_DELTA_MIN) {
                ++n_checked;
                if (!(f_ref(d - tau, dprev, s, h, e, alpha) >= 0.0))
                    ++n_bad;
            }
            if (d + tau < LUB_DELTA_MAX && d > LUB_DELTA_MIN) {
                ++n_checked;
                if (!(f_ref(d + tau, dprev, s, h, e, alpha) <= 0.0))
                    ++n_bad;
            }
            if (d == LUB_DELTA_MIN && !(f_ref(d, dprev, s, h, e, alpha) <= 0.0))
                ++n_bad; /* clamped: the root really is below */
        }
    }
    CHECK(n_bad == 0, "sign change violated in %d of %d checks", n_bad, n_checked);
    printf("normal_sign_change_checks=%d\nnormal_sign_change_violations=%d\n", n_checked, n_bad);
}

/* |dF_n/du_n| = g (1 - dx/ds) must stay in [0, g]: 0 <= dx/ds <= 1 (notes §7). */
static void test_stiffness_bound(void)
{
    law_rng r = {4242};
    double max_slope = 0.0, min_slope = 1.0;
    for (int i = 0; i < 50000; ++i) {
        double dprev, s, h, e, alpha;
        random_inputs(&r, i + 2, &dprev, &s, &h, &e, &alpha);
        double ds = 1e-7;
        double x0 = exp(lub_normal_solve(dprev, s, h, e, alpha, NULL));
        double x1 = exp(lub_normal_solve(dprev, s + ds, h, e, alpha, NULL));
        double sl = (x1 - x0) / ds;
        if (sl > max_slope)
            max_slope = sl;
        if (sl < min_slope)
            min_slope = sl;
    }
    CHECK(max_slope <= 1.0 + 1e-6 && min_slope >= -1e-6, "dx/ds in [%g, %g]", min_slope, max_slope);
    printf("normal_dx_ds_min=%.3e\nnormal_dx_ds_max=%.6f\n", min_slope, max_slope);
}

static void test_quasi_static_and_limits(void)
{
    int c;
    /* no contact: x = s */
    double d = lub_normal_solve(0.0, 0.3, INFINITY, 0.1, 1.0, &c);
    CHECK(c == 0 && fabs(exp(d) - 0.3) < 1e-15, "qs no contact x=%g c=%d", exp(d), c);
    /* contact: (1+alpha) x = s + alpha e */
    d = lub_normal_solve(0.0, 0.05, INFINITY, 0.1, 2.0, &c);
    CHECK(c == 1 && fabs(exp(d) - (0.05 + 0.2) / 3.0) < 1e-15, "qs contact x=%g", exp(d));
    /* crushed asperities, no lubrication (no dynamics): the fixed static floor */
    d = lub_normal_solve(0.0, -0.5, INFINITY, 0.1, 1.0, &c);
    CHECK(c == 1 && d == LUB_DELTA_STATIC_FLOOR, "qs floor d=%g c=%d", d, c);
    /* smooth, overlapping, no lubrication: static floor, whatever the history */
    d = lub_normal_solve(-3.0, -0.01, INFINITY, 0.0, 1.0, &c);
    CHECK(c == 1 && d == LUB_DELTA_STATIC_FLOOR, "qs smooth floor d=%g c=%d", d, c);
    d = lub_normal_solve(-5e4, -0.01, INFINITY, 0.0, 1.0, &c);
    CHECK(c == 1 && d == LUB_DELTA_STATIC_FLOOR, "qs smooth floor (deep history) d=%g", d);
    /* the bracketed solver uses the same static floor for h = inf */
    d = lub_normal_solve_bracketed(0.0, -0.5, INFINITY, 0.1, 1.0);
    CHECK(d == LUB_DELTA_STATIC_FLOOR, "bracketed qs floor d=%g", d);
    /* eps = 0 with lubrication: never contact, even deeply compressed with x_prev = e^-1000;
     * no floor: delta+ = delta- - ln(1 - h s) exactly (x+ = 0 in double) */
    d = lub_normal_solve(-1000.0, -0.5, 1e6, 0.0, 1.0, &c);
    CHECK(c == 0 && fabs(d - (-1000.0 - log(500001.0))) < 1e-12, "eps0 compressed d=%.17g c=%d", d,
          c);
    d = lub_normal_solve(-1.0e5, -0.5, 1e6, 0.0, 1.0, &c);
    CHECK(c == 0 && fabs(d - (-1.0e5 - log(500001.0))) < 1e-10, "eps0 compressed -1e5 d=%.17g", d);
    /* compressed smooth pair decays exponentially in delta: delta+ - delta- = -ln(1 - h s)
     * with x << |s| (b > 0 branch, x_prev = e^-600) */
    d = lub_normal_solve(-600.0, -0.2, 0.5, 0.0, 1.0, &c);
    CHECK(fabs(d - (-600.0 - log(1.1))) < 1e-12, "scaled decay d=%.17g", d);
    /* delta_prev = -1000: x_prev == 0 in double; small h: x+ = x_prev / (1 - h (s + alpha e))
     * (in contact, growing slowly), exact in log form */
    d = lub_normal_solve(-1000.0, 0.5, 1e-3, 0.01, 1.0, &c);
    CHECK(c == 1 && fabs(d - (-1000.0 - log1p(-1e-3 * 0.51))) < 1e-12, "dprev -1000 d=%.17g", d);
    /* subnormal x_prev (delta_prev = -720, 7 digits lost in exp): still exact */
    d = lub_normal_solve(-720.0, -0.2, 0.5, 0.0, 1.0, &c);
    CHECK(fabs(d - (-720.0 - log(1.1))) < 1e-12, "subnormal x_prev d=%.17g", d);
    /* but a large h lifts it back within one step: x ~ s (no contact) */
    d = lub_normal_solve(-1000.0, 0.5, 1e12, 0.01, 1.0, &c);
    CHECK(c == 0 && fabs(exp(d) - 0.5) < 1e-11, "dprev -1000 h 1e12 x=%.17g", exp(d));
    /* critical case b = 1 - h s = 0 with x_prev = e^-700: both terms of the closed form
     * underflow -> bracketed fallback; exact root x = sqrt(x_prev / h) */
    d = lub_normal_solve(-700.0, 1.0, 1.0, 0.0, 1.0, &c);
    CHECK(fabs(d - (-350.0)) < 1e-12 && c == 0, "fallback d=%.17g", d);
    d = lub_normal_solve(-1000.0, 0.5, 2.0, 0.0, 1.0, &c); /* root -500 */
    CHECK(fabs(d - (-500.0 - 0.5 * log(2.0))) < 1e-12, "fallback 2 d=%.17g", d);
    d = lub_normal_solve(-1.0e5, 1.0, 1.0, 0.0, 1.0, &c); /* fallback at depth: root -5e4 */
    CHECK(fabs(d - (-5.0e4)) < 1e-10 && c == 0, "fallback deep d=%.17g", d);
    /* guard clamp: pathological inputs stay finite (delta_prev below the guard, -inf) */
    d = lub_normal_solve(-2.0e7, -0.1, 1.0, 0.01, 1.0, &c);
    CHECK(d == LUB_DELTA_MIN && c == 1, "guard clamp d=%g", d);
    d = lub_normal_solve(-INFINITY, -0.1, 1.0, 0.01, 1.0, &c);
    CHECK(d == LUB_DELTA_MIN && c == 1, "delta_prev = -inf d=%g", d);
    d = lub_normal_solve(-1.0e4, -0.1, 1e300, 0.0, 1.0, &c);
    CHECK(isfinite(d) && d >= LUB_DELTA_MIN && d < -1.0e4, "huge h d=%g", d);
    /* static rough equilibrium: s fixed, many steps -> x = (s + alpha e)/(1+alpha) */
    double dd = log(0.05);
    for (int k = 0; k < 200; ++k)
        dd = lub_normal_solve(dd, -0.005, 1e3, 0.01, 1.0, &c);
    CHECK(c == 1 && fabs(exp(dd) - 0.0025) < 1e-14, "rough equilibrium x=%.17g", exp(dd));
    printf("normal_rough_equilibrium_x=%.15g\n", exp(dd));
    /* rate is continuous at x = e */
    double Rm = lub_normal_rate(log(0.1) - 1e-12, 0.05, 0.1, 10.0);
    double Rp = lub_normal_rate(log(0.1) + 1e-12, 0.05, 0.1, 10.0);
    CHECK(fabs(Rm - Rp) < 1e-10, "rate jump %g", Rm - Rp);
}

/* A compressed pair with fixed s < -alpha e (crushed asperities) or smooth s < 0 decays for
 * ever (notes §11 P5): delta strictly decreasing, each step removing ln(1 - h (s + alpha e))
 * once x << |s|, through the subnormal range and far below -700. */
static void test_compressed_decay(void)
{
    const struct {
        double s, e, alpha, h;
        int steps;
    } cases[] = {{-0.05, 0.01, 1.0, 2.0, 200000},
                 {-0.01, 0.0, 1.0, 50.0, 100000},
                 {-0.3, 0.02, 10.0, 0.1, 300000}};
    for (unsigned k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        const double s = cases[k].s, e = cases[k].e, al = cases[k].alpha, h = cases[k].h;
        const double b = 1.0 - h * (s + al * e); /* > 1 */
        const double dec = log(b);               /* asymptotic decrement per step */
        double d = log(0.5 * e + 1e-3), max_dev = 0.0;
        int monotone = 1, contact_all = 1, finite = 1;
        long nsub = 0;
        for (int it = 0; it < cases[k].steps; ++it) {
            int c = -1;
            const double dn = lub_normal_solve(d, s, h, e, al, &c);
            if (!(dn < d))
                monotone = 0;
            if (!isfinite(dn))
                finite = 0;
            if (e > 0.0 && it > 0 && !c)
                contact_all = 0;
            if (e == 0.0 && c)
                contact_all = 0;
            if (d < -60.0) { /* x < 1e-26: the decrement is ln b to round-off of delta */
                const double dev = fabs((d - dn) - dec);
                if (dev > max_dev)
                    max_dev = dev;
            }
            nsub += (dn < -708.4 && dn > -745.2);
            d = dn;
        }
        const double tol = 1e-13 + 4.0 * DBL_EPSILON * fabs(d);
        CHECK(finite && monotone, "case %u: delta not strictly decreasing / finite", k);
        CHECK(contact_all, "case %u: contact flag wrong", k);
        CHECK(d < -1.0e3 && d > LUB_DELTA_MIN, "case %u: final delta %g", k, d);
        CHECK(max_dev <= tol, "case %u: decrement deviates by %g from ln b", k, max_dev);
        CHECK(nsub > 0, "case %u: subnormal range not crossed", k);
        /* the rate at the end is s + alpha_c e exactly (x = 0) */
        const double R = lub_normal_rate(d, s, e, al);
        CHECK(R == s + (e > 0.0 ? al * e : 0.0), "case %u: rate %g", k, R);
        printf("normal_compressed_case%u_final_delta=%.6g\n", k, d);
        printf("normal_compressed_case%u_max_decrement_dev=%.3e\n", k, max_dev);
    }
}

int main(void)
{
    test_closed_vs_bracketed();
    test_sign_change();
    test_stiffness_bound();
    test_quasi_static_and_limits();
    test_compressed_decay();
    printf("normal_failures=%d\n", failures);
    return failures ? 1 : 0;
}

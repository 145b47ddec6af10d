/* test_law_normal.c — normal part of the lubricated contact law (engine/contact_normal.c).
 *  1. closed form vs bracketed log-space solve over 2e5 random inputs (x_prev down to 1e-300
 *     and delta_prev = -700 / -1000, s in [-0.5, 2], h in [1e-12, 1e12], eps in [0, 0.2],
 *     alpha in [1e-3, 1e3]): |delta_closed - delta_bracketed| <= 1e-12;
 *  2. contact flag exact (x+ < e) away from the boundary; never with eps = 0;
 *  3. incremental stiffness 0 <= dx+/ds <= 1 (|dF_n/du_n| <= g, the time-step argument of
 *     notes §7) on random inputs;
 *  4. quasi-static (h = inf) branches, the floor, and the analytic sedimentation limit.
 * Prints name=value lines; exits non-zero on failure. */
#include "contact_law.h"
#include "law_rng.h"

#include <float.h>
#include <math.h>
#include <stdio.h>

static int failures = 0;
#define CHECK(cond, ...)                                                                       \
    do {                                                                                       \
        if (!(cond)) {                                                                         \
            ++failures;                                                                        \
            if (failures < 20) {                                                               \
                fprintf(stderr, "FAIL %s:%d: ", __FILE__, __LINE__);                           \
                fprintf(stderr, __VA_ARGS__);                                                  \
                fputc('\n', stderr);                                                           \
            }                                                                                  \
        }                                                                                      \
    } while (0)

static void random_inputs(law_rng *r, int i, double *dprev, double *s, double *h, double *e,
                          double *alpha)
{
    if (i % 50 == 0)
        *dprev = -700.0;
    else if (i % 50 == 1)
        *dprev = -1000.0;
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
    int n_illcond = 0, n_illcond_used = 0;
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
        double tol = 1e-12 + 4.0 * DBL_EPSILON * kappa;
        (void)xp;
        if (4.0 * DBL_EPSILON * kappa > 1e-12)
            ++n_illcond;
        if (err > 1e-12 && err <= tol)
            ++n_illcond_used;
        CHECK(err <= tol, "closed %.17g vs bracketed %.17g (dprev=%g s=%.17g h=%.17g e=%.17g "
                            "alpha=%.17g)", dc, db, dprev, s, h, e, alpha);
        CHECK(dc >= LUB_DELTA_MIN && dc <= LUB_DELTA_MAX, "delta out of range %g", dc);
        n_contact += c;
        n_floor += (dc == LUB_DELTA_MIN);
        if (e == 0.0)
            n_eps0_contact += c;
        else if (fabs(db - log(e)) > 1e-12 && c != (db < log(e)))
            ++n_flag_mismatch;
    }
    CHECK(n_flag_mismatch == 0, "contact flag mismatches: %d", n_flag_mismatch);
    CHECK(n_eps0_contact == 0, "contact with eps = 0: %d", n_eps0_contact);
    CHECK(n_contact > N / 10, "too few contact cases sampled: %d", n_contact);
    printf("normal_random_cases=%d\n", N);
    printf("normal_closed_vs_bracketed_max_abs_ddelta=%.3e\n", max_err);
    printf("normal_contact_cases=%d\n", n_contact);
    printf("normal_illconditioned_cases=%d\n", n_illcond);
    printf("normal_cases_beyond_1e-12_within_condition_bound=%d\n", n_illcond_used);
    printf("normal_floor_cases=%d\n", n_floor);
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
        return (double)(base - (1.0L + ac) * x + hinv * expm1l((long double)dprev - (long double)d));
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
    CHECK(max_slope <= 1.0 + 1e-6 && min_slope >= -1e-6, "dx/ds in [%g, %g]", min_slope,
          max_slope);
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
    /* crushed asperities: floor */
    d = lub_normal_solve(0.0, -0.5, INFINITY, 0.1, 1.0, &c);
    CHECK(c == 1 && d == LUB_DELTA_MIN, "qs floor d=%g c=%d", d, c);
    /* smooth, overlapping, no lubrication: floor, finite */
    d = lub_normal_solve(-3.0, -0.01, INFINITY, 0.0, 1.0, &c);
    CHECK(c == 1 && d == LUB_DELTA_MIN, "qs smooth floor d=%g c=%d", d, c);
    /* eps = 0 with lubrication: never contact, even deeply compressed with x_prev = e^-1000 */
    d = lub_normal_solve(-1000.0, -0.5, 1e6, 0.0, 1.0, &c);
    CHECK(c == 0 && d == LUB_DELTA_MIN, "eps0 compressed d=%g c=%d", d, c);
    /* compressed smooth pair decays exponentially in delta: delta+ - delta- = -ln(1 - h s)
     * with x << |s| (b > 0 branch, x_prev = e^-600) */
    d = lub_normal_solve(-600.0, -0.2, 0.5, 0.0, 1.0, &c);
    CHECK(fabs(d - (-600.0 - log(1.1))) < 1e-12, "scaled decay d=%.17g", d);
    /* delta_prev = -1000: x_prev == 0 in double, root below the clamp */
    d = lub_normal_solve(-1000.0, 0.5, 1e-3, 0.01, 1.0, &c);
    CHECK(d == LUB_DELTA_MIN && c == 1, "dprev -1000 d=%g", d);
    /* but a large h lifts it back within one step: x ~ s (no contact) */
    d = lub_normal_solve(-1000.0, 0.5, 1e12, 0.01, 1.0, &c);
    CHECK(c == 0 && fabs(exp(d) - 0.5) < 1e-11, "dprev -1000 h 1e12 x=%.17g", exp(d));
    /* critical case b = 1 - h s = 0 with x_prev = e^-700: both terms of the closed form
     * underflow -> bracketed fallback; exact root x = sqrt(x_prev / h) */
    d = lub_normal_solve(-700.0, 1.0, 1.0, 0.0, 1.0, &c);
    CHECK(fabs(d - (-350.0)) < 1e-12 && c == 0, "fallback d=%.17g", d);
    d = lub_normal_solve(-1000.0, 0.5, 2.0, 0.0, 1.0, &c); /* root -500 */
    CHECK(fabs(d - (-500.0 - 0.5 * log(2.0))) < 1e-12, "fallback 2 d=%.17g", d);
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

int main(void)
{
    test_closed_vs_bracketed();
    test_sign_change();
    test_stiffness_bound();
    test_quasi_static_and_limits();
    printf("normal_failures=%d\n", failures);
    return failures ? 1 : 0;
}

/* Tests of resuspension_analysis.c against the exact steady suspension-balance profile of a
 * power-law normal viscosity with n = 2 (physics-reference §4, seed 000 eq. 3, 5, 6):
 *   eta(phi) = lambda (psi/(1 - psi))^2, psi = phi/phi_m,
 *   phi/Sh = -(d eta/d phi)(d phi/dy)  =>  (1 - psi)^-2 = (1 - psi0)^-2 - phi_m y/(lambda Sh),
 * so the front (phi = 0) is at y_f = lambda Sh ((1 - psi0)^-2 - 1)/phi_m.
 * Eq. 6 applied to the binned exact profile must return eta(phi) bin by bin: the check
 * fails if the 1/Sh factor, the integration direction or the half-bin term is wrong.
 * Also: inventory, height, the bed's base, the bulk selection (keep[i] equals the rule for every
 * bin, and a step profile where only the interface width excludes bins), dimensionless groups,
 * and the coarse graining of a layered profile (lub_profile_coarse_grain). */
#include <math.h>
#include <stdio.h>

#include "resuspension_analysis.h"

static int failures = 0;
#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: ", __FILE__, __LINE__);                                        \
            fprintf(stderr, __VA_ARGS__);                                                          \
            fprintf(stderr, "\n");                                                                 \
            ++failures;                                                                            \
        }                                                                                          \
    } while (0)

static const double lambda = 0.6, phi_m = 0.585, sh = 0.04, psi0 = 0.95;

static double psi_exact(double y)
{
    double q = 1.0 / ((1 - psi0) * (1 - psi0)) - phi_m * y / (lambda * sh);
    return q <= 1.0 ? 0.0 : 1.0 - 1.0 / sqrt(q);
}

int main(void)
{
    enum { N = 1000 };
    const double dy = 0.02;
    const double y_front = lambda * sh * (1.0 / ((1 - psi0) * (1 - psi0)) - 1.0) / phi_m;
    double phi[N], err[N], eta[N], eta_err[N];
    /* exact bin averages (fine midpoint sampling) and a constant 1% error bar */
    for (int i = 0; i < N; ++i) {
        double s = 0;
        for (int k = 0; k < 200; ++k)
            s += psi_exact((i + (k + 0.5) / 200.0) * dy);
        phi[i] = phi_m * s / 200.0;
        err[i] = 0.01 * phi[i];
    }
    lub_profile_normal_viscosity(phi, err, N, dy, sh, eta, eta_err);
    double worst = 0;
    int compared = 0;
    for (int i = 0; i < N; ++i) {
        double y = (i + 0.5) * dy;
        double psi = psi_exact(y);
        if (psi < 0.5 || y > y_front - 2 * dy)
            continue; /* near the sharp front (psi < 0.5 within ~0.3a of it) the half-bin term is
                         not accurate */
        double expect = lambda * pow(psi / (1 - psi), 2);
        double rel = fabs(eta[i] - expect) / expect;
        if (rel > worst)
            worst = rel;
        ++compared;
    }
    printf("sbm_front_height=%.6f\n", y_front);
    printf("eta_from_profile_max_rel_err=%.3e\n", worst);
    printf("bins_compared=%d\n", compared);
    CHECK(compared > 100, "too few bins compared (%d)", compared);
    CHECK(worst < 2e-3, "eq. 6 does not reproduce eta(phi): worst relative error %.3e", worst);

    /* errors: the bottom bin integrates all bins: sqrt(sum var) dy / Sh */
    double var = 0;
    for (int i = 1; i < N; ++i)
        var += err[i] * err[i] * dy * dy;
    var += 0.25 * err[0] * err[0] * dy * dy;
    CHECK(fabs(eta_err[0] - sqrt(var) / sh) < 1e-12 * eta_err[0], "error propagation");

    /* inventory = integral of phi = phi_m * integral psi dy (trapezoid on a fine grid) */
    double inv = 0;
    for (int k = 0; k < 200000; ++k)
        inv += psi_exact((k + 0.5) * (N * dy / 200000.0)) * (N * dy / 200000.0);
    inv *= phi_m;
    CHECK(fabs(lub_profile_inventory(phi, N, dy) - inv) < 1e-6 * inv, "inventory");

    /* height at a small level is within two bins of the exact front */
    double h = lub_profile_height(phi, N, 0.0, dy, 1e-3);
    printf("profile_height=%.6f\n", h);
    CHECK(fabs(h - y_front) < 2 * dy, "height %.5f vs front %.5f", h, y_front);
    CHECK(isnan(lub_profile_height(phi, N, 0.0, dy, 0.9)), "level above the profile -> NAN");

    /* bulk selection: interface bins and floor bins excluded */
    int keep[N];
    int kept = lub_profile_select_bulk(phi, N, 0.0, dy, 5.0, 1.0, 0.05, keep);
    double y_half = lub_profile_height(phi, N, 0.0, dy, 0.5 * phi[0]); /* phi[0] the maximum */
    int kept_rule = 0;
    for (int i = 0; i < N; ++i) {
        double y = (i + 0.5) * dy;
        const int rule = y <= y_half - 5.0 && y >= 1.0 && phi[i] >= 0.05;
        CHECK(keep[i] == rule, "bin %d (y %.3f, phi %.4f): keep %d, the rule says %d", i, y, phi[i],
              keep[i], rule);
        kept_rule += rule;
    }
    CHECK(kept > 0 && kept == kept_rule, "%d bulk bins kept, the rule keeps %d", kept, kept_rule);

    /* only the interface width excludes bins: a step profile phi = 0.5 over bins 0-39 (bins
     * of 0.5 a, so the half-maximum crossing is at y_int = 20), no floor skip, phi_min 0: the
     * bins with centre at or below y_int - 5 = 15 are kept, 0-29, and no other */
    {
        enum { M = 60 };
        double st[M];
        int kp[M];
        for (int i = 0; i < M; ++i)
            st[i] = i < 40 ? 0.5 : 0.0;
        CHECK(fabs(lub_profile_height(st, M, 0.0, 0.5, 0.25) - 20.0) < 1e-12, "step height");
        const int k = lub_profile_select_bulk(st, M, 0.0, 0.5, 5.0, 0.0, 0.0, kp);
        CHECK(k == 30, "step profile: %d bulk bins kept, expected 30 (centres <= 15)", k);
        for (int i = 0; i < M; ++i)
            CHECK(kp[i] == (i <= 29), "step profile: bin %d (centre %.2f) keep %d", i,
                  (i + 0.5) * 0.5, kp[i]);
        /* the bed's base: the bottom bin already at the level gives its centre; a level never
         * reached NAN; a rise from 0.1 at centre 0.25 to 0.5 at 0.75 crosses 0.25 at 0.4375 */
        CHECK(lub_profile_base(st, M, 0.0, 0.5, 0.25) == 0.25, "base of the step");
        CHECK(isnan(lub_profile_base(st, M, 0.0, 0.5, 0.6)), "base above the profile -> NAN");
        st[0] = 0.1;
        CHECK(fabs(lub_profile_base(st, M, 0.0, 0.5, 0.25) - 0.4375) < 1e-15, "base %.17g",
              lub_profile_base(st, M, 0.0, 0.5, 0.25));
    }

    /* coarse graining over one diameter (2 a, bins of 0.5 a): a layered profile (mean 0.48,
     * +-0.05 with the period of one diameter) becomes its mean away from the ends, exactly
     * (the window spans whole periods); the error of the window mean of independent bins with
     * equal errors e is e sqrt(2 (1/8)^2 + 3 (1/4)^2); at the ends the window is cut and
     * renormalised; a window no wider than a bin copies the profile */
    {
        enum { M = 40 };
        const double bw = 0.5;
        double lay[M], le[M], cg[M], cge[M];
        for (int i = 0; i < M; ++i) {
            lay[i] = 0.48 + 0.05 * sin(2.0 * 3.14159265358979323846 * (i + 0.5) * bw / 2.0 + 0.3);
            le[i] = 0.01;
        }
        lub_profile_coarse_grain(lay, le, M, bw, 2.0, cg, cge);
        double worst = 0.0;
        for (int i = 2; i < M - 2; ++i)
            worst = fmax(worst, fabs(cg[i] - 0.48));
        printf("coarse_grain_layered_max_dev=%.3g err_interior=%.6f\n", worst, cge[10]);
        CHECK(worst < 1e-12, "layered profile not averaged to its mean: %g", worst);
        const double e_exp = 0.01 * sqrt(2.0 / 64.0 + 3.0 / 16.0);
        CHECK(fabs(cge[10] - e_exp) < 1e-14, "window error %g vs %g", cge[10], e_exp);
        /* first bin: window [-0.75, 1.25] cut to [0, 1.25]: weights 0.5, 0.5, 0.25 */
        const double c0 = (0.5 * lay[0] + 0.5 * lay[1] + 0.25 * lay[2]) / 1.25;
        CHECK(fabs(cg[0] - c0) < 1e-15, "cut window at the floor %g vs %g", cg[0], c0);
        lub_profile_coarse_grain(lay, NULL, M, bw, 0.0, cg, cge);
        CHECK(cg[7] == lay[7] && isnan(cge[7]), "width 0 must copy the profile");
    }

    /* dimensionless groups */
    CHECK(fabs(lub_shields_number(2.0, -3.0, 4.0, 5.0, 0.5) - 0.6) < 1e-15, "Shields");
    CHECK(fabs(lub_acrivos_number(1.0, 1.0, 1.0, 1.0, 9.0) - 0.5) < 1e-15, "Acrivos");

    printf("%d passed, %d failed\n", failures ? 0 : 1, failures ? 1 : 0);
    return failures ? 1 : 0;
}

/* test_series.c — the steady-state statistics of a simple_shear run's series
 * (simple_shear_series.h) on synthetic series whose answers are known: ratio observables are
 * ratios of time averages (an exact proportion gives the ratio with no error), the stress parts
 * are averaged over their total's window (they add up to it), Iv is gd/<P> in the stress unit,
 * the error bars of mu and Iv are their delta-method values to round-off,
 * an imposed phi has no error while a free one has, a drifting headline is not steady, the
 * /target_rel_error check stops on a small error (its 90 % upper bound, not the estimate) and
 * never on a zero mean, never on a window the summary calls not steady or on a headline
 * averaged over less than /target_min_strain, and the room of the series grows without losing
 * samples. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "shear_test.h"
#include "simple_shear_series.h"
#include "stats.h"

#define SAMPLES 600
#define SAMPLE_STRAIN 0.02

/* a deterministic noise in [-0.5, 0.5) (64-bit LCG) */
static double noise(uint64_t *state)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*state >> 11) / 9007199254740992.0 - 0.5;
}

/* SAMPLES samples of a stationary suspension: P = 2 + noise, sigma_xy = mu P (exact), the
 * stress parts 40 / 60 % of sigma_xy, eta_11 = 1.3 eta_22, eta_33 = 0.7 eta_22; phi = phi0 +
 * phi_noise * noise; sxy_drift adds a linear rise of sigma_xy over the run */
static void fill(lub_ss_series *ser, double mu, double phi0, double phi_noise, double sxy_drift)
{
    uint64_t rng = 12345;
    ST_CHECK(lub_ss_series_reserve(ser, 16) == 0, "reserve");
    for (int i = 0; i < SAMPLES; ++i) {
        if (ser->n == ser->cap) /* grown while it fills: the samples held stay */
            ST_CHECK(lub_ss_series_reserve(ser, 2 * ser->cap) == 0, "grow");
        double v[SS_OBS_COUNT];
        memset(v, 0, sizeof v);
        const double P = 2.0 + noise(&rng);
        const double sxy = mu * P + sxy_drift * i / SAMPLES;
        const double e22 = P; /* gd = 1, s0 = 1 */
        v[SS_OBS_PHI] = phi0 + phi_noise * noise(&rng);
        v[SS_OBS_P] = P;
        v[SS_OBS_MU] = sxy / P;
        v[SS_OBS_ETA] = sxy;
        v[SS_OBS_IV] = 1.0 / P;
        v[SS_OBS_SXY] = sxy;
        v[SS_OBS_ETA11] = 1.3 * e22;
        v[SS_OBS_ETA22] = e22;
        v[SS_OBS_ETA33] = 0.7 * e22;
        v[SS_OBS_L1] = 1.3;
        v[SS_OBS_L3] = 0.7;
        v[SS_OBS_XY_NC] = 0.4 * sxy;
        v[SS_OBS_XY_SC] = 0.6 * sxy;
        ST_CHECK(lub_ss_series_append(ser, SAMPLE_STRAIN * i, v) == 0, "append %d", i);
    }
}

int main(void)
{
    lub_ss_params p;
    memset(&p, 0, sizeof p);
    p.transient_strain = 1.0;
    lub_ss_steady_stats st;

    /* imposed volume, mu 0.6 */
    lub_ss_series ser;
    memset(&ser, 0, sizeof ser);
    fill(&ser, 0.6, 0.5, 1e-15, 0.0); /* an imposed phi moves by round-off */
    ST_CHECK(ser.n == SAMPLES && ser.strain[SAMPLES - 1] == SAMPLE_STRAIN * (SAMPLES - 1),
             "samples kept while the room grew: %zu", ser.n);
    lub_ss_series_statistics(&p, 1.0, 1.0, &ser, &st);
    ST_CHECK(st.steady, "a stationary series is steady (drift z %g)", st.worst_drift_z);
    ST_CHECK(ser.strain[st.start] >= p.transient_strain, "window from strain %g",
             ser.strain[st.start]);
    ST_CHECK(fabs(st.mean[SS_OBS_MU] - 0.6) < 1e-14 && st.sem[SS_OBS_MU] < 1e-14,
             "mu = <sigma_xy>/<P> exactly: %.17g +- %g", st.mean[SS_OBS_MU], st.sem[SS_OBS_MU]);
    ST_CHECK(fabs(st.mean[SS_OBS_L1] - 1.3) < 1e-14 && fabs(st.mean[SS_OBS_L3] - 0.7) < 1e-14,
             "normal-stress ratios %.17g %.17g", st.mean[SS_OBS_L1], st.mean[SS_OBS_L3]);
    ST_CHECK(fabs(st.mean[SS_OBS_IV] - 1.0 / st.mean[SS_OBS_P]) < 1e-15,
             "Iv = gd/<P>: %.17g against %.17g (the mean of 1/P is %s)", st.mean[SS_OBS_IV],
             1.0 / st.mean[SS_OBS_P], "larger");
    ST_CHECK(fabs(st.mean[SS_OBS_XY_NC] + st.mean[SS_OBS_XY_SC] - st.mean[SS_OBS_SXY]) < 1e-14,
             "the parts add up to sigma_xy: %.17g + %.17g against %.17g", st.mean[SS_OBS_XY_NC],
             st.mean[SS_OBS_XY_SC], st.mean[SS_OBS_SXY]);
    ST_CHECK(st.sem[SS_OBS_PHI] == 0.0, "an imposed phi has no error: %g", st.sem[SS_OBS_PHI]);
    ST_CHECK(st.sem[SS_OBS_P] > 0.0 && isfinite(st.sem[SS_OBS_P]), "P has an error: %g",
             st.sem[SS_OBS_P]);

    /* the same in the units of an imposed pressure: gd = Iv = 0.01, s0 = 1 */
    lub_ss_series_statistics(&p, 0.01, 1.0, &ser, &st);
    ST_CHECK(fabs(st.mean[SS_OBS_IV] - 0.01 / st.mean[SS_OBS_P]) < 1e-15, "Iv = gd/(s0 <P>): %g",
             st.mean[SS_OBS_IV]);

    /* /target_rel_error: mu known exactly stops the run once the window is long enough */
    p.target_rel_error = 0.02;
    p.target_min_strain = 5.0;
    int zero = -1;
    p.pressure = 0; /* headline eta_r = sigma_xy/(eta gd): its error is not 0 */
    const int eta_stop = lub_ss_target_reached(&p, &ser, &zero, NULL);
    p.pressure = 1; /* headline mu */
    ST_CHECK(lub_ss_target_reached(&p, &ser, &zero, NULL) == 1 && zero == 0,
             "mu known to 0 %% stops (zero_mean %d)", zero);
    p.target_min_strain = 100.0; /* longer than the window */
    ST_CHECK(lub_ss_target_reached(&p, &ser, &zero, NULL) == 0, "no stop on a window too short");
    p.target_min_strain = 5.0;
    p.target_rel_error = 1e-6;
    p.pressure = 0;
    ST_CHECK(lub_ss_target_reached(&p, &ser, &zero, NULL) == 0 && eta_stop == 1,
             "eta_r's error (about 1 %% of a noise of 30 %%) is above 1e-6 of it, below 2 %%");
    lub_ss_series_free(&ser);

    /* mu is <sigma_xy>/<P>, not the mean of the sampled ratios: sigma_xy with a noise of its
     * own */
    p.pressure = 1;
    fill(&ser, 0.6, 0.55, 0.0, 0.0);
    uint64_t rng = 777;
    for (size_t i = 0; i < ser.n; ++i) {
        ser.v[SS_OBS_SXY][i] += 0.3 * noise(&rng);
        ser.v[SS_OBS_MU][i] = ser.v[SS_OBS_SXY][i] / ser.v[SS_OBS_P][i];
    }
    lub_ss_series_statistics(&p, 0.01, 1.0, &ser, &st);
    double sum_sxy = 0.0, sum_p = 0.0, sum_ratio = 0.0;
    for (size_t i = st.start; i < ser.n; ++i) {
        sum_sxy += ser.v[SS_OBS_SXY][i];
        sum_p += ser.v[SS_OBS_P][i];
        sum_ratio += ser.v[SS_OBS_MU][i];
    }
    const double ratio_of_means = sum_sxy / sum_p;
    const double mean_of_ratios = sum_ratio / (double)(ser.n - st.start);
    ST_CHECK(fabs(st.mean[SS_OBS_MU] - ratio_of_means) < 1e-12 &&
                 fabs(mean_of_ratios - ratio_of_means) > 1e-4,
             "mu %.10g: <sigma_xy>/<P> %.10g, mean of the ratios %.10g", st.mean[SS_OBS_MU],
             ratio_of_means, mean_of_ratios);
    ST_CHECK(st.sem[SS_OBS_MU] > 0.0 && st.sem[SS_OBS_MU] < 0.01, "mu's error %g",
             st.sem[SS_OBS_MU]);
    /* The error bars of mu and Iv, to round-off, against their definitions (README "Ratios
     * are ratios of means"), computed here from the series: each series' window starts at the
     * later of the common start and its own MSER-5 cut (lub_stats_analyse with min_start), a
     * ratio's at the later of its two series' windows. mu = <sigma_xy>/<P> has the delta
     * method's error: the SEM (stats.h rule) of z_k = (sigma_xy_k - mu P_k)/<P>, <P> = 2 here,
     * so a z without its division by <P> doubles it; Iv = gd/(s0 <P>) has gd sem(P)/(s0
     * <P>^2). Two unit systems (gd, s0) = (0.01, 1) and (0.03, 2.5). A factor on either error
     * bar fails these (the checks above only bound mu's error by 0.01). */
    for (int u = 0; u < 2; ++u) {
        const double gd = u ? 0.03 : 0.01, s0 = u ? 2.5 : 1.0;
        lub_ss_series_statistics(&p, gd, s0, &ser, &st);
        const double *P = ser.v[SS_OBS_P], *sxy = ser.v[SS_OBS_SXY];
        const size_t n = ser.n;
        static double zs[SAMPLES], scr[SAMPLES];
        size_t dp = lub_stats_mser(P, n, 5, NULL), ds = lub_stats_mser(sxy, n, 5, NULL);
        dp = dp > st.start ? dp : st.start;
        ds = ds > st.start ? ds : st.start;
        const size_t dm = dp > ds ? dp : ds;
        const double mp = lub_stats_mean(P + dp, n - dp);
        const double iv_sem = gd * lub_stats_sem(P + dp, n - dp, scr) / (s0 * mp * mp);
        const double mx = lub_stats_mean(sxy + dm, n - dm), my = lub_stats_mean(P + dm, n - dm);
        for (size_t i = dm; i < n; ++i)
            zs[i - dm] = (sxy[i] - mx / my * P[i]) / my;
        const double mu_sem = lub_stats_sem(zs, n - dm, scr);
        printf("series u%d windows: common %zu, P %zu, mu %zu; Iv %.6g +- %.6g (direct %.6g); "
               "mu %.6g +- %.6g (direct %.6g)\n",
               u, st.start, dp, dm, st.mean[SS_OBS_IV], st.sem[SS_OBS_IV], iv_sem,
               st.mean[SS_OBS_MU], st.sem[SS_OBS_MU], mu_sem);
        ST_CHECK(fabs(my - 2.0) < 0.1 && mu_sem > 0.0 && iv_sem > 0.0,
                 "premise: <P> %g near 2, error bars %g %g not 0", my, mu_sem, iv_sem);
        ST_CHECK(fabs(st.mean[SS_OBS_IV] - gd / (s0 * mp)) <= 1e-12 * gd / (s0 * mp),
                 "Iv %.17g against gd/(s0 <P>) %.17g", st.mean[SS_OBS_IV], gd / (s0 * mp));
        ST_CHECK(fabs(st.sem[SS_OBS_IV] - iv_sem) <= 1e-12 * iv_sem,
                 "Iv's error %.17g against gd sem(P)/(s0 <P>^2) %.17g", st.sem[SS_OBS_IV], iv_sem);
        ST_CHECK(fabs(st.mean[SS_OBS_MU] - mx / my) <= 1e-12 * mx / my, "mu %.17g against %.17g",
                 st.mean[SS_OBS_MU], mx / my);
        ST_CHECK(fabs(st.sem[SS_OBS_MU] - mu_sem) <= 1e-12 * mu_sem,
                 "mu's error %.17g against the delta method's %.17g", st.sem[SS_OBS_MU], mu_sem);
        /* the windows the summary states (from_strain, samples): mu's and Iv's own, the
         * others the common one (these series put all at the common start; shear.scene_cli's
         * case 3e has a run whose ratios start later) */
        ST_CHECK(st.from[SS_OBS_MU] == dm && st.from[SS_OBS_IV] == dp &&
                     st.from[SS_OBS_SXY] == st.start && st.from[SS_OBS_P] == st.start,
                 "windows from %zu (mu), %zu (Iv), %zu (sigma_xy): want %zu, %zu, %zu",
                 st.from[SS_OBS_MU], st.from[SS_OBS_IV], st.from[SS_OBS_SXY], dm, dp, st.start);
    }

    /* the stop tests the 90 % upper bound of mu's relative error, not the estimate: a target
     * between the two does not stop the run (it did until 2026-12-07); at the bound it does.
     * The check's record: the summary's error, and the bound as stats.h makes it */
    lub_ss_target_check chk;
    p.target_min_strain = 5.0;
    p.target_rel_error = 0.5;
    ST_CHECK(lub_ss_target_reached(&p, &ser, &zero, &chk) == 1, "a stop at 50 %%");
    ST_CHECK(
        fabs(chk.rel_error - st.sem[SS_OBS_MU] / st.mean[SS_OBS_MU]) < 1e-15 && chk.batches >= 32 &&
            chk.lag1 >= 0.0 && chk.dof == lub_stats_sem_dof(chk.batches, chk.lag1) &&
            chk.rel_bound == chk.rel_error * lub_stats_sem_upper_factor(chk.batches, chk.lag1) &&
            chk.rel_bound > 1.2 * chk.rel_error,
        "record: error %g (summary %g), bound %g, %zu batch means, lag-1 %g, dof %g", chk.rel_error,
        st.sem[SS_OBS_MU] / st.mean[SS_OBS_MU], chk.rel_bound, chk.batches, chk.lag1, chk.dof);
    p.target_rel_error = 0.5 * (chk.rel_error + chk.rel_bound);
    ST_CHECK(lub_ss_target_reached(&p, &ser, &zero, NULL) == 0,
             "no stop at %g: the error %g is within it, its 90 %% bound %g is not",
             p.target_rel_error, chk.rel_error, chk.rel_bound);
    p.target_rel_error = chk.rel_bound;
    ST_CHECK(lub_ss_target_reached(&p, &ser, &zero, NULL) == 1, "a stop at the bound %g",
             chk.rel_bound);
    lub_ss_series_free(&ser);

    /* a free phi has an error; a rising sigma_xy is not steady */
    p.pressure = 1;
    p.target_rel_error = 0.5;
    fill(&ser, 0.6, 0.55, 0.01, 0.0);
    lub_ss_series_statistics(&p, 0.01, 1.0, &ser, &st);
    ST_CHECK(st.sem[SS_OBS_PHI] > 1e-5 && st.sem[SS_OBS_PHI] < 1e-3,
             "a free phi's error: %g (noise 0.01/sqrt(12), %d samples)", st.sem[SS_OBS_PHI],
             SAMPLES);
    lub_ss_series_free(&ser);
    fill(&ser, 0.6, 0.55, 0.0, 1.0);
    lub_ss_series_statistics(&p, 0.01, 1.0, &ser, &st);
    ST_CHECK(!st.steady, "a drifting mu is not steady (drift z %g)", st.worst_drift_z);
    lub_ss_series_free(&ser);

    /* the stop takes the summary's verdict: a stationary mu (known exactly) with phi still
     * drifting is not steady, so it does not stop (it did until 2026-12-07) */
    p.target_rel_error = 0.5;
    p.target_min_strain = 5.0;
    fill(&ser, 0.6, 0.55, 0.01, 0.0);
    for (size_t i = 0; i < ser.n; ++i)
        ser.v[SS_OBS_PHI][i] += 0.02 * (double)i / SAMPLES;
    lub_ss_series_statistics(&p, 0.01, 1.0, &ser, &st);
    ST_CHECK(!st.steady, "a drifting phi is not steady (drift z %g)", st.worst_drift_z);
    ST_CHECK(lub_ss_target_reached(&p, &ser, &zero, NULL) == 0,
             "no stop while phi drifts, though mu's error is 0");
    lub_ss_series_free(&ser);

    /* /target_min_strain bounds the window mu is averaged over: P (and sigma_xy = mu P) settle
     * only at strain 3.5, later than the common start (strain 1), while the sampled mu and phi
     * are stationary from the first sample; mu = <sigma_xy>/<P> is averaged from about 3.5, so
     * 8.5 strain, not the 11 of the common start */
    fill(&ser, 0.6, 0.55, 0.01, 0.0);
    for (size_t i = 0; ser.strain[i] < 3.5; ++i) {
        ser.v[SS_OBS_P][i] *= 0.25;
        ser.v[SS_OBS_SXY][i] *= 0.25;
    }
    p.target_min_strain = 9.0;
    ST_CHECK(lub_ss_target_reached(&p, &ser, &zero, NULL) == 0,
             "no stop: mu's window is shorter than /target_min_strain");
    p.target_min_strain = 8.0;
    ST_CHECK(lub_ss_target_reached(&p, &ser, &zero, NULL) == 1,
             "a stop once the window is long enough");
    lub_ss_series_free(&ser);
    p.target_min_strain = 5.0;

    /* a headline of exactly 0 has no relative error: no stop, and it is said */
    fill(&ser, 0.0, 0.55, 0.0, 0.0);
    ST_CHECK(lub_ss_target_reached(&p, &ser, &zero, NULL) == 0 && zero == 1,
             "mu = 0 +- 0 does not stop (zero_mean %d)", zero);
    lub_ss_series_free(&ser);
    ST_CHECK(ser.v[0] == NULL && ser.cap == 0, "free leaves an empty series");
    ST_DONE();
}

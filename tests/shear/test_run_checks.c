/* test_run_checks.c — the advisory checks of a finished simple_shear run: each check fires
 * just beyond its threshold, stays silent just inside it and for NaN, and names the spec
 * member to change; an imposed phi at or above the jamming fraction replaces the advice to
 * stiffen the contacts; the headline off the §2 law warns only with another interaction set
 * than the law's. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "run_context.h"
#include "shear_run_checks.h"
#include "shear_test.h"

/* a run that passes every check */
static lub_shear_run_state clean(void)
{
    lub_shear_run_state st = {.elastic_number = 1e4,
                              .kinetic_share = 1e-4,
                              .kinetic_share_pressure = 1e-3,
                              .crushed_fraction = 0.0,
                              .bond_order_q6 = 0.05,
                              .lost_pairs = 0.0,
                              .steady = 1,
                              .steady_samples = 400.0,
                              .strain_reached = 10.0,
                              .transient_strain = 2.0,
                              .headline_rel_bound = NAN,
                              .pressure_ratio = NAN}; /* imposed volume */
    return st;
}

static char text[LUB_SHEAR_WARNINGS_MAX][LUB_SHEAR_WARNING_LEN];

/* number of warnings for st; *first gets the first one (or "") */
static int count(const lub_shear_run_state *st, const char **first)
{
    memset(text, 0, sizeof text);
    int n = lub_shear_run_warnings(st, text);
    *first = n > 0 ? text[0] : "";
    return n;
}

/* expects exactly one warning, containing `part1` and `part2` (NULL: not checked) */
static void one(const char *label, const lub_shear_run_state *st, const char *part1,
                const char *part2)
{
    const char *w;
    int n = count(st, &w);
    ST_CHECK(n == 1 && strstr(w, part1) && (!part2 || strstr(w, part2)), "%s: %d warning(s): %s",
             label, n, w);
}

/* expects no warning */
static void none(const char *label, const lub_shear_run_state *st)
{
    const char *w;
    int n = count(st, &w);
    ST_CHECK(n == 0, "%s: %d warning(s): %s", label, n, w);
}

/* one threshold check: the field, a value just beyond the threshold (one warning containing
 * part1 and part2), one just inside it (none) */
typedef struct {
    const char *label;
    size_t field; /* offsetof a double member of lub_shear_run_state */
    double beyond, inside;
    const char *part1, *part2;
} threshold_case;

static void set_field(lub_shear_run_state *st, size_t field, double value)
{
    memcpy((char *)st + field, &value, sizeof value);
}

int main(void)
{
    const char *w0;
    lub_shear_run_state st = clean();
    none("clean run", &st);

    const threshold_case cases[] = {
        {"El", offsetof(lub_shear_run_state, elastic_number), 4.9e3, 5.1e3, "/stiffness",
         "4.9e+03"},
        {"kinetic share", offsetof(lub_shear_run_state, kinetic_share), 0.011, 0.009, "/St",
         "1.1 % of sigma_xy"},
        {"kinetic share of the pressure", offsetof(lub_shear_run_state, kinetic_share_pressure),
         0.072, 0.009, "/St", "7.2 % of -sigma_yy"},
        {"crushed", offsetof(lub_shear_run_state, crushed_fraction), 0.02, 0.005, "crushed in 2 %",
         "/stiffness"},
        {"Q6", offsetof(lub_shear_run_state, bond_order_q6), 0.153, 0.092, "0.153", "/n_particles"},
        {"lost pairs", offsetof(lub_shear_run_state, lost_pairs), 1.0, 0.0, "1 active pair",
         "lower /dt_safety"},
        {"fixed dt", offsetof(lub_shear_run_state, dt_over_elastic), 1.5, 0.9, "1.5 times",
         "lower /dt"},
        {"fixed dt, many partners", offsetof(lub_shear_run_state, dt_over_stiffness), 1.2, 0.95,
         "1.2 times the step the pairs' summed stiffness allows", "lower /dt"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        const threshold_case *tc = &cases[c];
        st = clean();
        set_field(&st, tc->field, tc->beyond);
        one(tc->label, &st, tc->part1, tc->part2);
        set_field(&st, tc->field, tc->inside);
        none(tc->label, &st);
        set_field(&st, tc->field, NAN); /* a NaN or an infinity (0/0, x/0) fails no check */
        none(tc->label, &st);
        set_field(&st, tc->field, INFINITY);
        none(tc->label, &st);
    }
    /* Q6 against the noise of few bonds: 35 bonds per sample give 0.169 for random
     * directions, so 0.168 is no ordering (phi 0.05, N = 300 warned), while 0.6 is (threshold
     * 3 x 0.169); with 1200 bonds (dense, N = 300) the threshold stays 0.1 */
    st = clean();
    st.bond_order_random = 1.0 / sqrt(35.0);
    st.bond_order_q6 = 0.168;
    none("Q6 at the noise of 35 bonds", &st);
    st.bond_order_q6 = 0.6;
    one("Q6 above the noise of 35 bonds", &st, "Q6 = 0.600 is above 0.51", "/n_particles");
    st.bond_order_random = 1.0 / sqrt(1200.0);
    st.bond_order_q6 = 0.153;
    one("Q6 with 1200 bonds", &st, "Q6 = 0.153 is above 0.1", NULL);
    st.bond_order_random = NAN;
    one("Q6, bonds unknown", &st, "Q6 = 0.153 is above 0.1", NULL);

    /* imposed pressure not held: more than 10 % and 3 standard errors off (gain 100 with a
     * 1e-4 filter gave -19.3 P); a noisy 4 % (1.2 standard errors) is held; at imposed volume
     * (NaN) nothing is checked; a mean pressure <= 0 has no El to check */
    st = clean();
    st.pressure_ratio = -19.3;
    st.pressure_ratio_sem = 5.0;
    st.elastic_number = -517.0;
    one("pressure not held", &st, "did not hold the imposed pressure", "lower /servo/gain");
    ST_CHECK(strstr(text[0], "-19.3 +- 5 times P") != NULL, "pressure not held: %s", text[0]);
    st.elastic_number = 1e4;
    st.pressure_ratio = 1.041;
    st.pressure_ratio_sem = 0.035;
    none("pressure 4 % off, 1.2 standard errors", &st);
    st.pressure_ratio = 1.15;
    st.pressure_ratio_sem = 0.06; /* 2.5 standard errors: chance */
    none("pressure 15 % off, 2.5 standard errors", &st);
    st.pressure_ratio_sem = 0.04;
    one("pressure 15 % off, 3.75 standard errors", &st, "1.15 +- 0.04 times P", NULL);
    /* a mean known only to more than 10 % is not held (a servo switching between its clamps,
     * Iv 10, St 0.1: 1.31 +- 0.56 P passed the 3-standard-error gate until 2026-12-07); known
     * to 10 % it is chance again */
    st.pressure_ratio = 1.31;
    st.pressure_ratio_sem = 0.56;
    one("pressure 31 % off, known to 56 %", &st, "1.31 +- 0.56 times P", "lower /servo/gain");
    st.pressure_ratio = 1.25;
    st.pressure_ratio_sem = 0.1;
    none("pressure 25 % off, 2.5 standard errors of 10 %", &st);
    st.pressure_ratio = 1.05;
    st.pressure_ratio_sem = 0.2;
    none("pressure 5 % off, known to 20 %", &st);
    /* the servo oscillating: -sigma_yy fluctuating by more than 50 % rms about its mean (the
     * default servo: 3-12 %; Iv 10, St 0.1 at the default step: 2740 %) */
    st.pressure_ratio = 1.0;
    st.pressure_ratio_sem = 0.02;
    st.pressure_rms_ratio = 0.51;
    one("pressure rms 51 %", &st, "the pressure servo oscillates: -sigma_yy fluctuates by 51 %",
        "lower /dt_safety");
    ST_CHECK(strstr(text[0], "lower /servo/gain") && strstr(text[0], "/servo/filter_strain"),
             "servo oscillation advice: %s", text[0]);
    st.pressure_rms_ratio = 0.5;
    none("pressure rms 50 %", &st);
    st.pressure_rms_ratio = NAN;
    none("pressure rms unknown", &st);
    st.pressure_rms_ratio = 0.0;
    st.pressure_ratio = 1.15;
    st.pressure_ratio_sem = 0.04;
    /* a run without a steady state (Iv = 10, St = 10, strain 2: -sigma_yy 58.8 P over 26
     * samples, no error bar) is told to run longer, not only to lower the gain */
    st.steady = 0;
    st.pressure_ratio = 58.8;
    st.pressure_ratio_sem = NAN;
    const char *w_unreached;
    ST_CHECK(count(&st, &w_unreached) == 2 && strstr(text[0], "was not reached") &&
                 strstr(text[0], "58.8 (no error bar) times P") &&
                 strstr(text[0], "raise /strain") && strstr(text[0], "lower /servo/gain)") &&
                 strstr(text[1], "no steady state detected"),
             "pressure not reached, no steady state: %s | %s", text[0], text[1]);
    st.steady = 1;
    st.pressure_ratio = NAN;
    none("imposed volume", &st);

    /* the factor to raise the stiffness by is 5e3/El */
    st = clean();
    st.elastic_number = 1e3;
    one("El 1e3", &st, "by 5 or more", NULL);
    /* no steady state */
    st = clean();
    st.steady = 0;
    one("not steady", &st, "/strain", "drift");
    /* with a fixed /dt, lost pairs ask for a smaller /dt (dt_safety does not apply) */
    st = clean();
    st.lost_pairs = 3.0;
    st.dt_over_elastic = 0.5;
    {
        const char *w;
        const int n = count(&st, &w);
        ST_CHECK(n == 1 && strstr(w, "3 active pair") && strstr(w, "lower /dt") &&
                     !strstr(w, "/dt_safety"),
                 "lost pairs, fixed dt: %d warning(s): %s", n, w);
    }
    /* imposed phi at or above the seed's phi_m(mu_m): one warning that quotes El and the
     * crushed fraction instead of the two warnings advising a stiffer run (phi 0.6, mu_m 0.5
     * gave El 80 and 64 % crushed) */
    st = clean();
    st.elastic_number = 79.7;
    st.crushed_fraction = 0.64;
    st.phi_imposed = 0.6;
    st.phi_jamming = 0.5737;
    st.mu_m = 0.5;
    one("jammed", &st, "phi = 0.6 is at or above the jamming fraction phi_m(mu_m = 0.5) = 0.574",
        "El = 79.7, 64 % of the contacts crushed");
    ST_CHECK(strstr(text[0], "lower /phi") && !strstr(text[0], "raise /stiffness"),
             "jammed advice: %s", text[0]);
    ST_CHECK(strlen(text[0]) + 1 < LUB_SHEAR_WARNING_LEN, "jammed warning may be truncated");
    st.phi_imposed = 0.5737; /* at phi_m: jammed */
    one("at phi_m", &st, "at or above the jamming fraction", NULL);
    st.elastic_number = NAN; /* no steady samples: no values to quote, no "nan" */
    st.crushed_fraction = NAN;
    one("jammed, nothing measured", &st, "follows the stiffness (a stiffer run", NULL);
    ST_CHECK(!strstr(text[0], "nan"), "jammed, nothing measured: %s", text[0]);
    st.elastic_number = 79.7;
    st.crushed_fraction = 0.64;
    st.phi_imposed = 0.57; /* below: the El and crushed warnings, each asking for /stiffness */
    ST_CHECK(count(&st, &w0) == 2 && strstr(text[0], "raise /stiffness") &&
                 strstr(text[1], "raise /stiffness"),
             "below phi_m: %s", w0);
    st.phi_imposed = NAN; /* imposed pressure: phi is free */
    ST_CHECK(count(&st, &w0) == 2, "pressure control: %s", w0);
    st.phi_imposed = 0.6;
    st.phi_jamming = 0.0; /* not given: no check */
    ST_CHECK(count(&st, &w0) == 2, "no phi_m: %s", w0);

    st = clean();
    st.steady = 0;
    /* ended inside the transient: no steady-state means at all, and the message says why */
    st.steady_samples = 0.0;
    st.strain_reached = 1.0;
    one("ended in the transient", &st, "ended at strain 1, inside the transient",
        "raise /strain above /transient_strain");
    /* beyond the transient but no sample there (one huge fixed step): not "inside" it */
    st.strain_reached = 1e3;
    one("no sample after the transient", &st, "no steady-state samples after /transient_strain 2",
        "strain 1e+03");
    /* a sample spacing longer than the run after the transient: /sample_strain is named (the
     * advice was to raise /strain, with /sample_strain 10 and /strain 0.01) */
    st.transient_strain = 0.0;
    st.strain_reached = 0.01;
    st.sample_strain = 10.0;
    one("sample spacing beyond the run", &st, "every /sample_strain 10 of strain",
        "lower /sample_strain");
    st.sample_strain = 0.005; /* within the run: the spacing is not the cause */
    one("sample spacing within the run", &st, "no steady-state samples after /transient_strain 0",
        "raise /strain");
    /* stopped by a signal (SIGTERM, SIGXCPU): --resume, not a longer /strain (which was advised
     * with /strain 50) */
    st = clean();
    st.steady = 0;
    st.steady_samples = 0.0;
    st.strain_reached = 1.0;
    st.stopped = 1;
    st.strain_target = 50.0;
    st.checkpoint_kept = 1;
    one("stopped in the transient", &st, "stopped by a signal at strain 1 of /strain 50, inside",
        "null; lubdem run --resume continues it");
    { /* the run driver withdraws that advice when it keeps no checkpoint after all */
        char kept_text[LUB_SHEAR_WARNING_LEN];
        snprintf(kept_text, sizeof kept_text, "%s", text[0]);
        json_t *extra = json_pack("{s:[s, i, s]}", "warnings", kept_text, 7, "other advice");
        ST_CHECK(lub_run_withdraw_resume_advice(extra) == 1, "one piece of advice withdrawn");
        const char *w = json_string_value(json_array_get(json_object_get(extra, "warnings"), 0));
        const size_t head = strlen(kept_text) - strlen(LUB_RESUME_ADVICE);
        ST_CHECK(w && !strstr(w, "--resume") && strncmp(w, kept_text, head) == 0 &&
                     strcmp(w + head, LUB_RERUN_ADVICE) == 0,
                 "withdrawn advice: %s", w ? w : "(none)");
        ST_CHECK(lub_run_withdraw_resume_advice(extra) == 0, "withdrawn twice");
        ST_CHECK(lub_run_withdraw_resume_advice(NULL) == 0, "no summary: nothing to withdraw");
        json_decref(extra);
    }
    st.checkpoint_kept = 0; /* the checkpoint could not be written: --resume would start afresh */
    one("stopped without a checkpoint", &st, "stopped by a signal", "could not be written");
    ST_CHECK(!strstr(text[0], "--resume"), "no checkpoint, yet --resume advised: %s", text[0]);
    st.checkpoint_kept = 1;
    st.strain_reached = 10.0;
    st.steady_samples = 30.0;
    one("stopped before a steady state", &st, "before a steady state was detected",
        "not steady-state values; lubdem run --resume");
    st.steady = 1; /* a stopped run with a steady state says nothing of it */
    st.steady_samples = 400.0;
    none("stopped in a steady state", &st);

    /* the headline against the §2 law, with another interaction set than the law's: eta_r 28.0
     * against 13.05 (default set, phi 0.45) warns; 11 % off (within 15 %), the article's set, no
     * law value or no steady state do not */
    st = clean();
    st.headline = 28.03;
    st.headline_law = 13.05;
    one("eta_r off the law", &st,
        "eta_r = 28 is +115 % from the reference law's 13.1 (physics-reference section 2; "
        "tolerance 15 %):",
        "; set /lubrication_pairs \"delaunay\", /law/terms/roll and /law/terms/twist false");
    st.headline = 14.5;
    none("eta_r within 15 %", &st);
    st.headline = 28.03;
    st.article_set = 1;
    none("the article's set", &st);
    st.article_set = 0;
    st.headline_law = NAN;
    none("no law value", &st);
    st.headline_law = 0.0;
    none("law value 0 (not set)", &st);
    st.headline_law = 13.05;
    st.steady = 0;
    ST_CHECK(count(&st, &w0) == 1 && !strstr(w0, "reference law"), "no steady state: %s", w0);
    st = clean();
    st.headline_is_mu = 1;
    st.headline = 0.54; /* mu within 10 % ... */
    st.headline_law = 0.5;
    st.phi_mean = 0.545;
    st.phi_law = 0.562; /* ... phi 0.017 off */
    one("phi off the law", &st,
        "mu = 0.54 is +8 % from the reference law's 0.5, phi 0.545 is -0.017 from its 0.562",
        "tolerance 10 % and 0.015 in phi)");
    st.phi_mean = 0.55;
    none("mu and phi within their tolerances", &st);

    /* a /target_rel_error the run did not reach: said, with the error reached (a run that
     * missed a 0.5 % target ended complete without a word) */
    st = clean();
    st.headline = 1.28;
    st.headline_sem = 0.0265; /* 2.07 % */
    st.target_rel_error = 0.005;
    st.strain_target = 5.0;
    one("target error missed", &st,
        "the run ended at /strain 5 without stopping on /target_rel_error 0.005: the relative "
        "error of eta_r is 0.021;",
        "raise /strain (lubdem run --keep-checkpoint lets a run be extended)");
    st.headline_sem = 0.005; /* within the target, but the run did not stop on it */
    one("target error within, not stopped", &st, "error of eta_r is 0.0039, within the target",
        "raise /strain");
    /* with the 90 % upper bound the stop tests (lub_ss_target_reached): given, and a run whose
     * error is within the target but its bound is not is told so */
    st.headline_sem = 0.0265;
    st.headline_rel_bound = 0.031;
    one("target error missed, bound", &st, "error of eta_r is 0.021 (90 % upper bound 0.031);",
        "raise /strain");
    st.headline_sem = 0.005;
    st.headline_rel_bound = 0.0055;
    one("target error within, bound not", &st,
        "error of eta_r is 0.0039, within the target, but not its 90 % upper bound 0.0055, which "
        "the stop tests;",
        "raise /strain");
    st.headline_rel_bound = 0.0048;
    one("target error and bound within, not stopped", &st,
        "error of eta_r is 0.0039 (90 % upper bound 0.0048), within the target, but over less "
        "than /target_min_strain",
        "raise /strain");
    st.stopped_on_target = 1;
    none("stopped on the target", &st);
    st.stopped_on_target = 0;
    st.failed = 1; /* a numerical failure: its diagnostic says why (it was told to raise /strain) */
    none("target error of a failed run", &st);
    st.failed = 0;
    st.target_zero_mean = 1; /* the scene's own warning says why */
    none("target error of a zero mean", &st);
    st.target_zero_mean = 0;
    st.headline_sem = NAN;
    none("target error without an error bar", &st);
    st.target_rel_error = 0.0;
    st.headline_sem = 0.0265;
    none("no target", &st);

    /* the stiffness factor is rounded up: El 3829 needs 1.306, which %.2g printed as 1.3 */
    st = clean();
    st.elastic_number = 3829.0;
    one("El factor rounded up", &st, "elastic number k/(P a) = 3.83e+03", "by 1.4 or more");

    /* a run that ended 5e-5 strain after /transient_strain (the step's rounding past
     * /strain = /transient_strain): raise /strain, since no /sample_strain (minimum 1e-4)
     * fits (it advised lowering /sample_strain) */
    st = clean();
    st.steady = 0;
    st.steady_samples = 0.0;
    st.transient_strain = 2.0;
    st.strain_reached = 2.0000503;
    st.sample_strain = 0.02;
    one("strain equal to the transient", &st, "the run ended at strain 2, only 5.03e-05 after",
        "raise /strain above /transient_strain");

    /* the microstructure averaged from strain 1, before the steady state detected from 2.5:
     * one warning naming /microstructure/start_strain; from 2.5 on, none; without a steady
     * state (its own warning) or without microstructure (NaN), none of it */
    st = clean();
    st.pdf_first_strain = 1.0;
    st.steady_from_strain = 2.5;
    one("microstructure before the steady state", &st, "averaged from strain 1, before",
        "raise /microstructure/start_strain to 2.5");
    st.pdf_first_strain = 2.5;
    none("microstructure from the steady state", &st);
    st.pdf_first_strain = NAN;
    none("no microstructure", &st);

    /* everything at once (imposed pressure): nine messages, ten with a steady state, each
     * naming the spec member to change (a JSON pointer after "; raise ", "; lower " or
     * "; set "), none truncated; first without a steady state (its message), then with one
     * (the law's message and the microstructure window's instead) */
    st = clean();
    st.steady = 0;
    st.headline_is_mu = 1;
    st.headline = 0.7;
    st.headline_law = 0.5;
    st.phi_mean = 0.5;
    st.phi_law = 0.55;
    st.steady_samples = 400.0;
    st.strain_reached = 10.0;
    st.elastic_number = 1e2;
    st.kinetic_share = 0.5;
    st.crushed_fraction = 0.3;
    st.bond_order_q6 = 0.5;
    st.lost_pairs = 12345.0;
    st.dt_over_elastic = 70.0;
    st.pressure_ratio = 0.5;
    st.target_rel_error = 0.01;
    st.headline_sem = 0.0063;       /* 0.9 %: within the target */
    st.headline_rel_bound = 0.0095; /* and so is its bound: the longest of the messages */
    st.strain_target = 10.0;
    st.pdf_first_strain = 1.0;
    st.steady_from_strain = 2.0;
    for (int steady = 0; steady <= 1; ++steady) {
        st.steady = steady;
        const char *w;
        int n = count(&st, &w);
        ST_CHECK(n == 9 + steady && n < LUB_SHEAR_WARNINGS_MAX,
                 "all checks, steady %d: %d warnings", steady, n);
        int law = 0;
        for (int k = 0; k < n; ++k)
            law += strstr(text[k], "reference law") != NULL;
        ST_CHECK(law == steady, "steady %d: %d warning(s) about the law", steady, law);
        for (int k = 0; k < n; ++k) {
            size_t len = strlen(text[k]);
            ST_CHECK(len + 1 < LUB_SHEAR_WARNING_LEN, "warning %d may be truncated (%zu chars)", k,
                     len);
            ST_CHECK(strstr(text[k], "; raise /") || strstr(text[k], "; lower /") ||
                         strstr(text[k], "; set /"),
                     "warning %d names no spec member to change: %s", k, text[k]);
        }
    }
    ST_DONE();
}

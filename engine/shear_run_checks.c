/* shear_run_checks.c — advisory checks of a finished simple_shear run (see the header). */
#include "shear_run_checks.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>

#include "run_context.h"

/* appends one formatted message to out[*n] */
__attribute__((format(printf, 3, 4))) static void
add_warning(char out[LUB_SHEAR_WARNINGS_MAX][LUB_SHEAR_WARNING_LEN], int *n, const char *fmt, ...)
{
    if (*n >= LUB_SHEAR_WARNINGS_MAX) /* cannot happen (the header counts them): dropped */
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(out[(*n)++], LUB_SHEAR_WARNING_LEN, fmt, ap);
    va_end(ap);
}

/* x rounded up to two significant digits (the factor a warning asks for must be enough: 1.306
 * printed with %.2g was "1.3") */
static double round_up_2(double x)
{
    if (!(x > 0.0) || !isfinite(x))
        return x;
    const double unit = pow(10.0, floor(log10(x)) - 1.0);
    return ceil(x / unit - 1e-9) * unit;
}

/* a NaN or infinite value (0/0, x/0 of an empty or zero series) fails no check */
static int exceeds(double value, double limit) { return isfinite(value) && value > limit; }
static int falls_below(double value, double limit) { return isfinite(value) && value < limit; }

/* What the unreached target's warning adds to the relative error rel: the 90 % upper bound
 * the stop tests, and why a run within the target did not stop. */
static const char *target_note(const lub_shear_run_state *st, double rel, char *buf, size_t len)
{
    const double bound = st->headline_rel_bound;
    if (!isfinite(bound))
        return rel <= st->target_rel_error ? ", within the target, but over less than "
                                             "/target_min_strain of steady window or before "
                                             "the last check (one a strain)"
                                           : "";
    if (bound <= st->target_rel_error)
        snprintf(buf, len,
                 " (90 %% upper bound %.2g), within the target, but over less than "
                 "/target_min_strain of steady window or before the last check (one a strain)",
                 bound);
    else if (rel <= st->target_rel_error)
        snprintf(buf, len,
                 ", within the target, but not its 90 %% upper bound %.2g, which the stop "
                 "tests",
                 bound);
    else
        snprintf(buf, len, " (90 %% upper bound %.2g)", bound);
    return buf;
}

int lub_shear_run_warnings(const lub_shear_run_state *st,
                           char out[LUB_SHEAR_WARNINGS_MAX][LUB_SHEAR_WARNING_LEN])
{
    int n = 0;
    const double el = st->elastic_number;
    const int jammed = isfinite(st->phi_imposed) && isfinite(st->phi_jamming) &&
                       st->phi_jamming > 0.0 && st->phi_imposed >= st->phi_jamming;
    if (jammed) {
        char measured[64] = ""; /* the values the replaced warnings would have quoted */
        if (isfinite(el) && isfinite(st->crushed_fraction))
            snprintf(measured, sizeof measured, "El = %.3g, %.2g %% of the contacts crushed; ", el,
                     100.0 * st->crushed_fraction);
        add_warning(out, &n,
                    "phi = %.4g is at or above the jamming fraction phi_m(mu_m = %.3g) = %.3f "
                    "of the seed's law (physics-reference section 2, +-0.01): rigid spheres "
                    "cannot flow there and the stress follows the stiffness (%sa stiffer run "
                    "is not more rigid); lower /phi or impose the pressure (/control)",
                    st->phi_imposed, st->mu_m, st->phi_jamming, measured);
    }
    if (!jammed && el > 0.0 && falls_below(el, LUB_SHEAR_EL_MIN))
        add_warning(out, &n,
                    "elastic number k/(P a) = %.3g is below %.0e: the contacts are not rigid "
                    "enough for rigid-sphere rheology (eta_r and phi still move with the "
                    "stiffness there); raise /stiffness by %.2g or more",
                    el, LUB_SHEAR_EL_MIN, round_up_2(LUB_SHEAR_EL_MIN / el));
    if (exceeds(st->kinetic_share, LUB_SHEAR_KINETIC_SHARE_MAX) ||
        exceeds(st->kinetic_share_pressure, LUB_SHEAR_KINETIC_SHARE_MAX))
        add_warning(out, &n,
                    "the kinetic stress is %.2g %% of sigma_xy and %.2g %% of -sigma_yy, above "
                    "%.0f %%: particle inertia enters the rheology; lower /St",
                    100.0 * st->kinetic_share, 100.0 * st->kinetic_share_pressure,
                    100.0 * LUB_SHEAR_KINETIC_SHARE_MAX);
    if (!jammed && exceeds(st->crushed_fraction, LUB_CRUSHED_CONTACT_FRACTION_MAX))
        add_warning(out, &n,
                    "asperities crushed in %.2g %% of the contacts (u_n < -alpha eps a), "
                    "above %.0f %%: the results depend on the stiffness; raise /stiffness",
                    100.0 * st->crushed_fraction, 100.0 * LUB_CRUSHED_CONTACT_FRACTION_MAX);
    const double q6_noise =
        isfinite(st->bond_order_random) ? LUB_SHEAR_Q6_NOISE * st->bond_order_random : 0.0;
    const double q6_limit = fmax(LUB_SHEAR_Q6_MAX, q6_noise);
    if (exceeds(st->bond_order_q6, q6_limit))
        add_warning(out, &n,
                    "bond order Q6 = %.3f is above %.2g: the cell is ordering "
                    "(disordered sheared packings give 0.04-0.09), a finite-size effect; "
                    "raise /n_particles or /radius_std",
                    st->bond_order_q6, q6_limit);
    const double dev = st->pressure_ratio - 1.0;
    const int sem_known = isfinite(st->pressure_ratio_sem);
    const double dev_sem = sem_known ? st->pressure_ratio_sem : 0.0;
    char sem_text[48] = " (no error bar)";
    if (sem_known)
        snprintf(sem_text, sizeof sem_text, " +- %.2g", dev_sem);
    const int undetermined = exceeds(dev_sem, LUB_SHEAR_PRESSURE_DEVIATION_MAX);
    if (exceeds(fabs(dev), LUB_SHEAR_PRESSURE_DEVIATION_MAX) &&
        (fabs(dev) > 3.0 * dev_sem || undetermined)) {
        if (st->steady)
            add_warning(out, &n,
                        "the servo did not hold the imposed pressure: the steady mean of "
                        "-sigma_yy is %.3g%s times P, so phi, mu and eta_r are not those of "
                        "/Iv; lower /servo/gain (studied: 0.25-4; default 1)",
                        st->pressure_ratio, sem_text);
        else /* the run may end before the servo has brought the cell to P */
            add_warning(out, &n,
                        "the imposed pressure was not reached: the mean of -sigma_yy after the "
                        "transient is %.3g%s times P, in a run without a detected steady state, "
                        "so phi, mu and eta_r are not those of /Iv; raise /strain (and, if "
                        "servo_rate sits at +-gain in the time series, lower /servo/gain)",
                        st->pressure_ratio, sem_text);
    }
    if (exceeds(st->pressure_rms_ratio, LUB_SHEAR_SERVO_PRESSURE_RMS_MAX))
        add_warning(out, &n,
                    "the pressure servo oscillates: -sigma_yy fluctuates by %.3g %% rms about its "
                    "steady mean (the default servo: 3-7 %%; imposed volume: 23-33 %%), so its "
                    "oscillation, not the suspension, sets the stress; lower /servo/gain, raise "
                    "/servo/filter_strain or lower /dt_safety (or /St: inertia slows the "
                    "particles' answer to the cell)",
                    100.0 * st->pressure_rms_ratio);
    const double off = st->headline / st->headline_law - 1.0;
    const double tol = st->headline_is_mu ? LUB_SHEAR_LAW_MU_TOL : LUB_SHEAR_LAW_ETA_TOL;
    const double phi_off = st->phi_law > 0.0 ? st->phi_mean - st->phi_law : NAN;
    if (!st->article_set && st->steady && st->headline_law > 0.0 &&
        (exceeds(fabs(off), tol) || exceeds(fabs(phi_off), LUB_SHEAR_LAW_PHI_TOL))) {
        char phi_text[80] = "", phi_tol[24] = "", tol_text[40];
        if (isfinite(phi_off)) {
            snprintf(phi_text, sizeof phi_text, ", phi %.3f is %+.3f from its %.3f", st->phi_mean,
                     phi_off, st->phi_law);
            snprintf(phi_tol, sizeof phi_tol, " and %.3g in phi", LUB_SHEAR_LAW_PHI_TOL);
        }
        snprintf(tol_text, sizeof tol_text, "%.0f %%%s", 100.0 * tol, phi_tol);
        add_warning(out, &n,
                    "%s = %.3g is %+.0f %% from the reference law's %.3g%s (physics-reference "
                    "section 2; tolerance %s): the law was fitted with the seed article's "
                    "interaction set, which this run does not use (README, Where we disagree, "
                    "7); set /lubrication_pairs \"delaunay\", /law/terms/roll and "
                    "/law/terms/twist false to compare with it",
                    st->headline_is_mu ? "mu" : "eta_r", st->headline, 100.0 * off,
                    st->headline_law, phi_text, tol_text);
    }
    const int dt_fixed = st->dt_over_elastic > 0.0;
    const int room = n < LUB_SHEAR_WARNINGS_MAX; /* always (the header counts them) */
    if (room && exceeds(st->dt_over_elastic, LUB_SHEAR_DT_OVER_ELASTIC_MAX))
        lub_fixed_dt_warning(out[n++], LUB_SHEAR_WARNING_LEN, st->dt_over_elastic, "dt_elastic");
    else if (room && exceeds(st->dt_over_stiffness, LUB_SHEAR_DT_STIFFNESS_MAX))
        lub_fixed_dt_stiffness_warning(out[n++], LUB_SHEAR_WARNING_LEN, st->dt_over_stiffness,
                                       LUB_SHEAR_DT_STIFFNESS_MAX);
    if (exceeds(st->lost_pairs, 0.0))
        add_warning(out, &n,
                    "%.0f active pair states were lost at neighbour-list rebuilds "
                    "(contacts restarted without their history); raise /skin or lower %s",
                    st->lost_pairs, dt_fixed ? "/dt" : "/dt_safety");
    const int after_transient = !(st->strain_reached < st->transient_strain);
    if (!st->steady && st->stopped)
        add_warning(out, &n,
                    "the run was stopped by a signal at strain %.3g of /strain %g, %s: %s; %s",
                    st->strain_reached, st->strain_target,
                    after_transient ? "before a steady state was detected"
                                    : "inside the transient (/transient_strain)",
                    st->steady_samples == 0.0
                        ? "there are no steady-state samples and the steady-state results are null"
                        : "the means are not steady-state values",
                    st->checkpoint_kept ? LUB_RESUME_ADVICE
                                        : "its checkpoint could not be written: run it again");
    else if (!st->steady && st->steady_samples == 0.0 && after_transient &&
             st->sample_strain > st->strain_reached - st->transient_strain &&
             st->strain_reached - st->transient_strain < LUB_SHEAR_SAMPLE_SPAN_MIN)
        add_warning(out, &n,
                    "no steady-state samples: the run ended at strain %.3g, only %.3g after "
                    "/transient_strain %.3g, and the steady-state results are null; raise "
                    "/strain above /transient_strain",
                    st->strain_reached, st->strain_reached - st->transient_strain,
                    st->transient_strain);
    else if (!st->steady && st->steady_samples == 0.0 && after_transient &&
             st->sample_strain > st->strain_reached - st->transient_strain)
        add_warning(out, &n,
                    "no steady-state samples: one sample is taken every /sample_strain %.3g of "
                    "strain, more than the run's %.3g after /transient_strain %.3g (it ended at "
                    "strain %.3g), and the steady-state results are null; lower /sample_strain "
                    "(or raise /strain)",
                    st->sample_strain, st->strain_reached - st->transient_strain,
                    st->transient_strain, st->strain_reached);
    else if (!st->steady && st->steady_samples == 0.0 && after_transient)
        add_warning(out, &n,
                    "no steady-state samples after /transient_strain %.3g (the run ended at "
                    "strain %.3g), and the steady-state results are null; raise /strain",
                    st->transient_strain, st->strain_reached);
    else if (!st->steady && st->steady_samples == 0.0)
        add_warning(out, &n,
                    "no steady-state samples: the run ended at strain %.3g, inside the "
                    "transient (/transient_strain %.3g), and the steady-state results are null; "
                    "raise /strain above /transient_strain",
                    st->strain_reached, st->transient_strain);
    else if (!st->steady)
        add_warning(out, &n, "%s",
                    "no steady state detected (the transient lasts into the "
                    "second half of the run, or the watched series drift after it): the means "
                    "are not steady-state values; raise /strain");
    if (st->steady && falls_below(st->pdf_first_strain, st->steady_from_strain - 1e-9))
        add_warning(out, &n,
                    "the microstructure (/profiles) is averaged from strain %.4g, before the "
                    "steady state detected from strain %.4g: its maps mix in the transient; "
                    "raise /microstructure/start_strain to %.3g or more",
                    st->pdf_first_strain, st->steady_from_strain, st->steady_from_strain);
    /* a target error the run did not reach before /strain (a stopped run's advice is above; a
     * failed run did not end at /strain, and its diagnostic says why: until 2026-12-07 it was
     * told to raise /strain) */
    const double rel = fabs(st->headline_sem / st->headline);
    char note[160];
    if (st->target_rel_error > 0.0 && !st->stopped_on_target && !st->stopped && !st->failed &&
        !st->target_zero_mean && isfinite(rel))
        add_warning(out, &n,
                    "the run ended at /strain %g without stopping on /target_rel_error %g: the "
                    "relative error of %s is %.2g%s; raise /strain (lubdem run --keep-checkpoint "
                    "lets a run be extended)",
                    st->strain_target, st->target_rel_error, st->headline_is_mu ? "mu" : "eta_r",
                    rel, target_note(st, rel, note, sizeof note));
    return n;
}

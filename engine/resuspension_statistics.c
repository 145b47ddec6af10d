/* resuspension_statistics.c — the steady-state statistics of a resuspension run
 * (resuspension_statistics.h).
 */
#include "resuspension_statistics.h"

#include <math.h>

#include "resuspension_analysis.h"
#include "stats.h"

/* Seed's laws (resuspension article eq. 8–9). */
static double eta22_law(double phi, double phi_m)
{
    const double x = phi / phi_m;
    if (!(x < 1.0))
        return INFINITY;
    return pow(x, 9.0) / ((1.0 - x) * (1.0 - x)) + 150.0 * pow(x, 10.0);
}
static double lambda33_law(double phi)
{
    const double x = phi / 0.64;
    return pow(x, 7.5) / (1e-3 + pow(x, 6.0));
}

/* Standard error of the mean of x[0..n) by the stats.h rule (AR(1)-corrected batch means),
 * the naive SEM below LUB_STATS_MIN_BATCHES samples (then *batch_means = 0); NaN below 2. */
static double rs_series_sem(const double *x, int64_t n, double *scratch, int *batch_means)
{
    if (n <= 0)
        return NAN;
    double sem = lub_stats_sem(x, (size_t)n, scratch);
    if (!(sem >= 0.0) && n >= 2) {
        sem = sqrt(lub_stats_var(x, (size_t)n) / (double)n);
        *batch_means = 0;
    }
    return sem;
}

/* The time-averaged phi of every bin and its standard error; 1 when every error is a
 * batch-means one. */
static int rs_average_profile(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out)
{
    const int nb = in->nb;
    const int64_t navg = in->navg;
    int sem_batch_means = 1;
    for (int i = 0; i < nb; ++i) {
        out->y[i] = (i + 0.5) * in->dy;
        for (int64_t j = 0; j < navg; ++j)
            out->scratch[j] = in->samples[j * nb + i];
        out->phi[i] = navg > 0 ? lub_stats_mean(out->scratch, (size_t)navg) : NAN;
        out->phi_err[i] = rs_series_sem(out->scratch, navg, out->scratch2, &sem_batch_means);
    }
    return sem_batch_means;
}

/* The standard errors of eta_ii(y) and of the coarse-grained phi: each sample's own eta_ii(y)
 * (the cumulative sum of lub_profile_normal_viscosity, same order) and coarse phi
 * (lub_profile_coarse_bin) form a series per bin, whose standard error is taken as phi_err's
 * (rs_series_sem). Neighbouring bins are correlated (a sphere spans several bins, the
 * inventory is fixed), so no propagation of phi_err can give these (navg > 0). */
static int rs_derived_errors(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out)
{
    const int nb = in->nb;
    const int64_t navg = in->navg;
    const double dy = in->dy;
    int batch_means = 1;
    double *above = out->scratch3;
    for (int64_t k = 0; k < navg; ++k)
        above[k] = 0.0;
    for (int i = nb - 1; i >= 0; --i) {
        for (int64_t k = 0; k < navg; ++k) {
            const double phik = in->samples[k * nb + i];
            out->scratch[k] = (above[k] + 0.5 * phik * dy) / in->shields;
            above[k] += phik * dy;
        }
        out->eta_err[i] = rs_series_sem(out->scratch, navg, out->scratch2, &batch_means);
    }
    for (int i = 0; i < nb; ++i) {
        for (int64_t k = 0; k < navg; ++k)
            out->scratch[k] =
                lub_profile_coarse_bin(in->samples + k * nb, nb, dy, in->phi_window, i);
        out->phi_coarse_err[i] = rs_series_sem(out->scratch, navg, out->scratch2, &batch_means);
    }
    return batch_means;
}

/* The standard error of the suspension height: stats.h standard error of the instantaneous
 * heights of the averaging window (navg > 0). */
static double rs_height_error(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out)
{
    const int64_t navg = in->navg;
    size_t h0i = (size_t)(in->nh - navg);
    lub_stats_result hr;
    lub_stats_analyse(in->height + h0i, (size_t)navg, 0, out->scratch2, &hr);
    double hs_sem = hr.sem;
    if (!(hs_sem >= 0.0) && navg >= LUB_STATS_MIN_BATCHES) {
        /* too few samples after the MSER cut: batch means over the whole averaging
         * window, as phi_err */
        lub_stats_analyse_window(in->height + h0i, (size_t)navg, 0, out->scratch2, &hr);
        hs_sem = hr.sem;
    } else if (!(hs_sem >= 0.0) && navg >= 2) {
        /* fewer than 32 averaged samples: the naive SEM, as phi_err (phi_err_method) */
        hs_sem = sqrt(lub_stats_var(in->height + h0i, (size_t)navg) / (double)navg);
    }
    return hs_sem;
}

/* The seed's law at every bin's coarse-grained phi, the bulk bins' eta_ii(phi) rows and the
 * log-rms distance of their eta from the law (st). */
static void rs_compare_law(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out,
                           lub_rs_stats *st)
{
    double s2 = 0.0;
    int nl = 0, q = 0;
    for (int i = 0; i < in->nb; ++i) {
        double lw = eta22_law(out->phi_coarse[i], in->phi_m);
        if (in->vorticity)
            lw *= lambda33_law(out->phi_coarse[i]);
        out->law[i] = isfinite(lw) ? lw : NAN;
        out->bulk_mask[i] = out->bulk[i];
        if (out->bulk[i]) {
            out->eta_vs_phi[4 * q + 0] = out->phi_coarse[i];
            out->eta_vs_phi[4 * q + 1] = out->phi_coarse_err[i];
            out->eta_vs_phi[4 * q + 2] = out->eta[i];
            out->eta_vs_phi[4 * q + 3] = out->eta_err[i];
            ++q;
            if (isfinite(lw) && lw > 0.0 && out->eta[i] > 0.0) {
                double d = log(out->eta[i] / lw);
                s2 += d * d;
                ++nl;
            }
        }
    }
    st->eta_vs_phi_rows = q;
    st->law_log_rms = nl > 0 ? sqrt(s2 / nl) : NAN;
}

/* The mean flow-direction velocity per bin and its least-squares slope over the bulk bins
 * (NaN below three). */
static double rs_velocity_profile(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out)
{
    double bulk_rate = NAN;
    double sw = 0, sy = 0, sv = 0, syy = 0, syv = 0;
    for (int i = 0; i < in->nb; ++i) {
        out->velocity_x[i] = in->vx_volume[i] > 0.0 ? in->vx_sum[i] / in->vx_volume[i] : NAN;
        if (out->bulk[i] && isfinite(out->velocity_x[i])) {
            sw += 1.0;
            sy += out->y[i];
            sv += out->velocity_x[i];
            syy += out->y[i] * out->y[i];
            syv += out->y[i] * out->velocity_x[i];
        }
    }
    if (sw >= 3.0)
        bulk_rate = (sw * syv - sy * sv) / (sw * syy - sy * sy);
    return bulk_rate;
}

void lub_rs_statistics(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out,
                       lub_rs_stats *st)
{
    const int nb = in->nb;
    const double dy = in->dy;
    st->steady = 0;
    st->transient_end =
        in->nh >= 10 ? lub_stats_mser(in->height, (size_t)in->nh, 5, &st->steady) : 0;
    st->sem_batch_means = rs_average_profile(in, out);
    st->height = NAN;
    st->height_err = NAN;
    st->inventory = NAN;
    st->max_phi = NAN;
    st->bulk_bins = -1;
    st->eta_vs_phi_rows = 0;
    st->law_log_rms = NAN;
    st->bulk_velocity_slope = NAN;
    if (in->navg <= 0)
        return;
    st->max_phi = 0.0;
    for (int i = 0; i < nb; ++i)
        st->max_phi = fmax(st->max_phi, out->phi[i]);
    st->height = lub_profile_height(out->phi, nb, 0.0, dy, 0.5 * st->max_phi);
    st->height_err = rs_height_error(in, out);
    st->inventory = lub_profile_inventory(out->phi, nb, dy);
    lub_profile_normal_viscosity(out->phi, NULL, nb, dy, in->shields, out->eta, NULL);
    st->bulk_bins = lub_profile_select_bulk(out->phi, nb, 0.0, dy, in->interface_width,
                                            in->floor_skip, in->phi_min, out->bulk);
    /* eta_ii(phi) pairs the exact eta_ii(y) with phi averaged over phi_window (layering) */
    lub_profile_coarse_grain(out->phi, NULL, nb, dy, in->phi_window, out->phi_coarse, NULL);
    if (!rs_derived_errors(in, out))
        st->sem_batch_means = 0;
    rs_compare_law(in, out, st);
    st->bulk_velocity_slope = rs_velocity_profile(in, out);
}

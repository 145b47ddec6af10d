/* resuspension_statistics.c — the steady-state statistics of a resuspension run
 * (resuspension_statistics.h).
 */
#include "resuspension_statistics.h"

#include <math.h>

#include "continuum_normal_laws.h"
#include "resuspension_analysis.h"
#include "stats.h"

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

/* The first-order change of the linearly interpolated crossing y = y_lo + dy (L - phi_lo) /
 * (phi_hi - phi_lo) of the level L = phi_m/2 (m the bin of the maximum) between the bins lo and
 * hi = lo + 1 with phi_lo, phi_hi and phi_m: the coefficients of the three bins. */
typedef struct {
    int lo, hi, m;
    double g_lo, g_hi, g_m;
} rs_crossing_grad;

static rs_crossing_grad rs_crossing(const double *phi, int lo, int m, double level, double dy)
{
    const double d = phi[lo + 1] - phi[lo];
    rs_crossing_grad g = {lo, lo + 1, m, 0.0, 0.0, 0.0};
    g.g_lo = dy * (level - phi[lo + 1]) / (d * d);
    g.g_hi = -dy * (level - phi[lo]) / (d * d);
    g.g_m = 0.5 * dy / d;
    return g;
}

static double rs_crossing_change(const rs_crossing_grad *g, const double *s, const double *phi)
{
    return g->g_lo * (s[g->lo] - phi[g->lo]) + g->g_hi * (s[g->hi] - phi[g->hi]) +
           g->g_m * (s[g->m] - phi[g->m]);
}

/* The standard error (rs_series_sem) of the first-order change of the crossing `plus` minus that
 * of `minus` over the averaging window's samples; a NULL crossing contributes no change. */
static double rs_crossings_sem(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out,
                               const rs_crossing_grad *plus, const rs_crossing_grad *minus)
{
    for (int64_t k = 0; k < in->navg; ++k) {
        const double *s = in->samples + k * in->nb;
        out->scratch[k] = (plus ? rs_crossing_change(plus, s, out->phi) : 0.0) -
                          (minus ? rs_crossing_change(minus, s, out->phi) : 0.0);
    }
    int batch_means = 1;
    return rs_series_sem(out->scratch, in->navg, out->scratch2, &batch_means);
}

/* The standard errors of the suspension height (the top half-maximum crossing h of the averaged
 * profile), of the bed's base (its bottom crossing y_b) and of their difference h - y_b: the
 * first-order change of each with every sample's deviation from the averaged profile (delta
 * method, as lub_stats_ratio) forms a series whose standard error is taken as phi_err's
 * (rs_series_sem). Each crossing depends on the two bins around it and on the bin of the
 * maximum only, so the value and its error describe the same quantity over the same samples
 * (the whole averaging window). A crossing that is not interpolated (the top bin still above
 * half the maximum, or the bottom bin already at it) has a NaN error and, in the difference,
 * no first-order change (it sits at a bin centre). */
static void rs_crossing_errors(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out,
                               double max_phi, lub_rs_stats *st)
{
    const int nb = in->nb;
    const double dy = in->dy, level = 0.5 * max_phi;
    int m = 0, top = -1, bot = -1;
    st->height_err = st->bed_base_err = st->thickness_err = NAN;
    if (!(max_phi > 0.0))
        return;
    for (int j = 0; j < nb; ++j)
        if (out->phi[j] > out->phi[m])
            m = j;
    for (int j = nb - 1; j >= 0; --j)
        if (out->phi[j] >= level) {
            top = j;
            break;
        }
    for (int j = 0; j < nb; ++j)
        if (out->phi[j] >= level) {
            bot = j;
            break;
        }
    /* the interpolated crossings (NULL: none, or at a bin centre) */
    rs_crossing_grad gt, gb;
    const rs_crossing_grad *t = NULL, *b = NULL;
    if (top >= 0 && top < nb - 1) { /* the bins top (>= L) and top + 1 (< L) */
        gt = rs_crossing(out->phi, top, m, level, dy);
        t = &gt;
    }
    if (bot > 0) { /* the bins bot - 1 (< L) and bot (>= L) */
        gb = rs_crossing(out->phi, bot - 1, m, level, dy);
        b = &gb;
    }
    if (t)
        st->height_err = rs_crossings_sem(in, out, t, NULL);
    if (b)
        st->bed_base_err = rs_crossings_sem(in, out, b, NULL);
    st->thickness_err = rs_crossings_sem(in, out, t, b);
}

/* Whether the suspension height is steady over the averaging window (the last navg of the nh
 * height samples): MSER-5 on the window does not cut in its search limit (which needs 10
 * samples) and the drift test of the samples after its cut passes (|z| <= 3; skipped when fewer
 * than 2 x 32 samples follow the cut, as it needs 32 per half). */
static int rs_height_steady(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out,
                            size_t *cut)
{
    const size_t n = (size_t)in->navg;
    const double *h = in->height + (in->nh - in->navg);
    int mser_steady = 0;
    *cut = 0;
    if (n < LUB_RS_STEADY_MIN_SAMPLES)
        return 0;
    *cut = lub_stats_mser(h, n, 5, &mser_steady);
    const double z = lub_stats_drift_z(h + *cut, n - *cut, out->scratch2);
    return mser_steady && !(fabs(z) > 3.0);
}

/* The seed's law at every bin's coarse-grained phi, the bulk bins' eta_ii(phi) rows and the
 * log-rms distance of their eta from the law (st). */
static void rs_compare_law(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out,
                           lub_rs_stats *st)
{
    double s2 = 0.0;
    int nl = 0, q = 0;
    for (int i = 0; i < in->nb; ++i) {
        /* the seed's laws (resuspension article eq. 9, and eq. 8 for the vorticity
         * orientation), none at and above phi_m */
        const double psi = out->phi_coarse[i] / in->phi_m;
        double lw = psi < 1.0 ? lub_dem_eta22(psi) : INFINITY;
        if (in->vorticity)
            lw *= lub_dem_lambda33(out->phi_coarse[i], 0.64);
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

/* The mean flow-direction velocity per bin, its least-squares slope over the bulk bins (NaN
 * below three) and that slope's standard error (st). The slope is b = sum_i c_i v_i over the n
 * bulk bins a sphere crossed, c_i = (n y_i - sum y)/(n sum y^2 - (sum y)^2) and v_i = S_i/V_i
 * the ratio of the window's velocity sum and volume. A sample k moves S_i by s_ik and V_i by
 * vol_ik, so to first order b by its change
 *     d_k = sum_i c_i (s_ik - v_i vol_ik) / (V_i / navg)
 * (delta method, as lub_stats_ratio), whose mean over the window is 0 (sum_k s_ik = S_i =
 * v_i V_i); the error is the standard error of the series d_k (rs_series_sem). */
static void rs_velocity_profile(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out,
                                lub_rs_stats *st)
{
    const int nb = in->nb;
    double sw = 0, sy = 0, sv = 0, syy = 0, syv = 0;
    st->bulk_velocity_slope = st->bulk_velocity_slope_err = NAN;
    for (int i = 0; i < nb; ++i) {
        out->velocity_x[i] = in->vx_volume[i] > 0.0 ? in->vx_sum[i] / in->vx_volume[i] : NAN;
        if (out->bulk[i] && isfinite(out->velocity_x[i])) {
            sw += 1.0;
            sy += out->y[i];
            sv += out->velocity_x[i];
            syy += out->y[i] * out->y[i];
            syv += out->y[i] * out->velocity_x[i];
        }
    }
    if (sw < 3.0)
        return;
    const double den = sw * syy - sy * sy;
    st->bulk_velocity_slope = (sw * syv - sy * sv) / den;
    if (!in->vx_samples)
        return;
    for (int64_t k = 0; k < in->navg; ++k) {
        const double *s = in->vx_samples + k * nb, *phi = in->samples + k * nb;
        double d = 0.0;
        for (int i = 0; i < nb; ++i)
            if (out->bulk[i] && isfinite(out->velocity_x[i])) {
                const double c = (sw * out->y[i] - sy) / den;
                const double vol = phi[i] * in->bin_volume;
                d += c * (s[i] - out->velocity_x[i] * vol) / (in->vx_volume[i] / (double)in->navg);
            }
        out->scratch[k] = d;
    }
    int batch_means = 1;
    st->bulk_velocity_slope_err =
        rs_series_sem(out->scratch, in->navg, out->scratch2, &batch_means);
}

/* The mean share of the buoyant weight the shear drag carries over the samples and its standard
 * error (rs_series_sem), from the per-sample series (NaN without it). */
static void rs_drag_share(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out,
                          lub_rs_stats *st)
{
    int batch_means = 1;
    st->drag_share = st->drag_share_err = NAN;
    if (!in->drag_share || in->navg <= 0)
        return;
    st->drag_share = lub_stats_mean(in->drag_share, (size_t)in->navg);
    st->drag_share_err = rs_series_sem(in->drag_share, in->navg, out->scratch2, &batch_means);
}

void lub_rs_statistics(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out,
                       lub_rs_stats *st)
{
    const int nb = in->nb;
    const double dy = in->dy;
    st->steady = 0;
    st->window_cut = 0;
    int whole_steady = 0;
    st->transient_end =
        in->nh >= 10 ? lub_stats_mser(in->height, (size_t)in->nh, 5, &whole_steady) : 0;
    /* the height's transient (whole series) outlasting the start of the averaging window, or
     * reaching it with MSER-5 stopped by its search limit (the transient may go on) */
    const int64_t start = in->nh - in->navg;
    st->transient_in_window =
        in->navg > 0 && ((int64_t)st->transient_end > start ||
                         (!whole_steady && (int64_t)st->transient_end >= start));
    st->sem_batch_means = rs_average_profile(in, out);
    st->height = NAN;
    st->height_err = NAN;
    st->bed_base = NAN;
    st->bed_base_err = NAN;
    st->thickness_err = NAN;
    st->relative_height_increase = NAN;
    st->relative_height_increase_err = NAN;
    st->relative_height_increase_floor_plane = NAN;
    st->relative_height_increase_floor_plane_err = NAN;
    st->inventory = NAN;
    st->max_phi = NAN;
    st->bulk_bins = -1;
    st->eta_vs_phi_rows = 0;
    st->law_log_rms = NAN;
    st->bulk_velocity_slope = NAN;
    st->bulk_velocity_slope_err = NAN;
    rs_drag_share(in, out, st);
    if (in->navg <= 0)
        return;
    st->max_phi = 0.0;
    for (int i = 0; i < nb; ++i)
        st->max_phi = fmax(st->max_phi, out->phi[i]);
    st->steady = rs_height_steady(in, out, &st->window_cut);
    st->height = lub_profile_height(out->phi, nb, 0.0, dy, 0.5 * st->max_phi);
    st->bed_base = lub_profile_base(out->phi, nb, 0.0, dy, 0.5 * st->max_phi);
    rs_crossing_errors(in, out, st->max_phi, st);
    st->inventory = lub_profile_inventory(out->phi, nb, dy);
    /* (h - y_b - h0)/h0 with h0 = inventory/phi_m: the bed's rise above its own base, not above
     * the floor centre plane (y_b ~1.1 a there, the spheres resting on the floor's) */
    const double h0 = st->inventory / in->phi_m;
    st->relative_height_increase = (st->height - st->bed_base - h0) / h0;
    st->relative_height_increase_err = st->thickness_err / h0;
    st->relative_height_increase_floor_plane = (st->height - h0) / h0;
    st->relative_height_increase_floor_plane_err = st->height_err / h0;
    lub_profile_normal_viscosity(out->phi, NULL, nb, dy, in->shields, out->eta, NULL);
    st->bulk_bins = lub_profile_select_bulk(out->phi, nb, 0.0, dy, in->interface_width,
                                            in->floor_skip, in->phi_min, out->bulk);
    /* eta_ii(phi) pairs the exact eta_ii(y) with phi averaged over phi_window (layering) */
    lub_profile_coarse_grain(out->phi, NULL, nb, dy, in->phi_window, out->phi_coarse, NULL);
    if (!rs_derived_errors(in, out))
        st->sem_batch_means = 0;
    rs_compare_law(in, out, st);
    rs_velocity_profile(in, out, st);
}

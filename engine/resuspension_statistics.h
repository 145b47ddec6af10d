/* resuspension_statistics.h — the steady-state statistics of a resuspension run
 * (scene_resuspension.c), also of a partial run (whatever was averaged): from the instantaneous
 * phi(y) profiles and suspension heights the run sampled, the time-averaged phi(y) with the
 * stats.h error bars, the suspension height (phi crosses half its maximum) and its error, the
 * inventory, eta_ii(y) = (1/Sh) int_y^inf phi (eq. 6), the bulk bins (lub_profile_select_bulk),
 * the bulk points eta_ii(phi) with phi averaged over phi_window (lub_profile_coarse_grain, so
 * that the layering next to the floor does not bias them), the seed's laws at that phi (eq. 9;
 * for the vorticity orientation eta_33 = lambda_33 eta_22 with eq. 8) with the log-rms distance
 * of the bulk points from them, and the mean flow-direction velocity per bin with its
 * least-squares slope over the bulk bins. Whether the height is steady: MSER-5 and the drift
 * test over the averaging window; the end of its transient: MSER-5 on the whole height series.
 * The height is the top half-maximum crossing of the averaged profile and its error the SEM of
 * its first-order change with each sample's profile (delta method), both over the whole window;
 * the bed's base y_b is the bottom crossing, with its error by the same rule, and the relative
 * height increase (h - y_b - h0)/h0 (h0 = inventory/phi_m) has the error of h - y_b. The
 * velocity slope's error is the SEM of its first-order change with each sample's per-bin
 * velocity sums and volumes (delta method, as the height's); the gradient orientation's share
 * of the buoyant weight the shear drag carries is the mean of its per-sample series, with that
 * series' SEM (both since 2026-12-08; null before).
 *
 * Units: those of the scene (length a, time 1/gd, viscosity eta; velocities in a gd; phi and
 * eta_ii/eta dimensionless); y is measured from the floor centre plane.
 * Ownership: nothing is kept; every array is the caller's (the outputs nb long unless said
 * otherwise). Pure function: no I/O, no allocation, no global state.
 * Errors: none; a value the samples cannot give is NaN (no averaged sample; fewer than 2 for an
 * error bar; a law at phi >= phi_m).
 */
#ifndef LUBDEM_RESUSPENSION_STATISTICS_H
#define LUBDEM_RESUSPENSION_STATISTICS_H

#include <stddef.h>
#include <stdint.h>

/* Averaged samples MSER-5 needs to judge whether the height is steady (below: never steady). */
#define LUB_RS_STEADY_MIN_SAMPLES 10

typedef struct {
    int nb;                /* bins; bin i covers [i dy, (i + 1) dy) above the floor centre plane */
    double dy;             /* bin width (a) */
    const double *samples; /* navg profiles of nb instantaneous phi, one after the other */
    int64_t navg;          /* averaged samples (from /average_from on) */
    const double *height;  /* nh suspension-height samples (a), the last navg averaged */
    int64_t nh;
    const double *vx_volume; /* per bin, summed over the averaged samples: the spheres' volume */
    const double *vx_sum;    /* ... and their volume-weighted v_x relative to the floor-plane
                                mean flow */
    /* navg profiles of nb, one after the other: each averaged sample's own vx_sum terms (NULL:
     * none, and bulk_velocity_slope_err is NaN). The sample's sphere volume in a bin is not
     * stored: lub_profile_normalise made samples[k nb + i] of it times 1/bin_volume (one
     * constant for the run), so it is samples[k nb + i] x bin_volume up to the rounding of the
     * two products (relative 1e-16) */
    const double *vx_samples;
    double bin_volume; /* the cell's cross-section times dy (a^3) */
    /* gradient: navg per-sample shares of the buoyant weight the shear drag carries (NULL:
     * none, the vorticity orientation or a run continued from a checkpoint without them; then
     * drag_share and its error are NaN) */
    const double *drag_share;
    double shields;                              /* Sh of eta_ii = (1/Sh) int phi */
    double interface_width, floor_skip, phi_min; /* the bulk selection */
    double phi_m;                                /* the eta_22 law's jamming fraction */
    double phi_window;                           /* coarse graining of phi in eta_ii(phi) (a) */
    int vorticity; /* 1: the vorticity orientation (eta_33 = lambda_33 eta_22) */
} lub_rs_stats_input;

typedef struct {
    double *y;                           /* bin centres (a) */
    double *phi, *phi_err;               /* time-averaged phi and its standard error */
    double *phi_coarse, *phi_coarse_err; /* phi averaged over phi_window */
    double *eta, *eta_err;               /* eta_ii(y)/eta */
    /* every error: the standard error (stats.h rule, naive below LUB_STATS_MIN_BATCHES samples)
     * of the bin's series of per-sample values (phi, coarse phi, eta_ii of that sample) */
    double *law;        /* the seed's law at phi_coarse (NaN: none) */
    int *bulk;          /* 1: a bulk bin */
    double *bulk_mask;  /* the same as 1.0 or 0.0 (for the output) */
    double *velocity_x; /* mean v_x (a gd; NaN where no sphere passed) */
    double *eta_vs_phi; /* 4 nb: the bulk bins' (phi_coarse, its error, eta, its error) */
    double *scratch, *scratch2, *scratch3; /* max(nh, navg) + 1 each, overwritten */
} lub_rs_stats_profiles;

typedef struct {
    int steady;                 /* 1: the height is steady over the averaging window: MSER-5 on
                                   its samples does not cut in the search limit (needs 10) and
                                   the drift test after the cut passes (when >= 64 follow it) */
    size_t window_cut;          /* the window's samples MSER-5 cut there (0 below 10) */
    size_t transient_end;       /* the samples MSER-5 cuts from the whole height series (0
                                   without 10): the end of the height's transient */
    int transient_in_window;    /* 1: transient_end falls after the averaging window's start,
                                   or at it with MSER-5 stopped by its search limit */
    int sem_batch_means;        /* 1: every error bar is a batch-means one; 0: some bin's is the
                                   naive SEM (fewer than LUB_STATS_MIN_BATCHES samples) */
    double height, height_err;  /* suspension height of the averaged profile and its error (a;
                                   error NaN when the crossing is not interpolated) */
    double inventory;           /* int phi dy (a) */
    double max_phi;             /* of the averaged profile (NaN without a sample) */
    int bulk_bins;              /* bins selected as bulk (-1 without a sample) */
    int eta_vs_phi_rows;        /* rows of eta_vs_phi */
    double law_log_rms;         /* rms of log(eta / law) over the bulk bins */
    double bulk_velocity_slope; /* d<v_x>/dy over the bulk bins (gd; NaN below 3 bins) */
    /* its error: the SEM (rs_series_sem's rule) of the series over the samples k of its
     * first-order change sum_i c_i (s_ik - v_i vol_ik) / (V_i / navg), c_i the least-squares
     * coefficients of the bulk bins, s_ik and vol_ik the sample's velocity sum and volume in
     * bin i, V_i the window's volume and v_i its mean velocity (gd; NaN with the slope or
     * without vx_samples) */
    double bulk_velocity_slope_err;
    /* the mean of the per-sample drag shares and its SEM (1; NaN without drag_share) */
    double drag_share, drag_share_err;
    /* the bed's base y_b, the bottom half-maximum crossing of the averaged profile
     * (lub_profile_base), and its error (a; the delta method of height_err; NaN when the
     * crossing is not interpolated) */
    double bed_base, bed_base_err;
    /* the error of height - bed_base (the same delta method; a crossing that is not
     * interpolated contributes no change) */
    double thickness_err;
    /* (h - y_b - h0)/h0 with h0 = inventory/phi_m, and thickness_err/h0 (since 2026-12-07) */
    double relative_height_increase, relative_height_increase_err;
    /* (h - h0)/h0 and height_err/h0: h from the floor centre plane (before 2026-12-07 the
     * summary's relative_height_increase) */
    double relative_height_increase_floor_plane, relative_height_increase_floor_plane_err;
} lub_rs_stats;

void lub_rs_statistics(const lub_rs_stats_input *in, const lub_rs_stats_profiles *out,
                       lub_rs_stats *st);

#endif

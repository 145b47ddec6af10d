/* resuspension_summary.c — the results of a resuspension run into result.h5 and the summary
 * (resuspension_summary.h).
 */
#include "resuspension_summary.h"

#include <math.h>
#include <stdio.h>

#include "law_spec.h"
#include "network_output.h"
#include "resuspension_analysis.h"
#include "shear_run_checks.h"

/* The share of the weight the shear drag may carry before eta_normal is flagged (README,
 * resuspension Caveat): 2 %, ten times the agreement of eq. 6 with the pair network's sigma_yy
 * where no drag acts (0.06-0.2 %, vorticity runs of the 2026-12-06 audit), and a third of the
 * 6.5 % of a 20-strain gradient run flagged steady (audit gL). */
#define RS_DRAG_SHARE_MAX 0.02

static int write_profiles(lub_h5 *h5, const char *name, int n, const double *data, const char *unit)
{
    int64_t dims[1] = {n};
    return lub_h5_write_array(h5, name, 1, dims, data, unit);
}

int lub_rs_write_profiles(lub_h5 *out, int nb, const lub_rs_stats_profiles *pr, int rows)
{
    int wr = write_profiles(out, "y", nb, pr->y, "a") ||
             write_profiles(out, "phi", nb, pr->phi, "1") ||
             write_profiles(out, "phi_err", nb, pr->phi_err, "1") ||
             write_profiles(out, "phi_coarse", nb, pr->phi_coarse, "1") ||
             write_profiles(out, "phi_coarse_err", nb, pr->phi_coarse_err, "1") ||
             write_profiles(out, "eta_normal", nb, pr->eta, "1") ||
             write_profiles(out, "eta_normal_err", nb, pr->eta_err, "1") ||
             write_profiles(out, "bulk_mask", nb, pr->bulk_mask, "1") ||
             write_profiles(out, "eta_normal_law", nb, pr->law, "1") ||
             write_profiles(out, "velocity_x", nb, pr->velocity_x, "a gd");
    if (!wr) { /* also without a bulk bin: (0, 4), so that readers find it */
        int64_t dims[2] = {rows, 4};
        wr = lub_h5_write_array(out, "eta_vs_phi", 2, dims, pr->eta_vs_phi, "1") ||
             lub_h5_profile_note(out, "eta_vs_phi", "columns",
                                 "phi_coarse, phi_coarse_err, eta_normal, eta_normal_err (one "
                                 "row per bulk bin, bottom to top)");
    }
    return wr ? -1 : 0;
}

/* The crushed share of the contacts over the averaged samples (0 without contacts; NaN, not
 * measured, without an averaged sample: a run stopped before /average_from). */
static double rs_crushed_fraction(const lub_rs_outcome *o)
{
    if (o->averaged_samples <= 0)
        return NAN;
    return o->contacts_sum > 0 ? o->crushed_sum / o->contacts_sum : 0.0;
}

/* Gradient orientation: the mean share of the buoyant weight the shear drag carries over the
 * averaged samples, the mean of their series (lub_rs_stats.drag_share, NaN without the series;
 * its error drag_share_err); a run continued from a checkpoint without the series (before
 * 2026-12-08) has only their sum, and no error (NaN without a sample, or from a checkpoint older
 * than the sum). eta_ii(y) = (1/Sh) int phi takes the whole weight as pair stress, so it
 * overstates that stress by this share. */
static double rs_drag_share(const lub_rs_stats *st, const lub_rs_outcome *o)
{
    if (o->averaged_samples <= 0)
        return NAN;
    return isfinite(st->drag_share) ? st->drag_share
                                    : o->drag_share_sum / (double)o->averaged_samples;
}

/* " ± err" of a value in a warning (err in the value's scale), or "" without an error. */
static const char *rs_pm(char *buf, size_t len, double err)
{
    if (isfinite(err))
        snprintf(buf, len, " ± %.2g", err);
    else
        buf[0] = '\0';
    return buf;
}

/* The headline numbers and what the run did (ctx->summary_results). */
static void rs_put_results(lub_run_ctx *ctx, const lub_rs_spec *p, const lub_rs_scales *sc,
                           const lub_rs_stats *st, const lub_rs_outcome *o)
{
    const double a = sc->a, eta = sc->eta, gd = sc->gd, grav = sc->gravity, drho = sc->drho;
    const lub_rs_system *S = o->system;
    const lub_step_control *ctl = o->step_control;
    const double hs_mean = st->height, hs_sem = st->height_err;
    const double h0 = st->inventory / p->phi_m;
    const double A = lub_acrivos_number(eta, gd, drho, grav, h0 * a);
    lub_summary_put(ctx, "shields", lub_shields_number(eta, gd, drho, grav, a), NAN, "1");
    lub_summary_put(ctx, "acrivos", A, NAN, "1");
    lub_summary_put(ctx, "inertial_number", gd * sqrt(a / grav), NAN, "1");
    lub_summary_put(ctx, "stokes_number", sc->stokes, NAN, "1");
    lub_summary_put(ctx, "suspension_height", hs_mean, hs_sem, "a");
    lub_summary_put(ctx, "settled_height", h0, NAN, "a");
    lub_summary_put(ctx, "bed_base_height", st->bed_base, st->bed_base_err, "a");
    /* from the bed's base since 2026-12-07; the floor-plane value is the earlier definition */
    lub_summary_put(ctx, "relative_height_increase", st->relative_height_increase,
                    st->relative_height_increase_err, "1");
    lub_summary_put(ctx, "relative_height_increase_floor_plane",
                    st->relative_height_increase_floor_plane,
                    st->relative_height_increase_floor_plane_err, "1");
    lub_summary_put(ctx, "inventory", st->inventory, NAN, "a");
    lub_summary_put(ctx, "max_phi", st->max_phi, NAN, "1");
    lub_summary_put(ctx, "bulk_bins", st->bulk_bins >= 0 ? st->bulk_bins : NAN, NAN, "1");
    lub_summary_put(ctx, "bulk_velocity_slope", st->bulk_velocity_slope,
                    st->bulk_velocity_slope_err, "gd");
    lub_summary_put(ctx, "eta_vs_law_log_rms", st->law_log_rms, NAN, "1");
    lub_summary_put(ctx, "averaged_samples", (double)o->averaged_samples, NAN, "1");
    lub_summary_put(ctx, "min_clearance_above_floor", o->min_clearance, NAN, "a");
    lub_summary_put(ctx, "particles_below_floor", o->below_floor_max, NAN, "1");
    lub_summary_put(ctx, "lid_reflections", (double)S->lid_hits, NAN, "1");
    lub_summary_put(ctx, "crushed_contact_fraction", rs_crushed_fraction(o), NAN, "1");
    if (p->orientation == LUB_RS_GRADIENT)
        lub_summary_put(ctx, "shear_drag_weight_share", rs_drag_share(st, o), st->drag_share_err,
                        "1");
    lub_summary_put(ctx, "max_kinetic_energy", o->max_kinetic_energy, NAN, "eta gd a^3");
    lub_summary_put(ctx, "cell_width", o->cell_width, NAN, "a");
    lub_summary_put(ctx, "floor_radius", o->floor_radius, NAN, "a");
    lub_summary_put(ctx, "lid_height", o->y_lid - o->y_floor, NAN, "a");
    lub_summary_put(ctx, "initial_height", o->initial_height, NAN, "a");
    lub_summary_put(ctx, "dt", o->dt, NAN, "1/gd");
    lub_summary_put(ctx, "dt_min", ctl->dt_min, NAN, "1/gd");
    lub_summary_put(ctx, "dt_changes", (double)ctl->changes, NAN, "1");
    lub_summary_put(ctx, "dt_critical", o->dt_critical, NAN, "1/gd");
    lub_summary_put(ctx, "rebuilds", (double)S->rebuilds, NAN, "1");
    lub_summary_put(ctx, "dt_stiffness_ratio", ctl->ratio_max, NAN, "1");
    lub_summary_put(ctx, "solid_volume", o->solid_volume, NAN, "a^3");
    lub_summary_put(ctx, "initial_phi", o->initial_phi, NAN, "1");
}

/* The force terms the run had: gravity, the law's, the drags that act, floor and lid. */
static json_t *rs_active_terms(const lub_rs_spec *p, const lub_rs_system *S)
{
    json_t *terms = json_array();
    json_array_append_new(terms, json_string("gravity"));
    lub_law_terms_append(terms, S->law.terms);
    if (S->law.eps > 0.0)
        json_array_append_new(terms, json_string("normal_contact"));
    if (p->orientation == LUB_RS_GRADIENT && p->eta_shear > 0.0)
        json_array_append_new(terms, json_string("shear_drag"));
    if (p->eta_dilute > 0.0 && p->dilute_max >= 0)
        json_array_append_new(terms, json_string("dilute_drag"));
    json_array_append_new(terms, json_string("rough_floor"));
    json_array_append_new(terms, json_string("reflecting_lid"));
    return terms;
}

/* The warnings: each says what makes the results doubtful and which member to change. */
static json_t *rs_warnings(const lub_run_ctx *ctx, const lub_rs_spec *p, const lub_rs_scales *sc,
                           const lub_rs_stats *st, const lub_rs_outcome *o)
{
    const double a = sc->a, gd = sc->gd, grav = sc->gravity;
    const double bulk_rate = st->bulk_velocity_slope;
    json_t *warn = json_array();
    if (gd * sqrt(a / grav) > 5e-2)
        json_array_append_new(warn, json_string("inertial number gd sqrt(a/g) above 5e-2: "
                                                "inertia enhances resuspension (seed 000 §IV.C)"));
    if (!st->steady && o->averaged_samples > 0 && o->averaged_samples < LUB_RS_STEADY_MIN_SAMPLES) {
        /* MSER-5 and the drift test never ran: not "not steady", but not judged */
        char msg[400];
        snprintf(msg, sizeof msg,
                 "too few samples to judge whether the suspension height is steady (%lld "
                 "averaged, MSER-5 and the drift test need %d; height_steady is false): %s",
                 (long long)o->averaged_samples, LUB_RS_STEADY_MIN_SAMPLES,
                 !o->stopped ? "increase /strain, or lower /average_from or /sample_strain"
                 : lub_run_resumable(ctx)
                     ? "the run was stopped by a signal: " LUB_RESUME_ADVICE
                     : "the run was stopped by a signal and its checkpoint could not be "
                       "written: run it again");
        json_array_append_new(warn, json_string(msg));
    } else if (!st->steady) {
        const char *why = !o->stopped ? "suspension height not steady over the averaging "
                                        "window (MSER-5, drift test): increase /strain"
                          : lub_run_resumable(ctx)
                              ? "suspension height not steady (MSER-5) when the run was "
                                "stopped by a signal: " LUB_RESUME_ADVICE
                              : "suspension height not steady (MSER-5) when the run was "
                                "stopped by a signal, whose checkpoint could not be written: "
                                "run it again";
        json_array_append_new(warn, json_string(why));
    }
    if (st->transient_in_window) {
        char msg[320];
        snprintf(msg, sizeof msg,
                 "the suspension height's transient (MSER-5 on its whole series) ends at strain "
                 "%.4g, after /average_from (%.4g): the averages include part of it; raise "
                 "/average_from (see height_transient_end_strain)",
                 o->transient_end_strain, p->average_from);
        json_array_append_new(warn, json_string(msg));
    }
    if (o->averaged_samples > 0 && st->bulk_bins >= 0 && st->bulk_bins < 3) {
        char msg[640];
        snprintf(msg, sizeof msg,
                 "%d bulk bin%s (bulk_bins; fewer than 3): bulk_velocity_slope is null%s; the "
                 "bulk bins are those at least /analysis/interface_width below the interface, "
                 "/analysis/floor_skip above the floor and at phi >= /analysis/phi_min: lower "
                 "these, or make the bed thicker (/n) or the run longer (/strain)",
                 st->bulk_bins, st->bulk_bins == 1 ? "" : "s",
                 st->bulk_bins == 0 ? ", and so is eta_vs_law_log_rms; /profiles/eta_vs_phi has "
                                      "no rows"
                                    : "");
        json_array_append_new(warn, json_string(msg));
    }
    if (p->orientation == LUB_RS_GRADIENT && isfinite(bulk_rate) &&
        fabs(bulk_rate - gd) > 0.2 * gd) {
        char msg[400], pm[40];
        snprintf(msg, sizeof msg,
                 "the bed is not sheared homogeneously (bulk dv_x/dy = %.3g%s gd differs from gd "
                 "by more than 20 %%, see results/bulk_velocity_slope): raise "
                 "/shear_drag_viscosity",
                 bulk_rate / gd, rs_pm(pm, sizeof pm, st->bulk_velocity_slope_err / gd));
        json_array_append_new(warn, json_string(msg));
    }
    const double share = rs_drag_share(st, o);
    if (p->orientation == LUB_RS_GRADIENT && fabs(share) > RS_DRAG_SHARE_MAX) {
        char msg[440], pm[40];
        snprintf(msg, sizeof msg,
                 "the shear drag carries %.3g%s %% of the buoyant weight over the averaging "
                 "window (shear_drag_weight_share; the bed %s): eta_normal = (1/Sh) int phi "
                 "takes the whole weight as pair stress and is off by that share; raise "
                 "/average_from or /strain so that the bed is at rest on average",
                 100.0 * share, rs_pm(pm, sizeof pm, 100.0 * st->drag_share_err),
                 share > 0 ? "sinks" : "rises");
        json_array_append_new(warn, json_string(msg));
    }
    if (o->system->lid_hits > 0)
        json_array_append_new(warn, json_string("particles reached the lid: raise /lid_height"));
    lub_warn_fixed_dt(warn, p->dt, o->dt_critical, "dt_critical");
    lub_warn_fixed_dt_stiffness(warn, p->dt, o->dt_critical, o->step_control->ratio_max,
                                LUB_SHEAR_DT_STIFFNESS_MAX);
    if (rs_crushed_fraction(o) > LUB_CRUSHED_CONTACT_FRACTION_MAX) /* the message's "1 %" */
        json_array_append_new(warn,
                              json_string("asperities crushed in more than 1 % of the contacts "
                                          "(crushed_contact_fraction; u_n < -alpha eps a): "
                                          "contact forces exceed alpha stiffness eps, the "
                                          "results depend on /stiffness: raise it"));
    if (o->averaged_samples <= 0) {
        /* every member rs_put_results takes from the averaged profiles (README lists the same) */
        char msg[640];
        snprintf(msg, sizeof msg,
                 "no profile was averaged (the run ended before /average_from): the profiles "
                 "and what the averaging window measures (suspension_height, bed_base_height, "
                 "settled_height, relative_height_increase, "
                 "relative_height_increase_floor_plane, inventory, acrivos, max_phi, "
                 "bulk_bins, bulk_velocity_slope, eta_vs_law_log_rms, "
                 "crushed_contact_fraction%s) are null, and whether asperities are crushed "
                 "is unknown",
                 p->orientation == LUB_RS_GRADIENT ? ", shear_drag_weight_share" : "");
        json_array_append_new(warn, json_string(msg));
    }
    lub_network_warn_skipped(o->network, warn);
    return warn;
}

void lub_rs_write_summary(lub_run_ctx *ctx, const lub_rs_spec *p, const lub_rs_scales *sc,
                          const lub_rs_stats *st, const lub_rs_outcome *o)
{
    rs_put_results(ctx, p, sc, st, o);
    json_t *extra = ctx->summary_extra;
    json_object_set_new(extra, "active_terms", rs_active_terms(p, o->system));
    json_object_set_new(extra, "steps", json_integer(o->system->step));
    json_object_set_new(extra, "simulated_time", json_real(o->system->time));
    json_object_set_new(extra, "orientation",
                        json_string(p->orientation == LUB_RS_VORTICITY ? "vorticity" : "gradient"));
    json_object_set_new(extra, "height_steady", json_boolean(st->steady));
    json_object_set_new(extra, "height_transient_end_strain",
                        isfinite(o->transient_end_strain) ? json_real(o->transient_end_strain)
                                                          : json_null());
    json_object_set_new(extra, "phi_err_method",
                        json_string(o->averaged_samples < 2    ? "none (fewer than 2 samples)"
                                    : st->sem_batch_means == 1 ? "batch_means_ar1"
                                                               : "naive (fewer than 32 samples)"));
    json_object_set_new(extra, "warnings", rs_warnings(ctx, p, sc, st, o));
    json_object_set_new(
        extra, "units",
        json_pack("{s:s, s:s, s:s, s:s, s:s, s:s}", "length", "a (mean particle radius)",
                  "viscosity", "eta (fluid viscosity)", "time", "1/gd (inverse shear rate)",
                  "stress", "eta gd", "energy", "eta gd a^3", "note",
                  "drho g = 1/Sh, g = 1/I^2, rho_p = density_ratio drho; y from the floor "
                  "centre plane (in the snapshots' coordinates at result.h5 /profiles/y_floor)"));
}

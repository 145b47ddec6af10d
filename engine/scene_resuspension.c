/* scene_resuspension.c — viscous resuspension of buoyant lubricated spheres sheared above a
 * rough floor (physics-reference §4; seed 000, resuspension article §II.C–E, §III.B).
 *
 * Units (dimensionless): length a (mean radius), viscosity eta (fluid), time 1/gd (gd = 1).
 * Hence stresses are in eta gd, forces in eta gd a^2, energies in eta gd a^3.
 * Inputs are dimensionless groups:
 *   Sh = eta gd/(drho g a)          Shields number: drho g = 1/Sh (buoyant weight of a sphere
 *                                    = (4/3) pi r^3 / Sh)
 *   I  = gd sqrt(a/g)               inertial number: g = 1/I^2, hence drho = I^2/Sh
 *   density_ratio = rho_p/drho      particle mass density rho_p = density_ratio * drho
 *                                    (1: gravity acts on the whole particle mass, as in Yade)
 *   stiffness = g_bulk/(eta gd a)   contact-law bulk stiffness
 * The particle Stokes number St = rho_p gd a^2/eta = density_ratio I^2/Sh is reported.
 *
 * Cell: periodic in x (flow) and z; gravity along -y; rough floor of fixed spheres
 * (floor_wall.h), reflecting lid far above (lid_height x initial bed height). Orientation
 * "gradient": gravity along the gradient direction, shear imposed by a drag of viscosity
 * shear_drag_viscosity*eta towards u = gd (y - y_floor) e_x. "vorticity": gravity along the
 * vorticity direction, Lees–Edwards shear of the x-z plane (u = gd z e_x), no shear drag.
 * Dilute-region damping: Stokes drag with viscosity dilute_drag.viscosity*eta on particles
 * with at most dilute_drag.max_interactions active pairs (default 2: "fewer than three").
 *
 * Observables: phi(y) time- and plane-averaged over strain >= average_from with the stats.h
 * error bars (exact sphere–slab volumes, resuspension_profile.h), suspension height (phi
 * crosses half its maximum), eta_ii(y) = (1/Sh) int_y^inf phi (resuspension_analysis.h), the
 * bulk points eta_ii(phi) after lub_profile_select_bulk, phi averaged over analysis.phi_window
 * (default 2 a, one diameter: lub_profile_coarse_grain) so that the layering next to the floor
 * does not bias them, and the seed's laws (eq. 9; for the vorticity orientation eta_33 =
 * lambda_33 eta_22 with eq. 8) at that averaged phi for comparison (resuspension_statistics.h;
 * written by resuspension_summary.h).
 * y in all outputs is measured from the floor centre plane.
 *
 * The run (rs_run) goes through its phases with one rs_run_state: the spec
 * (resuspension_spec.h), the bed on its floor, the system and its step, the sample buffers, the
 * outputs, the continuation of a stopped run, the time loop, its end (the checkpoint of a stop,
 * the final network), the failure advice, and the report (statistics, profiles, summary).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "floor_wall.h"
#include "h5md_continue.h"
#include "law_spec.h"
#include "network_output.h"
#include "resuspension_analysis.h"
#include "resuspension_bed.h"
#include "resuspension_checkpoint.h"
#include "resuspension_profile.h"
#include "resuspension_spec.h"
#include "resuspension_statistics.h"
#include "resuspension_summary.h"
#include "resuspension_system.h"
#include "run_context.h"
#include "scene.h"
#include "state_checkpoint.h"
#include "step_count.h"
#include "step_schedule.h"
#include "step_stiffness.h"

#define RS_PI 3.14159265358979323846

/* Everything allocated for a run (freed in one place). */
typedef struct {
    double *radius, *floor_r, *samples, *scratch, *series_h, *phi_inst, *vol;
    double *series_t; /* the time of each height sample (1/gd) */
    double *phi, *phi_err, *eta, *eta_err, *ybin, *keepd, *law, *pairs_out, *scratch2, *scratch3,
        *vx_vol, *vx_sum, *vx_inst, *phi_cg, *phi_cg_err;
    /* per averaged sample, as samples: its per-bin volume-weighted v_x (vx_inst; its volume per
     * bin, vol, is not stored: phi_inst is vol times the constant 1/(area dy), so the statistics
     * take it back from samples, to rounding) and its drag share (gradient) */
    double *vx_samples, *drag_share;
    vec3 *pos, *floor_pos;
    int *keep;
    double *snap_x, *snap_v, *snap_w;
} rs_buffers;

static void rs_buffers_free(rs_buffers *b)
{
    double *d[] = {b->radius,   b->floor_r,    b->samples,   b->scratch,    b->series_h,
                   b->phi_inst, b->vol,        b->phi,       b->phi_err,    b->eta,
                   b->eta_err,  b->ybin,       b->keepd,     b->law,        b->pairs_out,
                   b->scratch2, b->vx_vol,     b->vx_sum,    b->vx_inst,    b->snap_x,
                   b->snap_v,   b->snap_w,     b->phi_cg,    b->phi_cg_err, b->scratch3,
                   b->series_t, b->vx_samples, b->drag_share};
    for (size_t i = 0; i < sizeof d / sizeof d[0]; ++i)
        free(d[i]);
    free(b->pos);
    free(b->floor_pos);
    free(b->keep);
    memset(b, 0, sizeof *b);
}

/* *buf reallocated to n doubles (its contents kept). 0, or -1 out of memory (*buf unchanged). */
static int rs_grow(double **buf, size_t n)
{
    double *p = realloc(*buf, n * sizeof *p);
    if (!p)
        return -1;
    *buf = p;
    return 0;
}

/* Grows the sample buffers so that the series holds `total` height samples and the average
 * `avg` profiles (the statistics' scratch max(total, avg) + 1); 0, 1 (the growth does not fit
 * in the memory the process may use: ctx->diagnostic says so, nothing grown) or -1 (no memory:
 * the buffers keep their contents). Called by every continuation, before the time loop (its
 * room from the stopped run's samples on). rs_allocate_samples has already checked and
 * allocated the room of a fresh run of the same /strain; the growth beyond it is a few samples
 * (the stopped run's steps against the bound's), checked here all the same. */
static int rs_samples_reserve(lub_run_ctx *ctx, rs_buffers *b, int nb, int64_t total, int64_t avg,
                              int64_t *nsamp_total, int64_t *nsamp_avg)
{
    const int64_t old_scratch = (*nsamp_avg > *nsamp_total ? *nsamp_avg : *nsamp_total) + 1;
    const int64_t new_total = total > *nsamp_total ? total : *nsamp_total;
    const int64_t new_avg = avg > *nsamp_avg ? avg : *nsamp_avg;
    const int64_t new_scratch = (new_avg > new_total ? new_avg : new_total) + 1;
    const double growth =
        (double)sizeof(double) * (2.0 * (double)(new_total - *nsamp_total) +
                                  (double)(new_avg - *nsamp_avg) * (2.0 * nb + 1.0) +
                                  3.0 * (double)(new_scratch - old_scratch));
    if (growth > 0.0) {
        char what[160];
        snprintf(what, sizeof what,
                 "the continuation's %lld more height samples and %lld more profiles of %d bins",
                 (long long)(new_total - *nsamp_total), (long long)(new_avg - *nsamp_avg), nb);
        if (!lub_memory_fits(ctx, growth, what, "/strain"))
            return 1;
    }
    if (total > *nsamp_total) {
        if (rs_grow(&b->series_h, (size_t)total) || rs_grow(&b->series_t, (size_t)total))
            return -1;
        *nsamp_total = total;
    }
    if (avg > *nsamp_avg) {
        if (rs_grow(&b->samples, (size_t)(avg * nb)) ||
            rs_grow(&b->vx_samples, (size_t)(avg * nb)) || rs_grow(&b->drag_share, (size_t)avg))
            return -1;
        *nsamp_avg = avg;
    }
    const size_t scratch = (size_t)(*nsamp_avg > *nsamp_total ? *nsamp_avg : *nsamp_total) + 1;
    return rs_grow(&b->scratch, scratch) || rs_grow(&b->scratch2, scratch) ||
                   rs_grow(&b->scratch3, scratch)
               ? -1
               : 0;
}

/* The time loop's state besides the system and the sample buffers: what a checkpoint holds
 * with them, so that a stopped run continues as if it had not stopped. */
typedef struct {
    int64_t step;           /* loop index to continue at */
    int64_t step_taken;     /* 1: the samples, snapshot and network frame of `step` are taken
                               (a stop, a periodic checkpoint), 0: not yet (the checkpoint of a
                               completed run, before the samples its end forces) */
    int64_t avg_start_step; /* first step averaged into the profiles */
    int64_t nh, navg;       /* height samples (= time-series rows) and averaged profiles */
    int64_t below_floor_max, frames_in_file;
    int64_t network_frames_in_file; /* /pair_network frames in the output file */
    double max_ke, min_lowest, contacts_sum, crushed_sum;
    double drag_share_sum; /* gradient: the shear drag's vertical force over the buoyant weight,
                              summed over the averaged samples (NaN: an older checkpoint) */
    int sample_series;     /* 1: the buffers' vx_samples and drag_share hold every averaged
                              sample's; 0: the run continues a checkpoint written without them
                              (before 2026-12-08), and the two errors they give are NaN */
    double y_floor, y_lid; /* the geometry the bed gave (checked on resuming) */
    lub_step_control ctl;
    lub_schedule sched;
} rs_loop;

/* The loop state, the samples and the system into path (a new file). 0, or -1 with why[len]. */
static int rs_checkpoint_write(const char *path, const json_t *resolved, const rs_loop *lp,
                               const rs_buffers *b, int nb, const lub_rs_system *S,
                               const char *output_file, char *why, size_t len)
{
    lub_ckpt *c =
        lub_run_checkpoint_create(path, "resuspension", lp->step, resolved, output_file, why, len);
    if (!c)
        return -1;
    const int64_t ints[6] = {lp->step, lp->avg_start_step,  lp->nh,
                             lp->navg, lp->below_floor_max, lp->frames_in_file};
    const double reals[6] = {lp->max_ke,      lp->min_lowest, lp->contacts_sum,
                             lp->crushed_sum, lp->y_floor,    lp->y_lid};
    int rc =
        lub_ckpt_put(c, "run/ints", LUB_CKPT_I64, 6, ints) ||
        lub_ckpt_put(c, "run/reals", LUB_CKPT_F64, 6, reals) ||
        lub_ckpt_put_i64(c, "run/network_frames_in_file", lp->network_frames_in_file) ||
        lub_ckpt_put_i64(c, "run/step_taken", lp->step_taken) ||
        lub_ckpt_put(c, "run/drag_share_sum", LUB_CKPT_F64, 1, &lp->drag_share_sum) ||
        lub_step_control_save(c, "run/step_control", &lp->ctl) ||
        lub_schedule_save(c, "run/schedule", &lp->sched) ||
        lub_ckpt_put(c, "series/height", LUB_CKPT_F64, (size_t)lp->nh, b->series_h) ||
        lub_ckpt_put(c, "series/time", LUB_CKPT_F64, (size_t)lp->nh, b->series_t) ||
        lub_ckpt_put(c, "profiles/samples", LUB_CKPT_F64, (size_t)(lp->navg * nb), b->samples) ||
        lub_ckpt_put(c, "profiles/vx_volume", LUB_CKPT_F64, (size_t)nb, b->vx_vol) ||
        lub_ckpt_put(c, "profiles/vx_sum", LUB_CKPT_F64, (size_t)nb, b->vx_sum) ||
        (lp->sample_series &&
         (lub_ckpt_put(c, "profiles/vx_samples", LUB_CKPT_F64, (size_t)(lp->navg * nb),
                       b->vx_samples) ||
          lub_ckpt_put(c, "series/drag_share", LUB_CKPT_F64, (size_t)lp->navg, b->drag_share))) ||
        lub_rs_save(c, S);
    return lub_run_checkpoint_close(c, rc, why, len);
}

/* The loop state of checkpoint c. 0, or -1 with why[len]. */
static int rs_checkpoint_read_loop(lub_ckpt *c, rs_loop *lp, char *why, size_t len)
{
    int64_t ints[6];
    double reals[6];
    if (lub_ckpt_get(c, "run/ints", LUB_CKPT_I64, 6, ints) ||
        lub_ckpt_get(c, "run/reals", LUB_CKPT_F64, 6, reals) ||
        lub_step_control_load(c, "run/step_control", &lp->ctl) ||
        lub_schedule_load(c, "run/schedule", &lp->sched) || ints[0] < 0 ||
        ints[0] > lp->sched.nsteps || ints[2] < 0 || ints[3] < 0 || ints[3] > ints[2]) {
        snprintf(why, len, "%s",
                 lub_ckpt_error(c)[0] ? lub_ckpt_error(c) : "inconsistent loop state");
        return -1;
    }
    lp->step = ints[0];
    lp->avg_start_step = ints[1];
    lp->nh = ints[2];
    lp->navg = ints[3];
    lp->below_floor_max = ints[4];
    lp->frames_in_file = ints[5];
    lp->max_ke = reals[0];
    lp->min_lowest = reals[1];
    lp->contacts_sum = reals[2];
    lp->crushed_sum = reals[3];
    lp->y_floor = reals[4];
    lp->y_lid = reals[5];
    /* unknown in a checkpoint older than the drag's share */
    lp->drag_share_sum = NAN;
    if (lub_ckpt_has(c, "run/drag_share_sum") &&
        lub_ckpt_get(c, "run/drag_share_sum", LUB_CKPT_F64, 1, &lp->drag_share_sum)) {
        snprintf(why, len, "%s", lub_ckpt_error(c));
        return -1;
    }
    /* the per-sample velocity sums and drag shares: none in a checkpoint older than them (also
     * none missing when nothing was averaged) */
    lp->sample_series = lp->navg == 0 || (lub_ckpt_has(c, "profiles/vx_samples") &&
                                          lub_ckpt_has(c, "series/drag_share"));
    /* none in a checkpoint older than the frames */
    if (lub_ckpt_get_i64_or(c, "run/network_frames_in_file", 0, &lp->network_frames_in_file)) {
        snprintf(why, len, "%s", lub_ckpt_error(c));
        return -1;
    }
    /* a checkpoint older than the flag: the end checkpoint was its only one taken before the
     * samples of its step, at the end of its schedule */
    if (lub_ckpt_get_i64_or(c, "run/step_taken", lp->step < lp->sched.nsteps, &lp->step_taken)) {
        snprintf(why, len, "%s", lub_ckpt_error(c));
        return -1;
    }
    return 0;
}

/* The samples of checkpoint c into b (room reserved). 0 or -1. A checkpoint older than the
 * samples' times (2026-12-07) gets the nominal ones, index x /sample_strain / gd; one without
 * the per-sample velocity sums and drag shares (lp->sample_series 0) leaves them out. */
static int rs_checkpoint_read_samples(lub_ckpt *c, const rs_loop *lp, rs_buffers *b, int nb,
                                      double nominal_spacing)
{
    if (!lub_ckpt_has(c, "series/time"))
        for (int64_t i = 0; i < lp->nh; ++i)
            b->series_t[i] = (double)i * nominal_spacing;
    else if (lub_ckpt_get(c, "series/time", LUB_CKPT_F64, (size_t)lp->nh, b->series_t))
        return -1;
    return lub_ckpt_get(c, "series/height", LUB_CKPT_F64, (size_t)lp->nh, b->series_h) ||
                   lub_ckpt_get(c, "profiles/samples", LUB_CKPT_F64, (size_t)(lp->navg * nb),
                                b->samples) ||
                   lub_ckpt_get(c, "profiles/vx_volume", LUB_CKPT_F64, (size_t)nb, b->vx_vol) ||
                   lub_ckpt_get(c, "profiles/vx_sum", LUB_CKPT_F64, (size_t)nb, b->vx_sum) ||
                   (lp->sample_series && (lub_ckpt_get(c, "profiles/vx_samples", LUB_CKPT_F64,
                                                       (size_t)(lp->navg * nb), b->vx_samples) ||
                                          lub_ckpt_get(c, "series/drag_share", LUB_CKPT_F64,
                                                       (size_t)lp->navg, b->drag_share)))
               ? -1
               : 0;
}

/* The interaction network of the system's current state (pair_network.h: the floor spheres'
 * pairs with free particles included, theirs with one another left out) into net (arrays
 * kept for the next frame), appended to /pair_network. final: no step of this run follows
 * (the rebuild the network may do is then not counted). 0, or the exit code with
 * ctx->diagnostic set. */
static int rs_network_frame(lub_run_ctx *ctx, lub_rs_system *S, lub_h5_frames *frames,
                            lub_pair_network *net, double gd, int final)
{
    const long rebuilds = S->rebuilds, flips = S->flips;
    int rc = lub_rs_complete_list(S);
    if (rc == LUB_RS_OK) {
        const lub_pair_network_source src = {
            .pairs = &S->pairs,
            .cell = &S->cell,
            .bodies = {.x = S->x, .v = S->v, .w = S->w, .r = S->r, .inv_i_share = S->inv_i_share},
            .law = &S->law,
            .cutoff = S->p.cutoff,
            .dt = S->p.dt,
            .n_free = S->n_mobile,
            .step = S->step};
        const int b = lub_pair_network_build(&src, net, S->fail_msg, sizeof S->fail_msg);
        rc = b == LUB_PAIR_NETWORK_OK      ? LUB_RS_OK
             : b == LUB_PAIR_NETWORK_NOMEM ? LUB_RS_NOMEM
                                           : LUB_RS_NONFINITE;
    }
    if (final) {
        S->rebuilds = rebuilds;
        S->flips = flips;
    }
    if (rc != LUB_RS_OK) {
        snprintf(
            ctx->diagnostic, sizeof ctx->diagnostic, "interaction network at step %ld: %s", S->step,
            rc == LUB_RS_NOMEM ? "out of memory (/pair_network: \"none\" avoids it)" : S->fail_msg);
        return rc == LUB_RS_NOMEM ? LUB_EXIT_INTERNAL : LUB_EXIT_NUMERICAL;
    }
    if (lub_network_append(frames, net, S->step, S->time * gd)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }
    return LUB_EXIT_OK;
}

/* The time series of result.h5 /observables, one row per sample. */
#define RS_NSERIES 6
static const char *const rs_series_names[RS_NSERIES] = {
    "suspension_height", "center_of_mass_height", "mean_phi",
    "kinetic_energy",    "max_fluctuation_speed", "dilute_particles"};
static const int rs_series_ncomp[RS_NSERIES] = {1, 1, 1, 1, 1, 1};
static const char *const rs_series_units[RS_NSERIES] = {"a", "a", "1", "eta gd a^3", "a gd", "1"};

/* One run: what its phases (rs_run) share. Zeroed at the start; freed by rs_run_state_free. */
typedef struct {
    lub_run_ctx *ctx;
    const json_t *resolved; /* the resolved spec (written into checkpoints) */
    lub_rs_spec p;          /* its law scaled by the system's set-up */
    lub_rs_scales sc;
    int N; /* free particles */
    rs_buffers B;
    lub_rs_system S;
    rs_loop lp; /* the loop's state: a fresh start, or the checkpoint's (resumed) */
    /* the bed and the cell (a) */
    lub_bed_info binfo;
    double L, rf, rmin, vsum, y_floor, y_lid, h_init, Ly;
    int nfloor;
    /* the step (1/gd) */
    double dt, dt_crit;
    int dt_adapts;     /* the step follows the pairs' summed stiffness */
    int step_unstable; /* the failure is one the time step causes (non-finite, escape, runaway) */
    /* the profile bins and the sample buffers' room */
    double dy, area;
    int nb;
    int64_t nsamp_total, nsamp_avg;
    int ev_sample, ev_snap; /* events of lp.sched (-1: no snapshots) */
    /* the outputs */
    lub_h5_table *tab;
    lub_h5_frames *network; /* /pair_network (NULL: none) */
    lub_pair_network net;   /* its arrays, kept from frame to frame */
    /* the loop */
    int64_t first_step, frames; /* loop start; snapshots asked for */
    int64_t stopped_at;         /* the loop index a stop request ended the loop at (-1: none) */
    int end_checkpoint;         /* --keep-checkpoint: written at the last step, before its sample */
} rs_run_state;

static void rs_run_state_free(rs_run_state *r)
{
    r->ctx->threads_used = r->S.team_min; /* the smallest team the steps got (0: no step) */
    lub_rs_free(&r->S);
    rs_buffers_free(&r->B);
}

/* The resolved spec into r->p and its scales: a spec the resolve accepted, so a refusal here is
 * the engine's fault (exit 1). */
static int rs_read_spec(rs_run_state *r)
{
    lub_error err;
    json_t *spec = json_deep_copy(r->resolved);
    int rr = lub_rs_spec_read(spec, &r->p, &err);
    json_decref(spec);
    if (rr) {
        snprintf(r->ctx->diagnostic, sizeof r->ctx->diagnostic, "%s: %s", err.pointer, err.message);
        return LUB_EXIT_INTERNAL;
    }
    r->sc = lub_rs_spec_scales(&r->p);
    r->N = (int)r->p.n;
    return LUB_EXIT_OK;
}

/* The bed (resuspension_bed.h) lifted onto the rough floor fitted to its cell, the lid above it
 * and the cell's height: B.radius, B.pos, B.floor_r, B.floor_pos and the geometry. */
static int rs_build_bed(rs_run_state *r)
{
    const lub_rs_spec *p = &r->p;
    lub_run_ctx *ctx = r->ctx;
    rs_buffers *B = &r->B;
    const int N = r->N;
    B->radius = malloc((size_t)N * sizeof *B->radius);
    B->pos = malloc((size_t)N * sizeof *B->pos);
    if (!B->radius || !B->pos) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory");
        return LUB_EXIT_INTERNAL;
    }
    lub_bed_params bp = {.n = N,
                         .width = p->width,
                         .phi_target = p->initial_phi,
                         .radius_std = p->radius_std,
                         .seed = (uint64_t)p->seed};
    int brc = lub_bed_build(&bp, B->radius, B->pos, &r->binfo);
    if (brc) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "initial bed failed (%s; packing code %d, %d per layer, phi %.4g)",
                 brc == -1 ? "out of memory" : "packing", r->binfo.info_code, r->binfo.per_layer,
                 r->binfo.layer_phi);
        return LUB_EXIT_INTERNAL;
    }
    const double L = r->L = r->binfo.side;
    /* floor: square lattice fitted to the cell width */
    const int nside = lub_floor_side_count(L, p->floor_radius, 4);
    const double rf = r->rf = L / (2.0 * nside);
    r->nfloor = nside * nside;
    double rmax = 0.0, rmin = INFINITY, vsum = 0.0, ylow = INFINITY;
    for (int i = 0; i < N; ++i) {
        rmax = fmax(rmax, B->radius[i]);
        rmin = fmin(rmin, B->radius[i]);
        vsum += 4.0 / 3.0 * RS_PI * pow(B->radius[i], 3.0);
        ylow = fmin(ylow, B->pos[i].y - B->radius[i]);
    }
    r->rmin = rmin;
    r->vsum = vsum;
    if (!(lub_floor_max_passing_radius(rf, p->floor_jitter) < rmin)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "fitted floor radius %.4g lets particles of radius %.4g through", rf, rmin);
        return LUB_EXIT_INTERNAL;
    }
    const double y_floor = r->y_floor = rf * (1.0 + p->floor_jitter) + 1.0;
    const double y_start = y_floor + rf * (1.0 + p->floor_jitter) + 0.05;
    double ytop = 0.0;
    for (int i = 0; i < N; ++i) {
        B->pos[i].y += y_start - ylow;
        ytop = fmax(ytop, B->pos[i].y + B->radius[i]);
    }
    r->h_init = ytop - y_floor;
    r->y_lid = y_floor + p->lid_height * r->h_init;
    const double d_list = 2.0 * rmax * (1.0 + 0.5 * p->cutoff) + p->skin;
    r->Ly = r->y_lid + d_list + 2.0 * rmax + 1.0;

    B->floor_r = malloc((size_t)r->nfloor * sizeof *B->floor_r);
    B->floor_pos = malloc((size_t)r->nfloor * sizeof *B->floor_pos);
    if (!B->floor_r || !B->floor_pos) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory");
        return LUB_EXIT_INTERNAL;
    }
    for (int i = 0; i < r->nfloor; ++i)
        B->floor_r[i] = rf;
    lub_floor_build(nside, rf, y_floor, p->floor_jitter, (uint64_t)p->seed + 7919u, B->floor_pos);
    return LUB_EXIT_OK;
}

/* The system (resuspension_system.h) of the bed and the floor, its time step and the step
 * control; the step-count rule with this bed's lightest particle (exit 2). */
static int rs_init_system(rs_run_state *r)
{
    lub_rs_spec *p = &r->p;
    const lub_rs_scales *sc = &r->sc;
    lub_run_ctx *ctx = r->ctx;
    const int N = r->N;
    lub_law_spec_scale(&p->law, sc->eta, p->stiffness * sc->eta * sc->gd * sc->a);
    lub_rs_params sp = {.orientation = p->orientation,
                        .shear_rate = sc->gd,
                        .gravity = sc->gravity,
                        .drho = sc->drho,
                        .rho = sc->rho,
                        .eta_shear = p->eta_shear * sc->eta,
                        .eta_dilute = p->eta_dilute * sc->eta,
                        .dilute_max_interactions = (int)p->dilute_max,
                        .y_floor = r->y_floor,
                        .y_lid = r->y_lid,
                        .cutoff = p->cutoff,
                        .skin = p->skin,
                        .dt = 1.0,
                        .threads = ctx->threads};
    /* time step: elastic bound on the lightest particle (normal and tangential), notes §7 */
    const double rmin = r->rmin;
    const double mmin = sc->rho * 4.0 / 3.0 * RS_PI * rmin * rmin * rmin;
    double dt_crit = sqrt(mmin / p->law.params.k_bulk);
    if (p->law.params.k_t > 0.0)
        dt_crit = fmin(dt_crit, sqrt(0.4 * mmin / p->law.params.k_t));
    r->dt_crit = dt_crit;
    sp.dt = p->dt > 0.0 ? p->dt : p->dt_safety * dt_crit;
    const rs_buffers *B = &r->B;
    int src = lub_rs_init(&r->S, &sp, &p->law.params, N, B->radius, B->pos, r->nfloor, B->floor_r,
                          B->floor_pos, r->L, r->Ly, r->L);
    if (src == LUB_RS_NOMEM) {
        lub_diagnostic_out_of_memory(ctx, "system", N, 0.0, "/n");
        return LUB_EXIT_INTERNAL;
    }
    if (src) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "system init failed (%d)", src);
        return LUB_EXIT_INTERNAL;
    }
    /* the step: fixed (/dt), or /dt_safety of the single-pair bound, lowered while the pairs'
     * summed stiffness needs it (/dt_stiffness_safety; step_stiffness.h, checked at every
     * neighbour-list rebuild) */
    r->dt_adapts = p->dt <= 0.0 && p->dt_stiffness_safety > 0.0;
    lub_step_control_init(&r->lp.ctl, sp.dt, r->dt_adapts ? p->dt_stiffness_safety : 0.0);
    const double dt = r->dt = r->lp.ctl.dt;
    if (!ctx->resume_path && !lub_step_count_ok(lub_step_count(p->strain / sc->gd, dt))) {
        /* the step-count rule (step_count.h) with this bed's lightest particle, which
         * validation could only bound: refused before the first step, exit 2 */
        lub_error err;
        const double r_eff =
            p->dt > 0.0 ? 1.0 : pow(dt_crit / lub_rs_elastic_dt(p, 1.0), 2.0 / 3.0);
        lub_rs_step_refusal(p, r_eff, lub_step_count(p->strain / sc->gd, dt), dt, "", &err);
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s: %s", err.pointer, err.message);
        return LUB_EXIT_BAD_SPEC;
    }
    return LUB_EXIT_OK;
}

/* The profile bins, the sample event, a fresh loop state and every buffer of the samples and
 * the statistics (refused beyond the memory the process may use). */
static int rs_allocate_samples(rs_run_state *r)
{
    const lub_rs_spec *p = &r->p;
    const double gd = r->sc.gd, dt = r->dt;
    lub_run_ctx *ctx = r->ctx;
    rs_buffers *B = &r->B;
    rs_loop *lp = &r->lp;
    const int N = r->N;
    r->area = lub_rs_area(&r->S);

    /* profile bins from the floor centre plane to the lid */
    const double dy = r->dy = p->bin_width;
    const int nb = r->nb = (int)ceil((r->y_lid - r->y_floor) / dy);
    lub_schedule_init(&lp->sched, dt, p->strain / gd);
    const int64_t sample_every = lub_schedule_period(p->sample_strain / gd, dt);
    r->ev_sample = lub_schedule_add(&lp->sched, sample_every, 0, p->sample_strain / gd);
    /* room for the most samples any step the control may choose gives (the loop never grows
     * it; until 2026-12-07 a change of the step reallocated the buffers, outside the memory
     * check) */
    const double dt_max = lp->ctl.dt_base;
    r->nsamp_total = lub_schedule_most_occurrences(&lp->sched, r->ev_sample, 0.0, dt_max);
    lp->avg_start_step = (int64_t)ceil(p->average_from / (gd * dt) - 1e-9);
    r->nsamp_avg = lub_schedule_most_occurrences(&lp->sched, r->ev_sample,
                                                 fmax(0.0, p->average_from / gd - dt_max), dt_max);
    lp->min_lowest = INFINITY;
    lp->sample_series = 1;
    lp->y_floor = r->y_floor;
    lp->y_lid = r->y_lid;
    const int64_t nsamp_avg = r->nsamp_avg, nsamp_total = r->nsamp_total;
    const size_t scratch = (size_t)(nsamp_avg > nsamp_total ? nsamp_avg : nsamp_total) + 1;
    /* what grows with the run's length: the profiles (phi and velocity sums, and the drag
     * share, of every averaged sample), the height series and the statistics' three scratch
     * arrays (the per-bin arrays and the snapshots are small beside them) */
    const double profile_bytes = (double)nsamp_avg * (2.0 * nb + 1.0) * sizeof *B->samples;
    const double series_bytes =
        (2.0 * (double)nsamp_total + 3.0 * (double)scratch) * sizeof(double);
    char samples_what[160];
    snprintf(samples_what, sizeof samples_what,
             "the profiles of %d bins over %lld samples from /average_from on and the height "
             "series of %lld samples",
             nb, (long long)nsamp_avg, (long long)nsamp_total);
    if (!lub_memory_fits(ctx, profile_bytes + series_bytes, samples_what,
                         profile_bytes >= series_bytes
                             ? "/strain - /average_from (or raise /bin_width or /sample_strain)"
                             : "/strain (or raise /sample_strain)"))
        return LUB_EXIT_INTERNAL;
    const struct {
        double **buf;
        size_t n;
    } want[] = {{&B->samples, (size_t)(nsamp_avg * nb)},
                {&B->vx_samples, (size_t)(nsamp_avg * nb)},
                {&B->drag_share, (size_t)nsamp_avg},
                {&B->scratch, scratch},
                {&B->scratch2, scratch},
                {&B->scratch3, scratch},
                {&B->series_h, (size_t)nsamp_total},
                {&B->series_t, (size_t)nsamp_total},
                {&B->phi_inst, (size_t)nb},
                {&B->vx_vol, (size_t)nb},
                {&B->vx_sum, (size_t)nb},
                {&B->vx_inst, (size_t)nb},
                {&B->vol, (size_t)nb},
                {&B->phi, (size_t)nb},
                {&B->phi_err, (size_t)nb},
                {&B->eta, (size_t)nb},
                {&B->eta_err, (size_t)nb},
                {&B->ybin, (size_t)nb},
                {&B->keepd, (size_t)nb},
                {&B->law, (size_t)nb},
                {&B->pairs_out, (size_t)nb * 4},
                {&B->phi_cg, (size_t)nb},
                {&B->phi_cg_err, (size_t)nb},
                {&B->snap_x, (size_t)N * 3},
                {&B->snap_v, (size_t)N * 3},
                {&B->snap_w, (size_t)N * 3}};
    int allocated = (B->keep = calloc((size_t)nb, sizeof *B->keep)) != NULL;
    for (size_t k = 0; k < sizeof want / sizeof want[0]; ++k)
        allocated &= (*want[k].buf = calloc(want[k].n, sizeof(double))) != NULL;
    if (!allocated) { /* what was allocated is freed with the rest (rs_buffers_free) */
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "out of memory for the profiles (%d bins x %lld samples) and the height series "
                 "(%lld samples): raise /bin_width or /sample_strain, or lower /strain",
                 nb, (long long)nsamp_avg, (long long)nsamp_total);
        return LUB_EXIT_INTERNAL;
    }
    return LUB_EXIT_OK;
}

/* The outputs defined in result.h5: the time series, the particles (/snapshots), the
 * interaction network (/pair_network); the snapshot event. */
static int rs_define_outputs(rs_run_state *r)
{
    const lub_rs_spec *p = &r->p;
    lub_run_ctx *ctx = r->ctx;
    rs_loop *lp = &r->lp;
    r->tab = lub_h5_set_units(ctx->out, "1/gd", "a", "a gd", "gd") == 0
                 ? lub_h5_table_create(ctx->out, RS_NSERIES, rs_series_names, rs_series_ncomp,
                                       rs_series_units)
                 : NULL;
    const char *bnd[3] = {"periodic", "none", "periodic"};
    int snap_ok =
        p->snapshots == 0 || lub_h5_particles_define(ctx->out, r->N, r->B.radius, bnd) == 0;
    /* /pair_network: its arrays (about 3 kB a particle at phi 0.5) are kept from frame to frame */
    r->network = p->pair_network != LUB_NETWORK_NONE && r->tab && snap_ok
                     ? lub_network_define(ctx->out, "eta*gd*a^2", "eta*gd*a^3", "1/gd")
                     : NULL;
    if (!r->tab || !snap_ok || (p->pair_network != LUB_NETWORK_NONE && !r->network)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }
    if (r->network &&
        !lub_memory_fits(ctx, 1.25 * 20.0 * (double)r->S.n * (double)LUB_PAIR_NETWORK_PAIR_BYTES,
                         "the interaction network (/pair_network, 20 pairs a particle)",
                         "/pair_network"))
        return LUB_EXIT_INTERNAL;
    const int64_t snap_every = p->snapshots > 1
                                   ? (lp->sched.nsteps + p->snapshots - 2) / (p->snapshots - 1)
                                   : lp->sched.nsteps + 1;
    r->ev_snap = p->snapshots > 0
                     ? lub_schedule_add(&lp->sched, snap_every, 0, (double)snap_every * r->dt)
                     : -1;
    return LUB_EXIT_OK;
}

/* Takes up the stopped run's state from ctx->resume_path (--resume): its loop state, samples
 * and system, and its time series, snapshots and network frames copied into the new result.h5.
 * Refused (exit 2, ctx->resume_rejected) when the checkpoint does not fit this run. */
static int rs_continue_stopped_run(rs_run_state *r)
{
    const lub_rs_spec *p = &r->p;
    const double gd = r->sc.gd;
    lub_run_ctx *ctx = r->ctx;
    lub_rs_system *S = &r->S;
    char why[600] = "";
    rs_loop saved;
    memset(&saved, 0, sizeof saved);
    int no_room = 0; /* rs_samples_reserve: 1 = beyond the memory the process may use, -1 = none */
    lub_ckpt *ck = lub_ckpt_open(ctx->resume_path, why, sizeof why);
    if (ck && rs_checkpoint_read_loop(ck, &saved, why, sizeof why) == 0) {
        if (saved.y_floor != r->y_floor || saved.y_lid != r->y_lid ||
            saved.sched.n_events != r->lp.sched.n_events) {
            snprintf(why, sizeof why,
                     "the bed or the events differ from the stopped run's (another build?)");
        } else if (lub_rs_restore(ck, S)) {
            snprintf(why, sizeof why, "%s",
                     lub_ckpt_error(ck)[0] ? lub_ckpt_error(ck) : "inconsistent pairs");
        } else if (saved.sched.t_end != p->strain / gd &&
                   p->strain < S->time * gd * (1.0 - 1e-12)) {
            /* a continuation may ask for another /strain (resume_may_differ), not for less
             * than the stopped run has done */
            snprintf(why, sizeof why,
                     "/strain: %g here, but the stopped run has already sheared to %.6g", p->strain,
                     S->time * gd);
        } else {
            /* ... and then takes the steps of a run asked for that strain from the start
             * (lub_schedule_set_end; the checkpoint of a completed run is taken before its
             * last sample, which only the run's end forces) */
            if (saved.sched.t_end != p->strain / gd)
                lub_schedule_set_end(&saved.sched, p->strain / gd);
            const int64_t left = lub_schedule_most_occurrences(&saved.sched, r->ev_sample, S->time,
                                                               saved.ctl.dt_base);
            if ((double)saved.sched.nsteps > LUB_MAX_STEPS) /* at the stopped run's step */
                snprintf(why, sizeof why,
                         "/strain: %g would take the run to %.3g steps at its step of %.3g, "
                         "more than the %.0e a run may take (README, CLI contract, \"Step "
                         "count\")",
                         p->strain, (double)saved.sched.nsteps, saved.ctl.dt, LUB_MAX_STEPS);
            else if ((no_room =
                          rs_samples_reserve(ctx, &r->B, r->nb, saved.nh + left, saved.navg + left,
                                             &r->nsamp_total, &r->nsamp_avg)) != 0 ||
                     rs_checkpoint_read_samples(ck, &saved, &r->B, r->nb, p->sample_strain / gd)) {
                if (!no_room) /* a memory refusal is not a refused continuation: below */
                    snprintf(why, sizeof why, "%s",
                             lub_ckpt_error(ck)[0] ? lub_ckpt_error(ck) : "unreadable samples");
            } else if (lub_h5_continue_output(
                           ctx->resume_result, r->tab, RS_NSERIES, rs_series_names, rs_series_ncomp,
                           saved.nh, r->B.series_h, ctx->out, r->N,
                           p->snapshots > 0 ? saved.frames_in_file : 0, why, sizeof why) == 0 &&
                       (!r->network || lub_h5_continue_frames(ctx->resume_result, r->network,
                                                              saved.network_frames_in_file, why,
                                                              sizeof why) == 0)) {
                why[0] = '\0';
            }
        }
    }
    if (ck)
        lub_ckpt_close(ck, NULL, 0);
    if (no_room) { /* as a fresh run without the memory for its samples (rs_allocate_samples) */
        if (no_room < 0)
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                     "out of memory for the samples of the continuation from %s (%d bins x %lld "
                     "profiles, %lld height samples): raise /bin_width or /sample_strain, or lower "
                     "/strain",
                     ctx->resume_path, r->nb, (long long)(saved.navg), (long long)saved.nh);
        return LUB_EXIT_INTERNAL;
    }
    if (!ck || why[0]) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "cannot continue from %s: %s",
                 ctx->resume_path, why[0] ? why : "unreadable");
        ctx->resume_rejected = 1;
        return LUB_EXIT_BAD_SPEC;
    }
    r->lp = saved;
    r->dt = r->lp.ctl.dt;
    r->first_step = saved.step;
    r->frames = saved.frames_in_file;
    ctx->resumed_from_step = S->step;
    ctx->resume_begun = 1;
    return LUB_EXIT_OK;
}

/* The loop state a checkpoint at loop index `step` holds with the system and the samples: the
 * snapshots and network frames in the output file so far. */
static void rs_mark_loop_state(rs_run_state *r, int64_t step, int taken)
{
    r->lp.step = step;
    r->lp.step_taken = taken;
    r->lp.frames_in_file = r->frames - lub_h5_snapshots_skipped(r->ctx->out, NULL, NULL, 0);
    r->lp.network_frames_in_file = lub_h5_frames_written(r->network, NULL);
}

/* The lowest free sphere's clearance above the floor plane and the count of centres below it,
 * at a sample or a snapshot. */
static void rs_track_floor_clearance(rs_run_state *r)
{
    int below = 0;
    double low = lub_rs_lowest(&r->S, &below);
    r->lp.min_lowest = fmin(r->lp.min_lowest, low - r->y_floor);
    if (below > r->lp.below_floor_max)
        r->lp.below_floor_max = below;
}

/* The sample of loop index `step` at time t: the instantaneous phi(y) and velocity profile, the
 * time series' row, the height and (from /average_from on) the profile kept for the average.
 * LUB_EXIT_OK, or LUB_EXIT_IO with the diagnostic set. */
static int rs_sample(rs_run_state *r, int64_t step, double t)
{
    const lub_rs_spec *p = &r->p;
    const lub_rs_system *S = &r->S;
    rs_buffers *B = &r->B;
    rs_loop *lp = &r->lp;
    const int nb = r->nb;
    const double dy = r->dy, y_floor = r->y_floor;
    memset(B->vol, 0, (size_t)nb * sizeof *B->vol);
    double ysum = 0.0, msum = 0.0;
    int dilute = 0;
    const int in_avg = step >= lp->avg_start_step;
    double drag_share = 0.0; /* gradient, averaged samples */
    memset(B->vx_inst, 0, (size_t)nb * sizeof *B->vx_inst);
    for (int i = 0; i < r->N; ++i) {
        /* velocity along the flow relative to the floor-plane mean flow: v_x for the
         * gradient orientation, v_x - gd z for the vorticity one (should be ~ 0) */
        const double vrel = p->orientation == LUB_RS_VORTICITY
                                ? S->v[i].x - lub_rs_mean_velocity(S, S->x[i]).x
                                : S->v[i].x;
        lub_profile_add_sphere_weighted(B->vol, B->vx_inst, nb, y_floor, dy, S->x[i].y, S->r[i],
                                        vrel);
        ysum += S->m[i] * (S->x[i].y - y_floor);
        msum += S->m[i];
        dilute += step > 0 && S->nint[i] <= (int)p->dilute_max;
    }
    if (in_avg && p->orientation == LUB_RS_GRADIENT) {
        /* the shear drag's vertical force (u has no y component) against the buoyant weight */
        double fy = 0.0, w = 0.0;
        for (int i = 0; i < r->N; ++i) {
            fy -= 6.0 * RS_PI * p->eta_shear * S->r[i] * S->v[i].y;
            w += S->weight[i];
        }
        drag_share = w > 0.0 ? fy / w : 0.0;
        lp->drag_share_sum += drag_share;
    }
    if (in_avg) {
        lp->contacts_sum += (double)S->n_contacts;
        lp->crushed_sum += (double)S->n_crushed;
        for (int i = 0; i < nb; ++i) {
            B->vx_vol[i] += B->vol[i];
            B->vx_sum[i] += B->vx_inst[i];
        }
    }
    lub_profile_normalise(B->vol, nb, dy, r->area, B->phi_inst);
    double pmax = 0.0;
    for (int i = 0; i < nb; ++i)
        pmax = fmax(pmax, B->phi_inst[i]);
    const double hs = lub_profile_height(B->phi_inst, nb, 0.0, dy, 0.5 * pmax);
    const double inv = lub_profile_inventory(B->phi_inst, nb, dy);
    const double ke = lub_rs_kinetic_energy(S);
    lp->max_ke = fmax(lp->max_ke, ke);
    double row[RS_NSERIES] = {hs, ysum / msum, inv / hs, ke, S->max_speed, (double)dilute};
    if (lub_h5_table_append(r->tab, S->step, t * r->sc.gd, row)) {
        snprintf(r->ctx->diagnostic, sizeof r->ctx->diagnostic, "%s",
                 lub_h5_last_error(r->ctx->out));
        return LUB_EXIT_IO;
    }
    if (lp->nh >= r->nsamp_total ||
        (step >= lp->avg_start_step && lp->navg >= r->nsamp_avg)) { /* never: their room */
        snprintf(r->ctx->diagnostic, sizeof r->ctx->diagnostic,
                 "internal error: the sample buffers are full (%lld height samples, %lld "
                 "profiles) at strain %.6g",
                 (long long)r->nsamp_total, (long long)r->nsamp_avg, t * r->sc.gd);
        return LUB_EXIT_INTERNAL;
    }
    B->series_t[lp->nh] = t;
    B->series_h[lp->nh++] = hs;
    if (step >= lp->avg_start_step) {
        memcpy(&B->samples[lp->navg * nb], B->phi_inst, (size_t)nb * sizeof *B->phi_inst);
        memcpy(&B->vx_samples[lp->navg * nb], B->vx_inst, (size_t)nb * sizeof *B->vx_inst);
        B->drag_share[lp->navg] = drag_share;
        lp->navg++;
    }
    return LUB_EXIT_OK;
}

/* The particles' snapshot at time t (unwrapped positions, absolute velocities, spins, the
 * cell's edges). LUB_EXIT_OK, or LUB_EXIT_IO with the diagnostic set. */
static int rs_snapshot(rs_run_state *r, double t)
{
    const lub_rs_system *S = &r->S;
    rs_buffers *B = &r->B;
    for (int i = 0; i < r->N; ++i) {
        vec3 xu, vu;
        lub_rs_unwrapped(S, i, &xu, &vu);
        memcpy(&B->snap_x[3 * i], &xu, 3 * sizeof(double));
        memcpy(&B->snap_v[3 * i], &vu, 3 * sizeof(double));
        memcpy(&B->snap_w[3 * i], &S->w[i], 3 * sizeof(double));
    }
    double edges[9];
    for (int row = 0; row < 3; ++row) /* rows = edge vectors = columns of H */
        for (int c = 0; c < 3; ++c)
            edges[3 * row + c] = S->cell.h[c][row];
    if (lub_h5_particles_snapshot(r->ctx->out, S->step, t, edges, B->snap_x, B->snap_v, B->snap_w,
                                  NULL)) {
        snprintf(r->ctx->diagnostic, sizeof r->ctx->diagnostic, "%s",
                 lub_h5_last_error(r->ctx->out));
        return LUB_EXIT_IO;
    }
    r->frames++;
    return LUB_EXIT_OK;
}

/* A periodic checkpoint (--checkpoint-every) of the state after the sample of loop index
 * `step`, as at a stop (the run then goes on); a failure is recorded, not fatal. */
static void rs_periodic_checkpoint(rs_run_state *r, int64_t step)
{
    lub_run_ctx *ctx = r->ctx;
    rs_mark_loop_state(r, step, 1);
    char why[400] = "";
    if (lub_periodic_copy_output(ctx->periodic, ctx->out) == 0) {
        if (rs_checkpoint_write(ctx->periodic->ckpt_tmp, r->resolved, &r->lp, &r->B, r->nb, &r->S,
                                LUB_PERIODIC_OUTPUT, why, sizeof why) == 0)
            lub_periodic_publish(ctx->periodic);
        else
            lub_periodic_failed(ctx->periodic, why);
    }
}

/* A step that failed with LUB_RS_* code e: the diagnostic, whether the time step is to blame
 * (r->step_unstable), and the exit code. */
static int rs_step_failed(rs_run_state *r, int e)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_rs_system *S = &r->S;
    if (e == LUB_RS_NOMEM && !S->fail_msg[0]) { /* the pair lists could not grow */
        char what[96];
        snprintf(what, sizeof what, "pair lists, step %lld", (long long)S->step);
        lub_diagnostic_out_of_memory(ctx, what, r->N, 0.0, "/n");
    } else {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s (code %d)", S->fail_msg, e);
    }
    const int rc = e == LUB_RS_NOMEM ? LUB_EXIT_INTERNAL : LUB_EXIT_NUMERICAL;
    r->step_unstable = e == LUB_RS_NONFINITE || e == LUB_RS_ESCAPED || e == LUB_RS_RUNAWAY;
    if (e == LUB_RS_ESCAPED && S->escaped_below &&
        lub_rs_weight_overlap(&r->p) >= LUB_RS_WEIGHT_OVERLAP_BLAMED) {
        /* heavy spheres on soft contacts sink through the floor: not the step's doing */
        const size_t len = strlen(ctx->diagnostic);
        snprintf(ctx->diagnostic + len, sizeof ctx->diagnostic - len,
                 ": the contacts give way under the bed's weight (a sphere's own weight "
                 "compresses a contact by %.3g a, (4/3) pi / (/shields /stiffness)); "
                 "raise /stiffness",
                 lub_rs_weight_overlap(&r->p));
        r->step_unstable = 0;
    }
    return rc;
}

/* The step control lowered the step after loop index `step`: the schedule and the averaging
 * start follow (the sample buffers already cover any step). LUB_EXIT_OK, or the exit code with
 * the diagnostic set (the step-count rule). */
static int rs_step_changed(rs_run_state *r, int64_t step)
{
    const lub_rs_spec *p = &r->p;
    const double gd = r->sc.gd;
    lub_run_ctx *ctx = r->ctx;
    rs_loop *lp = &r->lp;
    const double dt = r->dt = lp->ctl.dt;
    r->S.p.dt = dt;
    lub_schedule_set_dt(&lp->sched, step + 1, r->S.time, dt);
    if ((double)lp->sched.nsteps > LUB_MAX_STEPS) { /* step-count rule (step_count.h) */
        lub_step_count_fell(ctx->diagnostic, sizeof ctx->diagnostic, dt, r->S.time * gd,
                            p->dt_stiffness_safety, lp->ctl.changes, (double)lp->sched.nsteps);
        return LUB_EXIT_NUMERICAL;
    }
    if (lp->avg_start_step > step + 1)
        lp->avg_start_step =
            step + 1 + (int64_t)ceil((p->average_from / gd - r->S.time) / dt - 1e-9);
    return LUB_EXIT_OK; /* the sample buffers cover any step (rs_allocate_samples) */
}

/* The time loop from r->first_step to the end of the schedule: samples, snapshots, network
 * frames and checkpoints at their events, then the step. Ends at the last step, on a stop
 * request (r->stopped_at) or on a failure; returns the exit code so far. */
static int rs_time_loop(rs_run_state *r)
{
    lub_run_ctx *ctx = r->ctx;
    rs_loop *lp = &r->lp;
    int rc = LUB_EXIT_OK;
    r->stopped_at = -1;
    for (int64_t step = r->first_step; step <= lp->sched.nsteps; ++step) {
        const double t = r->S.time;
        /* the samples of the step a continuation starts at were taken by the stopped run (but
         * for a completed run's, its checkpoint taken before them): the end does not force them
         * again (a continuation asked for the strain already done) */
        const int taken = step == r->first_step && lp->step_taken; /* the checkpoint's */
        const int end = step == lp->sched.nsteps && !taken;
        if (step == lp->sched.nsteps && ctx->checkpoint_always && ctx->checkpoint_path) {
            /* A completed run keeps its state before the samples of its last step, which the
             * end forces (a sample, a snapshot) and a longer run would not take: its extension
             * (a larger /strain) then takes the steps and samples of the longer run. */
            rs_mark_loop_state(r, step, taken);
            r->end_checkpoint =
                rs_checkpoint_write(ctx->checkpoint_path, r->resolved, lp, &r->B, r->nb, &r->S,
                                    "result.h5", ctx->checkpoint_failure,
                                    sizeof ctx->checkpoint_failure) == 0;
        }
        const int sample = lub_schedule_due(&lp->sched, r->ev_sample, step) || end;
        const int snap = r->ev_snap >= 0 && (lub_schedule_due(&lp->sched, r->ev_snap, step) || end);
        if (sample || snap)
            rs_track_floor_clearance(r);
        if (sample && (rc = rs_sample(r, step, t)) != LUB_EXIT_OK)
            break;
        /* the network first: its list completion may wrap positions (the snapshot's are
         * unwrapped, lub_rs_unwrapped) */
        if (snap && r->p.pair_network == LUB_NETWORK_SNAPSHOTS &&
            (rc = rs_network_frame(ctx, &r->S, r->network, &r->net, r->sc.gd,
                                   step == lp->sched.nsteps)) != LUB_EXIT_OK)
            break;
        if (snap && (rc = rs_snapshot(r, t)) != LUB_EXIT_OK)
            break;
        if (step == lp->sched.nsteps)
            break;
        if (ctx->periodic && lub_periodic_due(ctx->periodic, step))
            rs_periodic_checkpoint(r, step);
        if (ctx->stop_requested && *ctx->stop_requested) {
            rc = LUB_EXIT_INTERRUPTED;
            r->stopped_at = step;
            break;
        }
        int e = lub_rs_step(&r->S);
        if (e != LUB_RS_OK) {
            rc = rs_step_failed(r, e);
            break;
        }
        if (lub_rs_step_control(&r->S, &lp->ctl) && (rc = rs_step_changed(r, step)) != LUB_EXIT_OK)
            break;
        if ((step & 255) == 0)
            lub_progress_update(ctx->progress, (double)step / (double)lp->sched.nsteps, r->S.step);
    }
    return rc;
}

/* After the loop: the checkpoint of a stopped run, the network of the final state, and which
 * checkpoint the driver may keep. Returns the exit code. */
static int rs_finish_loop(rs_run_state *r, int rc)
{
    lub_run_ctx *ctx = r->ctx;
    lub_progress_last_step(ctx->progress, r->S.step);
    ctx->checkpoint_written = r->end_checkpoint && rc == LUB_EXIT_OK;
    /* a stop between the sample of a step and the step: that state into the checkpoint */
    if (r->stopped_at >= 0 && ctx->checkpoint_path) {
        rs_mark_loop_state(r, r->stopped_at, 1);
        ctx->checkpoint_written =
            rs_checkpoint_write(ctx->checkpoint_path, r->resolved, &r->lp, &r->B, r->nb, &r->S,
                                "result.h5", ctx->checkpoint_failure,
                                sizeof ctx->checkpoint_failure) == 0;
    }
    /* the network of the final state (after the checkpoint, which keeps the state before the
     * rebuild the network may do), unless a snapshot's frame already shows it */
    int64_t network_last_step = -1;
    lub_h5_frames_written(r->network, &network_last_step);
    if (r->network && network_last_step != r->S.step &&
        (rc == LUB_EXIT_OK || rc == LUB_EXIT_INTERRUPTED)) {
        const int nrc = rs_network_frame(ctx, &r->S, r->network, &r->net, r->sc.gd, 1);
        if (nrc != LUB_EXIT_OK)
            rc = nrc;
    }
    lub_pair_network_free(&r->net);
    return rc;
}

/* After a numerical failure the time step may be to blame: what set it, and what to change. */
static void rs_failure_advice(rs_run_state *r, int rc)
{
    const lub_rs_spec *p = &r->p;
    if (rc == LUB_EXIT_NUMERICAL && r->dt_adapts && r->step_unstable)
        lub_diagnostic_adapted_dt_hint(r->ctx, r->dt, p->dt_safety, r->dt_crit, "dt_critical",
                                       r->lp.ctl.changes, p->dt_stiffness_safety,
                                       r->lp.ctl.ratio_max);
    else if (rc == LUB_EXIT_NUMERICAL && (r->step_unstable || p->dt > r->dt_crit))
        lub_diagnostic_dt_hint(r->ctx, p->dt, p->dt_safety, r->dt_crit, "dt_critical");
}

/* The steady-state statistics (also for a partial run: whatever was averaged), the profiles
 * into result.h5 and the summary. Returns the exit code (LUB_EXIT_IO when the profiles cannot
 * be written by a run that had none). */
static int rs_report(rs_run_state *r, int rc)
{
    const lub_rs_spec *p = &r->p;
    lub_run_ctx *ctx = r->ctx;
    rs_buffers *B = &r->B;
    const rs_loop *lp = &r->lp;
    const int gradient = p->orientation == LUB_RS_GRADIENT;
    const lub_rs_stats_input in = {.nb = r->nb,
                                   .dy = r->dy,
                                   .samples = B->samples,
                                   .navg = lp->navg,
                                   .height = B->series_h,
                                   .nh = lp->nh,
                                   .vx_volume = B->vx_vol,
                                   .vx_sum = B->vx_sum,
                                   .vx_samples = lp->sample_series ? B->vx_samples : NULL,
                                   .bin_volume = r->area * r->dy,
                                   .drag_share =
                                       lp->sample_series && gradient ? B->drag_share : NULL,
                                   .shields = p->Sh,
                                   .interface_width = p->interface_width,
                                   .floor_skip = p->floor_skip,
                                   .phi_min = p->phi_min,
                                   .phi_m = p->phi_m,
                                   .phi_window = p->phi_window,
                                   .vorticity = p->orientation == LUB_RS_VORTICITY};
    const lub_rs_stats_profiles pr = {.y = B->ybin,
                                      .phi = B->phi,
                                      .phi_err = B->phi_err,
                                      .phi_coarse = B->phi_cg,
                                      .phi_coarse_err = B->phi_cg_err,
                                      .eta = B->eta,
                                      .eta_err = B->eta_err,
                                      .law = B->law,
                                      .bulk = B->keep,
                                      .bulk_mask = B->keepd,
                                      .velocity_x = B->vx_inst,
                                      .eta_vs_phi = B->pairs_out,
                                      .scratch = B->scratch,
                                      .scratch2 = B->scratch2,
                                      .scratch3 = B->scratch3};
    lub_rs_stats st;
    lub_rs_statistics(&in, &pr, &st);
    /* the floor centre plane in the cell's coordinates (those of the particle snapshots), from
     * which every y of the profiles and the summary is measured */
    const int64_t one = 1;
    const int floor_failed = lub_h5_write_array(ctx->out, "y_floor", 1, &one, &r->y_floor, "a");
    if ((floor_failed ||
         (lp->navg > 0 && lub_rs_write_profiles(ctx->out, r->nb, &pr, st.eta_vs_phi_rows))) &&
        rc == LUB_EXIT_OK) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        rc = LUB_EXIT_IO;
    }
    const lub_rs_outcome o = {.system = &r->S,
                              .step_control = &lp->ctl,
                              .network = r->network,
                              .dt = r->dt,
                              .dt_critical = r->dt_crit,
                              .cell_width = r->L,
                              .floor_radius = r->rf,
                              .y_floor = r->y_floor,
                              .y_lid = r->y_lid,
                              .initial_height = r->h_init,
                              .solid_volume = r->vsum,
                              .initial_phi = r->binfo.layer_phi,
                              .averaged_samples = lp->navg,
                              .transient_end_strain = st.transient_end < (size_t)lp->nh
                                                          ? B->series_t[st.transient_end] * r->sc.gd
                                                          : NAN,
                              .min_clearance = lp->min_lowest,
                              .below_floor_max = lp->below_floor_max,
                              .max_kinetic_energy = lp->max_ke,
                              .contacts_sum = lp->contacts_sum,
                              .crushed_sum = lp->crushed_sum,
                              .drag_share_sum = lp->drag_share_sum,
                              .stopped = r->stopped_at >= 0};
    lub_rs_write_summary(ctx, p, &r->sc, &st, &o);
    return rc;
}

static int rs_run(const json_t *resolved, lub_run_ctx *ctx)
{
    rs_run_state r;
    memset(&r, 0, sizeof r);
    r.ctx = ctx;
    r.resolved = resolved;
    r.stopped_at = -1;
    /* set-up: each phase runs only when the ones before it succeeded */
    int rc = rs_read_spec(&r);
    if (rc == LUB_EXIT_OK)
        rc = rs_build_bed(&r);
    if (rc == LUB_EXIT_OK)
        rc = rs_init_system(&r);
    if (rc == LUB_EXIT_OK)
        rc = rs_allocate_samples(&r);
    if (rc == LUB_EXIT_OK)
        rc = rs_define_outputs(&r);
    if (rc == LUB_EXIT_OK && ctx->resume_path) /* the stopped run's state replaces the fresh one */
        rc = rs_continue_stopped_run(&r);
    if (rc != LUB_EXIT_OK) {
        rs_run_state_free(&r);
        return rc;
    }
    rc = rs_finish_loop(&r, rs_time_loop(&r));
    rs_failure_advice(&r, rc);
    rc = rs_report(&r, rc);
    rs_run_state_free(&r);
    return rc;
}

/* what a continuation may change: a completed run is extended to a larger /strain, and may
 * write the interaction network otherwise */
static const char *const rs_resume_may_differ[] = {"strain", "pair_network", NULL};

const lub_scene lub_scene_resuspension = {
    .name = "resuspension",
    .title = "Viscous resuspension of buoyant spheres sheared above a rough floor",
    .description =
        "Viscous resuspension (Chevremont, Chareyre & Bodiguel, resuspension article): N "
        "lubricated spheres (Gaussian radii) in a cell periodic in x and z above a rough "
        "floor of fixed spheres, gravity along -y, a reflecting lid far above. orientation "
        "'gradient': gravity along the gradient, shear imposed by a drag (viscosity "
        "shear_drag_viscosity eta, default 1/30) towards u = gd y e_x; 'vorticity': gravity "
        "along the vorticity, Lees-Edwards shear of the x-z plane, no shear drag. Particles "
        "with at most dilute_drag.max_interactions pairs get a Stokes drag. Units: a, eta, "
        "1/gd; inputs Sh = eta gd/(drho g a), I = gd sqrt(a/g), density_ratio rho_p/drho. "
        "Reports the steady phi(y) with error bars, the suspension height, eta_ii(y) = "
        "(1/Sh) int_y phi, the bulk eta_ii(phi) (interface discarded), Sh, Acrivos A, I.",
    .resolve = lub_rs_spec_resolve,
    .run = rs_run,
    .resumable = 1,
    .resume_may_differ = rs_resume_may_differ,
};

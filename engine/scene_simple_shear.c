/* scene_simple_shear.c — tri-periodic simple-shear rheometer of a dense suspension of rough,
 * lubricated, frictional spheres (physics-reference §2–§3; seed 000 rheology article and
 * normal-stress chapter; seed 004).
 *
 * Units (dimensionless):
 *   length a = mean radius (radii Gaussian, relative std `radius_std`), fluid viscosity eta = 1;
 *   control "volume":   shear rate gd = 1  -> stress unit eta gd, time unit 1/gd;
 *   control "pressure": particle pressure P = 1 -> stress unit P, gd = Iv P/eta = Iv,
 *                       time unit eta/P.
 *   Density from the Stokes number St = rho gd a^2/eta; bulk stiffness g = stiffness * s0 * a
 *   with s0 = eta gd (volume) or P (pressure); k_n = alpha g; k_t = kt_ratio g.
 * Controls: imposed volume (cell fixed in y, pressure measured) or imposed particle pressure
 * (servo on the gradient-direction cell size, see servo_step()).
 * Observables: virial stress split NC/SC/NL/SL/kinetic (stress.h), phi, P = -sigma_yy,
 * mu = sigma_xy/P, eta_r = sigma_xy/(eta gd), Iv = eta gd/P, eta_ii = -sigma_ii/(eta gd),
 * sigma_11/sigma_22, sigma_33/sigma_22, the interaction number Z (2 x interacting pairs / N: the
 * pairs inside the cut-off, or the Delaunay set's, so it grows with the cut-off; not a contact
 * coordination) and the contact number Z_c (2 x contacts / N, rattlers counted),
 * the global bond order Q6 of the first neighbour shell (bond_order.h: 0.05-0.09 in sheared
 * disordered packings, 0.57 for fcc; a rise flags ordering of the cell), optional microstructure
 * (microstructure.h). Steady state and error bars: stats.h. Optional `drag_viscosity` eta_d: a
 * Stokes drag -6 pi eta_d eta r (v - L x) on every particle towards the affine flow (the shear drag
 * of the resuspension scene's gradient orientation), so that its effect on the stresses can be
 * measured in homogeneous shear; "affine_drag" is then listed in active_terms. The drag is a body
 * force: it is not part of the virial stress. The summary's elastic_number (stiffness s0/<P>)
 * and warnings come from the advisory checks of shear_run_checks.h.
 * The spec's members and checks are in simple_shear_spec.h, the series and their statistics in
 * simple_shear_series.h; this file is the run: the system from a packing or a checkpoint, the
 * outputs, the time loop, and what is written at its end (ss_run calls the phases in order).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "continuum_normal_laws.h"
#include "h5md_continue.h"
#include "law_spec.h"
#include "network_output.h"
#include "packing.h"
#include "pair_network.h"
#include "run_context.h"
#include "scene.h"
#include "scene_summary.h"
#include "shear_checkpoint.h"
#include "shear_run_checks.h"
#include "shear_system.h"
#include "simple_shear_series.h"
#include "simple_shear_spec.h"
#include "state_checkpoint.h"
#include "stats.h"
#include "step_count.h"
#include "step_schedule.h"
#include "step_stiffness.h"

/* bond_order_q6: bonds are pairs with centre distance below this factor times r_i + r_j
 * (gaps below 0.4 a_ij: the first shell of neighbours) */
#define SS_BOND_FACTOR 1.2

static int ss_resolve(json_t *spec, lub_error *err)
{
    lub_ss_params p;
    return lub_ss_read(spec, &p, err);
}

/* Servo (imposed pressure). P_f is an exponential low-pass of the instantaneous pressure
 * -sigma_yy with time constant filter_strain/gd; the gradient-direction dilation rate is
 *   L_yy = gain * gd * clamp((P_f - P)/P, -1, 1):
 * the cell expands when the filtered pressure is too high and contracts when it is too low.
 * The change of L_yy is applied as a homogeneous velocity change (lub_shear_set_gradient),
 * so the particles follow the cell without a pressure wave. */
static void servo_step(lub_shear_system *s, double p_inst, double *p_f, double dt, double gd,
                       const lub_ss_params *p)
{
    double tau = p->servo_filter_strain / gd;
    double w = dt / tau;
    if (w > 1.0)
        w = 1.0;
    *p_f += w * (p_inst - *p_f);
    double err = (*p_f - 1.0);
    if (err > 1.0)
        err = 1.0;
    if (err < -1.0)
        err = -1.0;
    double L[3][3];
    memcpy(L, s->cell.L, sizeof L);
    L[1][1] = p->servo_gain * gd * err;
    lub_shear_set_gradient(s, L);
}

/* 1 when the stopped run's result file (path) has images with its snapshots, or none to copy;
 * 0 for a file written before images were: its continuation then has none either, so that no
 * frame carries images that are not its own. */
static int ss_stopped_has_image(const char *path, int64_t frames)
{
    if (frames <= 0)
        return 1;
    char err[8];
    lub_h5_reader *r = lub_h5r_open(path, err, sizeof err);
    const int has = r && lub_h5r_has_image(r) == 1;
    lub_h5r_close(r);
    return has;
}

static int ss_snapshot(lub_run_ctx *ctx, const lub_shear_system *s)
{
    _Static_assert(sizeof(int) == sizeof(int32_t), "the images are written as int32");
    double edges[9];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            edges[3 * r + c] = s->cell.h[c][r]; /* rows = edge vectors */
    return lub_h5_particles_snapshot(ctx->out, s->step, s->time, edges, (const double *)s->x,
                                     (const double *)s->v, (const double *)s->w,
                                     lub_h5_particles_has_image(ctx->out) ? s->img : NULL);
}

/* The interaction network of the system's current state (pair_network.h, computed into net,
 * whose arrays are kept for the next frame) appended to /pair_network. final: no step of this
 * run follows. 0, or the exit code with ctx->diagnostic set. */
static int ss_network_frame(lub_run_ctx *ctx, lub_shear_system *s, lub_h5_frames *frames,
                            lub_pair_network *net, int final)
{
    /* The rebuild the network may do first is the one the next step would do: before a step
     * it counts (the step control adapts the step after each rebuild it sees, and the step
     * then does none), at the end it is none of the run's, and the summary's
     * neighbor_rebuilds and cell_flips stay those of the steps; so do the Delaunay update
     * statistics (the update a final frame may do is none of the run's either). */
    const long rebuilds = s->rebuilds, flips = s->flips;
    const lub_topology topo = s->topo;
    const int rc = lub_shear_pair_network(s, net);
    if (final) {
        s->rebuilds = rebuilds;
        s->flips = flips;
        s->topo.updates = topo.updates;
        s->topo.inside = topo.inside;
        s->topo.allowed = topo.allowed;
        s->topo.open = topo.open;
    }
    if (rc != LUB_SHEAR_OK) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "interaction network at step %ld: %s",
                 s->step,
                 rc == LUB_SHEAR_NOMEM ? "out of memory (/pair_network: \"none\" avoids it)"
                                       : s->fail_msg);
        return rc == LUB_SHEAR_NOMEM ? LUB_EXIT_INTERNAL : LUB_EXIT_NUMERICAL;
    }
    if (lub_network_append(frames, net, s->step, s->time)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }
    return LUB_EXIT_OK;
}

/* The time loop's state besides the system (shear_system.h): what a checkpoint holds with the
 * system and the series, so that a stopped run continues as if it had not stopped. */
typedef struct {
    int64_t step;               /* steps done */
    double strain;              /* shear strain done */
    double p_f;                 /* the servo's filtered pressure (servo_step) */
    double next_check;          /* strain of the next /target_rel_error check */
    double bonds_sum;           /* Q6 bonds over all samples, for the noise floor of the Q6 check */
    int64_t bonds_samples;      /* samples in bonds_sum */
    int64_t frames;             /* particle snapshots asked for so far */
    int64_t last_snapshot_step; /* system step of the last snapshot written, -1 none */
    int64_t snap_owed_step;     /* system step of a state whose snapshot event fell within half a
                                   spacing of the end and was left to the end's snapshot (which a
                                   longer run, extending this one, takes at once), -1 none */
    double packing_min_gap;
    /* the packing's pairs closer than /law/eps a_ij (contacts from the first step) and its
     * smallest gap over a_ij; -1 and NaN from a checkpoint older than them (2026-12-07) */
    int64_t packing_contacts;
    double packing_min_gap_aij;
    lub_step_control ctl;
    lub_schedule sched;
} ss_loop;

/* The loop state, the series and the system into path (a new file), with the particle
 * snapshots and /pair_network frames its output file holds. 0, or -1 with why[len]. */
static int ss_checkpoint_write(const char *path, const json_t *resolved, const ss_loop *lp,
                               const lub_ss_series *ser, int64_t frames_in_file,
                               int64_t network_frames_in_file, const lub_shear_system *sys,
                               const char *output_file, char *why, size_t len)
{
    lub_ckpt *c =
        lub_run_checkpoint_create(path, "simple_shear", lp->step, resolved, output_file, why, len);
    if (!c)
        return -1;
    const int rc = lub_ckpt_put_i64(c, "run/step", lp->step) ||
                   lub_ckpt_put_f64(c, "run/strain", lp->strain) ||
                   lub_ckpt_put_f64(c, "run/servo_filtered_pressure", lp->p_f) ||
                   lub_ckpt_put_f64(c, "run/next_check", lp->next_check) ||
                   lub_ckpt_put_f64(c, "run/bonds_sum", lp->bonds_sum) ||
                   lub_ckpt_put_i64(c, "run/bonds_samples", lp->bonds_samples) ||
                   lub_ckpt_put_i64(c, "run/frames_in_file", frames_in_file) ||
                   lub_ckpt_put_i64(c, "run/network_frames_in_file", network_frames_in_file) ||
                   lub_ckpt_put_f64(c, "run/packing_min_gap", lp->packing_min_gap) ||
                   lub_ckpt_put_i64(c, "run/packing_contacts", lp->packing_contacts) ||
                   lub_ckpt_put_f64(c, "run/packing_min_gap_aij", lp->packing_min_gap_aij) ||
                   lub_ckpt_put_i64(c, "run/last_snapshot_step", lp->last_snapshot_step) ||
                   lub_ckpt_put_i64(c, "run/snapshot_owed_step", lp->snap_owed_step) ||
                   lub_step_control_save(c, "run/step_control", &lp->ctl) ||
                   lub_schedule_save(c, "run/schedule", &lp->sched) || lub_ss_series_save(c, ser) ||
                   lub_shear_save(c, sys);
    return lub_run_checkpoint_close(c, rc, why, len);
}

/* The loop state (lp: all but the series) of checkpoint c, with the rows, snapshots and
 * /pair_network frames its output file holds (a checkpoint older than the frames: none); the
 * series are read by lub_ss_series_load once they have room. 0, or -1 with why[len]. */
static int ss_checkpoint_read_loop(lub_ckpt *c, ss_loop *lp, int64_t *rows, int64_t *frames_in_file,
                                   int64_t *network_frames_in_file, char *why, size_t len)
{
    size_t n_rows = 0;
    if (lub_ckpt_get_i64(c, "run/step", &lp->step) ||
        lub_ckpt_get_f64(c, "run/strain", &lp->strain) ||
        lub_ckpt_get_f64(c, "run/servo_filtered_pressure", &lp->p_f) ||
        lub_ckpt_get_f64(c, "run/next_check", &lp->next_check) ||
        lub_ckpt_get_f64(c, "run/bonds_sum", &lp->bonds_sum) ||
        lub_ckpt_get_i64(c, "run/bonds_samples", &lp->bonds_samples) ||
        lub_ckpt_get_i64(c, "run/frames_in_file", frames_in_file) ||
        lub_ckpt_get_f64(c, "run/packing_min_gap", &lp->packing_min_gap) ||
        lub_step_control_load(c, "run/step_control", &lp->ctl) ||
        lub_schedule_load(c, "run/schedule", &lp->sched) ||
        lub_ckpt_count(c, "series/strain", &n_rows)) {
        snprintf(why, len, "%s",
                 lub_ckpt_error(c)[0] ? lub_ckpt_error(c) : "inconsistent step control or events");
        return -1;
    }
    if (lp->step < 0 || lp->step > lp->sched.nsteps) {
        snprintf(why, len, "inconsistent loop state (step %lld of %lld)", (long long)lp->step,
                 (long long)lp->sched.nsteps);
        return -1;
    }
    /* none in a checkpoint older than the frames, or than the snapshot steps (2026-12-07) */
    if (lub_ckpt_get_i64_or(c, "run/network_frames_in_file", 0, network_frames_in_file) ||
        lub_ckpt_get_i64_or(c, "run/last_snapshot_step", -1, &lp->last_snapshot_step) ||
        lub_ckpt_get_i64_or(c, "run/snapshot_owed_step", -1, &lp->snap_owed_step) ||
        lub_ckpt_get_i64_or(c, "run/packing_contacts", -1, &lp->packing_contacts)) {
        snprintf(why, len, "%s", lub_ckpt_error(c));
        return -1;
    }
    lp->packing_min_gap_aij = NAN;
    if (lub_ckpt_has(c, "run/packing_min_gap_aij") &&
        lub_ckpt_get_f64(c, "run/packing_min_gap_aij", &lp->packing_min_gap_aij)) {
        snprintf(why, len, "%s", lub_ckpt_error(c));
        return -1;
    }
    *rows = (int64_t)n_rows;
    return 0;
}

/* The start of a continuation (ctx->resume_path): opens the checkpoint, reads the loop state
 * into *lp (rows, snapshots and network frames to copy into *rows, *frames, *network_frames),
 * the radii and positions into new arrays. 0, or -1 with ctx->resume_rejected and the
 * diagnostic set (the checkpoint closed). */
static int ss_resume_begin(lub_run_ctx *ctx, int n, lub_ckpt **ckpt, ss_loop *lp, int64_t *rows,
                           int64_t *frames, int64_t *network_frames, double **radius, vec3 **pos)
{
    char why[512] = "";
    int saved_n = 0;
    *ckpt = lub_ckpt_open(ctx->resume_path, why, sizeof why);
    if (*ckpt &&
        ss_checkpoint_read_loop(*ckpt, lp, rows, frames, network_frames, why, sizeof why) == 0) {
        if (lub_shear_saved_particles(*ckpt, &saved_n, radius) || saved_n != n) {
            snprintf(why, sizeof why, "%s",
                     lub_ckpt_error(*ckpt)[0] ? lub_ckpt_error(*ckpt) : "another particle count");
        } else if (!(*pos = malloc((size_t)n * sizeof **pos))) {
            snprintf(why, sizeof why, "out of memory (positions)");
        } else if (lub_ckpt_get(*ckpt, "system/x", LUB_CKPT_F64, 3 * (size_t)n, *pos)) {
            snprintf(why, sizeof why, "%s", lub_ckpt_error(*ckpt));
        } else {
            return 0;
        }
    }
    snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "cannot continue from %s: %s",
             ctx->resume_path, why[0] ? why : "unreadable");
    ctx->resume_rejected = 1;
    if (*ckpt)
        lub_ckpt_close(*ckpt, NULL, 0);
    *ckpt = NULL;
    free(*radius);
    free(*pos);
    *radius = NULL;
    *pos = NULL;
    return -1;
}

/* ------------------------------------------------------------------------------------------ */
/* The run, in phases over one state (ss_run at the end of this section orchestrates them). */

typedef struct {
    /* fixed for the run */
    const json_t *resolved;
    lub_run_ctx *ctx;
    lub_ss_params p;
    int n;
    double gd;     /* shear rate in the scene units */
    double s0;     /* stress unit: P or eta gd (eta = 1) */
    double dt_el;  /* the elastic bound of the lightest particle (lub_shear_elastic_dt) */
    int dt_adapts; /* the step follows the pairs' summed stiffness (/dt_stiffness_safety) */
    int ev_sample, ev_pdf, ev_snap; /* the schedule's events (-1: none) */
    /* the state */
    lub_shear_system sys;
    ss_loop lp; /* the loop's state: a fresh start, or the checkpoint's (resumed) */
    double dt;  /* the current step */
    lub_ss_series ser;
    double *radius;
    lub_h5_table *tab;
    lub_h5_frames *network; /* /pair_network, when asked for */
    lub_pair_network net;   /* its arrays, kept from frame to frame */
    /* a continuation: the checkpoint it starts from (closed once read), and what its output
     * file holds */
    lub_ckpt *resume;
    int64_t resume_rows, resume_frames, resume_network_frames;
    /* the outcome */
    int exit_code;
    int64_t step;           /* steps done when the loop ended */
    int stopped_early;      /* stopped on /target_rel_error */
    int stopped_by_request; /* a stop request ended the loop between two steps */
    int step_unstable;      /* the failure is one the time step causes (non-finite, runaway) */
    int servo_squeezed;     /* the failure is a cell the servo squeezed (its diagnostic says so) */
} ss_run_state;

/* The particles of a fresh run: a packing at /phi, into r->radius, *pos and *cell. */
static int ss_pack(ss_run_state *r, vec3 **pos, lub_cell *cell)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_ss_params *p = &r->p;
    const int n = r->n;
    r->radius = malloc((size_t)n * sizeof *r->radius);
    *pos = malloc((size_t)n * sizeof **pos);
    if (!r->radius || !*pos) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory (packing)");
        return LUB_EXIT_INTERNAL;
    }
    lub_packing_params pp = {.n = n,
                             .phi = p->phi,
                             .radius_std = p->radius_std,
                             .seed = (uint64_t)p->seed,
                             .margin = p->initial_gap, /* gaps >= margin a_ij */
                             .max_sweeps = 2000000,
                             .stop = ctx->stop_requested};
    lub_packing_info pinfo;
    int prc = lub_packing_generate(&pp, r->radius, *pos, cell, &pinfo);
    if (prc == -3) { /* SIGTERM/SIGINT while packing: a partial run without a step */
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "stopped while generating the packing, before the first step");
        return LUB_EXIT_INTERRUPTED;
    }
    if (prc) {
        if (prc == -1)
            lub_diagnostic_out_of_memory(ctx, "packing", n, 0.0, "/n_particles");
        else if (prc == -4) /* too few spheres: the spec refuses such sizes before */
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                     "packing generation failed: %d spheres at phi=%g are too few for the "
                     "packing's pair search (cube narrower than twice their contact distance)",
                     n, p->phi);
        else
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                     "packing generation failed (target fraction not reached without "
                     "overlaps) for n=%d phi=%g",
                     n, p->phi);
        return LUB_EXIT_INTERNAL;
    }
    r->lp.packing_min_gap = pinfo.min_gap;
    lub_packing_gaps gaps;
    if (lub_packing_gap_census(cell, *pos, r->radius, n, p->law.params.eps, &gaps)) {
        lub_diagnostic_out_of_memory(ctx, "packing", n, 0.0, "/n_particles");
        return LUB_EXIT_INTERNAL;
    }
    r->lp.packing_contacts = gaps.below;
    r->lp.packing_min_gap_aij = gaps.min_gap_a;
    return LUB_EXIT_OK;
}

/* The step and its schedule: the step fixed (/dt), or /dt_safety of the single-pair bound,
 * lowered while the pairs' summed stiffness needs it (/dt_stiffness_safety; step_stiffness.h,
 * checked at every neighbour-list rebuild); the fresh run's step count checked; the Delaunay
 * updates; the events (samples, microstructure, snapshots) of a fresh run. */
static int ss_schedule(ss_run_state *r)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_ss_params *p = &r->p;
    ss_loop *lp = &r->lp;
    const double gd = r->gd;
    r->dt_el = lub_shear_elastic_dt(&r->sys);
    r->dt_adapts = p->dt <= 0.0 && p->dt_stiffness_safety > 0.0;
    lub_step_control_init(&lp->ctl, p->dt > 0 ? p->dt : p->dt_safety * r->dt_el,
                          r->dt_adapts ? p->dt_stiffness_safety : 0.0);
    r->dt = lp->ctl.dt;
    r->sys.dt = r->dt;
    const double dt = r->dt;
    if (!r->resume && !lub_step_count_ok(lub_step_count(p->strain / gd, dt))) {
        /* the step-count rule (step_count.h) with this packing's lightest particle, which
         * validation could only bound: refused before the first step, exit 2 */
        lub_error err;
        memset(&err, 0, sizeof err);
        const double r_eff =
            p->dt > 0.0 ? 1.0 : pow(r->dt_el / lub_ss_elastic_dt(p, 1.0), 2.0 / 3.0);
        lub_ss_step_refusal(p, r_eff, lub_step_count(p->strain / gd, dt), dt, "", &err);
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s: %s", err.pointer, err.message);
        return LUB_EXIT_BAD_SPEC;
    }
    if (p->delaunay) { /* contacts (u_n < eps a) are never cut off between updates */
        const double every = fmin(1e6, fmax(1.0, floor(p->delaunay_strain / (gd * dt) + 0.5)));
        lub_shear_use_delaunay(&r->sys, (int)every, fmax(0.05, 2.0 * p->law.params.eps));
    }
    const double t_end = p->strain / gd;
    lub_schedule_init(&lp->sched, dt, t_end);
    const int64_t sample_every = lub_schedule_period(p->sample_strain / gd, dt);
    const int64_t pdf_every = lub_schedule_period(p->pdf_interval / gd, dt);
    const int64_t snap_every =
        p->snapshots > 0 ? (lp->sched.nsteps + p->snapshots - 1) / p->snapshots : 0;
    r->ev_sample =
        lub_schedule_add(&lp->sched, sample_every, sample_every - 1, p->sample_strain / gd);
    r->ev_pdf = lub_schedule_add(&lp->sched, pdf_every, 0, p->pdf_interval / gd);
    r->ev_snap = snap_every > 0 ? lub_schedule_add(&lp->sched, snap_every, snap_every - 1,
                                                   (double)snap_every * dt)
                                : -1;
    lp->next_check = fmax(p->transient_strain + 1.0, 1.0);
    lp->last_snapshot_step = lp->snap_owed_step = -1;
    return LUB_EXIT_OK;
}

/* A continuation: the stopped run's state replaces the fresh one (same events, same ids), and
 * a new /strain moves the end. */
static int ss_continue(ss_run_state *r, const ss_loop *resumed)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_ss_params *p = &r->p;
    ss_loop *lp = &r->lp;
    const double t_end = p->strain / r->gd;
    if (lub_shear_restore(r->resume, &r->sys) || resumed->sched.n_events != lp->sched.n_events) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "cannot continue from %s: %s",
                 ctx->resume_path,
                 lub_ckpt_error(r->resume)[0] ? lub_ckpt_error(r->resume)
                                              : "inconsistent pairs or events");
        ctx->resume_rejected = 1;
        return LUB_EXIT_BAD_SPEC;
    }
    *lp = *resumed;
    r->dt = lp->ctl.dt;
    r->sys.dt = r->dt;
    ctx->resumed_from_step = lp->step;
    ctx->resume_begun = 1;
    /* a continuation may ask for another /strain (scene: resume_may_differ), not for less
     * than the stopped run has done: the run then takes the steps of one asked for that
     * strain from the start (lub_schedule_set_end) */
    if (t_end != lp->sched.t_end) {
        if (p->strain < lp->strain) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                     "cannot continue from %s: /strain: %g here, but the stopped run has "
                     "already sheared to %.6g",
                     ctx->resume_path, p->strain, lp->strain);
            ctx->resume_rejected = 1;
            return LUB_EXIT_BAD_SPEC;
        }
        lub_schedule_set_end(&lp->sched, t_end);
        if ((double)lp->sched.nsteps > LUB_MAX_STEPS) { /* at the stopped run's step */
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                     "cannot continue from %s: /strain: %g would take the run to %.3g steps "
                     "at its step of %.3g, more than the %.0e a run may take (README, CLI "
                     "contract, \"Step count\")",
                     ctx->resume_path, p->strain, (double)lp->sched.nsteps, r->dt, LUB_MAX_STEPS);
            ctx->resume_rejected = 1;
            return LUB_EXIT_BAD_SPEC;
        }
    }
    return LUB_EXIT_OK;
}

/* The system, from a packing or from the checkpoint of a stopped run, with its step and
 * schedule. */
static int ss_setup_system(ss_run_state *r)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_ss_params *p = &r->p;
    vec3 *pos = NULL;
    lub_cell cell;
    lub_cell_init_box(&cell, 1.0, 1.0, 1.0); /* a continuation's cell comes from its checkpoint */
    ss_loop resumed;
    memset(&resumed, 0, sizeof resumed);
    if (ctx->resume_path) {
        if (ss_resume_begin(ctx, r->n, &r->resume, &resumed, &r->resume_rows, &r->resume_frames,
                            &r->resume_network_frames, &r->radius, &pos))
            return LUB_EXIT_BAD_SPEC;
        r->lp.packing_min_gap = resumed.packing_min_gap;
        r->lp.packing_contacts = resumed.packing_contacts;
        r->lp.packing_min_gap_aij = resumed.packing_min_gap_aij;
    } else {
        const int rc = ss_pack(r, &pos, &cell);
        if (rc != LUB_EXIT_OK) {
            free(pos);
            return rc;
        }
    }
    cell.L[0][1] = r->gd;
    int pdf_nt = p->pdf_on ? (int)p->pdf_nt : 0, pdf_np = p->pdf_on ? (int)p->pdf_np : 0;
    int src = lub_shear_init(&r->sys, r->n, r->radius, pos, &cell, &p->law.params, p->St / r->gd,
                             p->cutoff, p->skin, 1.0, ctx->threads, pdf_nt, pdf_np);
    free(pos);
    if (src) {
        lub_diagnostic_out_of_memory(ctx, "system", r->n, 0.0, "/n_particles");
        return LUB_EXIT_INTERNAL;
    }
    r->sys.drag_viscosity = p->drag_viscosity; /* eta = 1 */
    int rc = ss_schedule(r);
    if (rc == LUB_EXIT_OK && r->resume)
        rc = ss_continue(r, &resumed);
    /* the bond list of bond_order_q6, where the pair list cannot hold the bonds, allocated
     * here rather than at the first sample that needs it (no allocation in the time loop) */
    if (rc == LUB_EXIT_OK &&
        lub_shear_bond_order_prepare(&r->sys, SS_BOND_FACTOR) == LUB_NLIST_NOMEM) {
        lub_diagnostic_out_of_memory(ctx, "bond list", r->n, 0.0, "/n_particles");
        rc = LUB_EXIT_INTERNAL;
    }
    return rc;
}

/* The series from the first sample (a continuation: from the checkpoint's) to /strain. */
static int ss_setup_series(ss_run_state *r)
{
    lub_run_ctx *ctx = r->ctx;
    const ss_loop *lp = &r->lp;
    /* room for the most samples any step the control may choose gives (the loop never grows
     * it; until 2026-12-07 a change of the step reallocated every series, outside the memory
     * check) */
    const size_t samples_cap = (size_t)r->resume_rows +
                               (size_t)lub_schedule_most_occurrences(&lp->sched, r->ev_sample,
                                                                     r->sys.time, lp->ctl.dt_base);
    char series_what[96];
    snprintf(series_what, sizeof series_what, "the %zu samples of the time series", samples_cap);
    if (!lub_memory_fits(ctx, (double)samples_cap * LUB_SS_SAMPLE_BYTES, series_what,
                         "/strain (or raise /sample_strain)"))
        return LUB_EXIT_INTERNAL;
    if (lub_ss_series_reserve(&r->ser, samples_cap)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory (series)");
        return LUB_EXIT_INTERNAL;
    }
    if (r->resume) {
        if (lub_ss_series_load(r->resume, &r->ser, (size_t)r->resume_rows)) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "cannot continue from %s: %s",
                     ctx->resume_path, lub_ckpt_error(r->resume));
            ctx->resume_rejected = 1;
            return LUB_EXIT_BAD_SPEC;
        }
        lub_ckpt_close(r->resume, NULL, 0);
        r->resume = NULL;
    }
    return LUB_EXIT_OK;
}

/* The time-series table's columns (one row per sample; ss_record_sample writes them). */
#define SS_TABLE_COLUMNS 17
static const char *const ss_table_names[SS_TABLE_COLUMNS] = {"strain",
                                                             "phi",
                                                             "pressure",
                                                             "mu",
                                                             "eta_r",
                                                             "Iv",
                                                             "Z",
                                                             "Z_contact",
                                                             "cell_ly",
                                                             "servo_rate",
                                                             "stress/total",
                                                             "stress/normal_contact",
                                                             "stress/tangential_contact",
                                                             "stress/normal_lubrication",
                                                             "stress/tangential_lubrication",
                                                             "stress/kinetic",
                                                             "bond_order_q6"};
static const int ss_table_widths[SS_TABLE_COLUMNS] = {1, 1, 1, 1, 1, 1, 1, 1, 1,
                                                      1, 9, 9, 9, 9, 9, 9, 1};

/* result.h5's tables, the interaction network and the first snapshot; a continuation's
 * output carries the stopped run's rows, snapshots and network frames, unchanged. */
static int ss_open_outputs(ss_run_state *r)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_ss_params *p = &r->p;
    const char *su = p->pressure ? "P" : "eta*gd";
    const char *tunits[SS_TABLE_COLUMNS] = {"1",  "1", su, "1", "1", "1", "1", "1", "a",
                                            "gd", su,  su, su,  su,  su,  su,  "1"};
    r->tab = lub_h5_set_units(ctx->out, p->pressure ? "eta/P" : "1/gd", "a",
                              p->pressure ? "a*P/eta" : "a*gd", p->pressure ? "P/eta" : "gd") == 0
                 ? lub_h5_table_create(ctx->out, SS_TABLE_COLUMNS, ss_table_names, ss_table_widths,
                                       tunits)
                 : NULL;
    if (!r->tab) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }
    const char *force_unit = p->pressure ? "P*a^2" : "eta*gd*a^2";
    const char *torque_unit = p->pressure ? "P*a^3" : "eta*gd*a^3";
    if (p->pair_network != LUB_NETWORK_NONE &&
        !(r->network = lub_network_define(ctx->out, force_unit, torque_unit,
                                          p->pressure ? "eta/P" : "1/gd"))) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }
    const char *bnd[3] = {"periodic", "periodic", "periodic"};
    if (ctx->resume_path) {
        char why[600] = "";
        if (p->snapshots > 0 && (lub_h5_particles_define(ctx->out, r->n, r->radius, bnd) ||
                                 (ss_stopped_has_image(ctx->resume_result, r->resume_frames) &&
                                  lub_h5_particles_define_image(ctx->out))))
            snprintf(why, sizeof why, "%s", lub_h5_last_error(ctx->out));
        else if (lub_h5_continue_output(
                     ctx->resume_result, r->tab, SS_TABLE_COLUMNS, ss_table_names, ss_table_widths,
                     r->resume_rows, r->ser.strain, ctx->out, r->n,
                     p->snapshots > 0 ? r->resume_frames : 0, why, sizeof why) == 0 &&
                 r->network)
            lub_h5_continue_frames(ctx->resume_result, r->network, r->resume_network_frames, why,
                                   sizeof why);
        r->lp.frames = p->snapshots > 0 ? r->resume_frames : 0;
        if (why[0]) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "cannot continue from %s: %s",
                     ctx->resume_result, why);
            ctx->resume_rejected = 1;
            return LUB_EXIT_BAD_SPEC;
        }
    } else if (p->snapshots > 0) {
        int rc;
        if (p->pair_network == LUB_NETWORK_SNAPSHOTS &&
            (rc = ss_network_frame(ctx, &r->sys, r->network, &r->net, 0)) != LUB_EXIT_OK)
            return rc;
        if (lub_h5_particles_define(ctx->out, r->n, r->radius, bnd) ||
            lub_h5_particles_define_image(ctx->out) || ss_snapshot(ctx, &r->sys)) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
            return LUB_EXIT_IO;
        }
        r->lp.frames = 1;
        r->lp.last_snapshot_step = r->sys.step;
    }
    return LUB_EXIT_OK;
}

/* A periodic checkpoint (--checkpoint-every) of the state before step `step`, as at a stop
 * (the run then goes on). */
static void ss_periodic_checkpoint(ss_run_state *r, int64_t step)
{
    lub_run_ctx *ctx = r->ctx;
    r->lp.step = step;
    const int64_t in_file = r->lp.frames - lub_h5_snapshots_skipped(ctx->out, NULL, NULL, 0);
    const int64_t network_in_file = lub_h5_frames_written(r->network, NULL);
    char why[400] = "";
    if (lub_periodic_copy_output(ctx->periodic, ctx->out) == 0) {
        if (ss_checkpoint_write(ctx->periodic->ckpt_tmp, r->resolved, &r->lp, &r->ser, in_file,
                                network_in_file, &r->sys, LUB_PERIODIC_OUTPUT, why,
                                sizeof why) == 0)
            lub_periodic_publish(ctx->periodic);
        else
            lub_periodic_failed(ctx->periodic, why);
    }
}

/* The diagnostic and exit code of a step that failed with lub_shear_step's code rc. */
static int ss_step_failed(ss_run_state *r, int rc, int64_t step, double strain_here, double ly,
                          double phi_here)
{
    lub_run_ctx *ctx = r->ctx;
    if (rc == LUB_SHEAR_NOMEM && !r->sys.fail_msg[0]) { /* the pair lists could not grow */
        char what[96];
        snprintf(what, sizeof what, "pair lists, step %lld, strain %.4f", (long long)step,
                 strain_here);
        lub_diagnostic_out_of_memory(ctx, what, r->n, (double)lub_shear_memory_bytes(&r->sys),
                                     "/n_particles");
    } else {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s (step %lld, strain %.4f)",
                 r->sys.fail_msg[0] ? r->sys.fail_msg : "simulation failure", (long long)step,
                 strain_here);
    }
    r->step_unstable = rc == LUB_SHEAR_NONFINITE || rc == LUB_SHEAR_RUNAWAY;
    r->servo_squeezed = rc == LUB_SHEAR_CELL_TOO_SMALL && r->p.pressure;
    if (r->servo_squeezed) { /* only the servo moves L_y */
        const size_t len = strlen(ctx->diagnostic);
        snprintf(ctx->diagnostic + len, sizeof ctx->diagnostic - len,
                 ": the pressure servo squeezed the cell (L_y %.3g a, phi %.3g); lower "
                 "/servo/gain (studied: 0.25-4; default 1), or raise /n_particles",
                 ly, phi_here);
    }
    return (rc == LUB_SHEAR_NOMEM) ? LUB_EXIT_INTERNAL : LUB_EXIT_NUMERICAL;
}

/* After step `step`: the step the pairs' summed stiffness asks for (when it changed, the
 * schedule and the Delaunay update period follow it; the series' room already covers it). */
static int ss_follow_step_control(ss_run_state *r, int64_t step)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_ss_params *p = &r->p;
    ss_loop *lp = &r->lp;
    if (!lub_shear_step_control(&r->sys, &lp->ctl))
        return LUB_EXIT_OK;
    r->dt = lp->ctl.dt;
    r->sys.dt = r->dt;
    lub_schedule_set_dt(&lp->sched, step + 1, r->sys.time, r->dt);
    if ((double)lp->sched.nsteps > LUB_MAX_STEPS) { /* step-count rule (step_count.h) */
        lub_step_count_fell(ctx->diagnostic, sizeof ctx->diagnostic, r->dt, lp->strain,
                            p->dt_stiffness_safety, lp->ctl.changes, (double)lp->sched.nsteps);
        return LUB_EXIT_NUMERICAL;
    }
    if (r->sys.topology_interval > 0)
        r->sys.topology_interval =
            (int)fmin(1e6, (double)lub_schedule_period(p->delaunay_strain / r->gd, r->dt));
    return LUB_EXIT_OK; /* the series' room covers any step (ss_setup_series) */
}

/* The sampled state of a step (taken by lub_shear_step with LUB_SAMPLE_STRESS) into the series
 * and a row of the time-series table. phi_here, ly, rate: phi, L_y and L_yy of the evaluated
 * configuration; time: its time. */
static int ss_record_sample(ss_run_state *r, int64_t step, const lub_shear_sample *smp,
                            double strain_here, double phi_here, double ly, double rate,
                            double time)
{
    lub_run_ctx *ctx = r->ctx;
    const double gd = r->gd, s0 = r->s0;
    /* bond order after the step: one pass over the pair list where it reaches every bond
     * (cut-off >= 0.4 a, skin not overspent), else over a list of its own (shear_system.h) */
    long bonds_here = 0;
    const double q6_here = lub_shear_bond_order_q6(&r->sys, SS_BOND_FACTOR, &bonds_here);
    r->lp.bonds_sum += (double)bonds_here;
    ++r->lp.bonds_samples;
    double tot[9];
    lub_stress_total(&smp->stress, tot);
    const double P = -tot[4];
    const double sxy = tot[1];
    const double vals[SS_OBS_COUNT] = {
        phi_here,
        P / s0,
        sxy / P,
        sxy / gd,
        gd / P,
        sxy / s0,
        -tot[0] / gd,
        -tot[4] / gd,
        -tot[8] / gd,
        tot[0] / tot[4],
        tot[8] / tot[4],
        2.0 * (double)smp->n_active / r->n,
        2.0 * (double)smp->n_contacts / r->n,
        smp->stress.part[LUB_SP_NC][1] / s0,
        smp->stress.part[LUB_SP_SC][1] / s0,
        smp->stress.part[LUB_SP_NL][1] / s0,
        smp->stress.part[LUB_SP_SL][1] / s0,
        smp->stress.part[LUB_SP_KIN][1] / s0,
        smp->stress.part[LUB_SP_NC][4] / s0,
        smp->stress.part[LUB_SP_SC][4] / s0,
        smp->stress.part[LUB_SP_NL][4] / s0,
        smp->stress.part[LUB_SP_SL][4] / s0,
        smp->stress.part[LUB_SP_KIN][4] / s0,
        smp->n_contacts ? (double)smp->n_crushed / (double)smp->n_contacts : 0.0,
        smp->n_contacts ? (double)smp->n_sliding / (double)smp->n_contacts : 0.0,
        q6_here};
    if (lub_ss_series_append(&r->ser, strain_here, vals)) { /* never: ss_setup_series */
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "internal error: the time series is full (%zu samples) at strain %.6g", r->ser.cap,
                 strain_here);
        return LUB_EXIT_INTERNAL;
    }
    double row[10 + 6 * 9 + 1];
    _Static_assert(sizeof row == LUB_SS_ROW_BYTES, "LUB_SS_ROW_BYTES: one row of the time series");
    row[0] = strain_here;
    row[1] = phi_here;
    row[2] = P / s0;
    row[3] = sxy / P;
    row[4] = sxy / gd;
    row[5] = gd / P;
    row[6] = vals[SS_OBS_Z];
    row[7] = vals[SS_OBS_ZC];
    row[8] = ly;
    row[9] = rate / gd;
    for (int k = 0; k < 9; ++k)
        row[10 + k] = tot[k] / s0;
    for (int part = 0; part < LUB_SP_N; ++part)
        for (int k = 0; k < 9; ++k)
            row[19 + 9 * part + k] = smp->stress.part[part][k] / s0;
    row[19 + 9 * LUB_SP_N] = q6_here;
    if (lub_h5_table_append(r->tab, step, time, row)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }
    if (!isfinite(P) || !isfinite(sxy)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "non-finite stress at step %lld (strain %.4f)", (long long)step, strain_here);
        r->step_unstable = 1;
        return LUB_EXIT_NUMERICAL;
    }
    return LUB_EXIT_OK;
}

/* A snapshot of the current state, and the network frame that goes with it. */
static int ss_snapshot_now(ss_run_state *r)
{
    /* the network first: its list completion may move positions by cell vectors
     * (pair_network.h), which the snapshot then shows */
    int rc;
    if (r->p.pair_network == LUB_NETWORK_SNAPSHOTS &&
        (rc = ss_network_frame(r->ctx, &r->sys, r->network, &r->net, 0)) != LUB_EXIT_OK)
        return rc;
    if (ss_snapshot(r->ctx, &r->sys))
        return LUB_EXIT_IO;
    r->lp.frames++;
    r->lp.last_snapshot_step = r->sys.step;
    r->lp.snap_owed_step = -1;
    return LUB_EXIT_OK;
}

/* 1 when a snapshot event met after `done` steps is taken there: not within half a spacing of
 * the end (nor at the end), whose snapshot follows the loop. */
static int ss_snapshot_before_end(const ss_run_state *r, int64_t done)
{
    const lub_schedule *sched = &r->lp.sched;
    return done < sched->nsteps && sched->t_end - r->sys.time > 0.5 * sched->ev[r->ev_snap].spacing;
}

/* A snapshot (and the network frame that goes with it) when one is due after step `step`:
 * not within half a spacing of the end, whose snapshot follows the loop (an adapted step
 * moves the events: the last could fall a step before the end). */
static int ss_snapshot_if_due(ss_run_state *r, int64_t step)
{
    ss_loop *lp = &r->lp;
    if (!(r->ev_snap >= 0 && lub_schedule_due(&lp->sched, r->ev_snap, step)))
        return LUB_EXIT_OK;
    if (!ss_snapshot_before_end(r, step + 1)) {
        lp->snap_owed_step = r->sys.step;
        return LUB_EXIT_OK;
    }
    return ss_snapshot_now(r);
}

/* The time loop, from the loop state's step to the end, a stop request, a failure or the
 * /target_rel_error stop; r->step is the steps done. */
static void ss_time_loop(ss_run_state *r)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_ss_params *p = &r->p;
    ss_loop *lp = &r->lp;
    lub_shear_system *sys = &r->sys;
    /* A continuation of a run whose last step was a /target_rel_error check (next_check is
     * set one strain past the strain of the check) repeats that check with its own
     * /target_rel_error and /target_min_strain, as a run asked for them from the start would
     * have made it at that step: a run stopped on its target and extended with the same target
     * and a longer /strain stops there, with no step more (until 2026-12-06 it went on to the
     * next check, one strain later). */
    if (ctx->resume_path && p->target_rel_error > 0 && lp->next_check == lp->strain + 1.0 &&
        lub_ss_target_reached(p, &r->ser, NULL, NULL))
        r->stopped_early = 1;
    /* An extension of a completed run whose last snapshot event fell near its end, and was
     * left to the end's snapshot (written after its checkpoint, so not copied): a run asked
     * for the longer /strain from the start takes that event's snapshot (until 2026-12-07 the
     * extension had none there). */
    if (ctx->resume_path && lp->snap_owed_step == sys->step && r->ev_snap >= 0 &&
        ss_snapshot_before_end(r, lp->step) && (r->exit_code = ss_snapshot_now(r)) != LUB_EXIT_OK) {
        r->step = lp->step;
        return;
    }
    int64_t step;
    for (step = lp->step; step < lp->sched.nsteps && !r->stopped_early; ++step) {
        if (ctx->periodic && lub_periodic_due(ctx->periodic, step))
            ss_periodic_checkpoint(r, step);
        if (ctx->stop_requested && *ctx->stop_requested) {
            r->exit_code = LUB_EXIT_INTERRUPTED;
            r->stopped_by_request = 1;
            break;
        }
        const int sample = lub_schedule_due(&lp->sched, r->ev_sample, step);
        const double strain_here = lp->strain; /* strain of the evaluated configuration */
        const int pdf_due = lub_schedule_due(&lp->sched, r->ev_pdf, step);
        /* from /microstructure/start_strain, to half a step: the strain summed step by step
         * is the start's to round-off only (Iv 0.1, dt 0.002: 0.04999999999999981 at the
         * step of 0.05, whose snapshot was skipped until 2026-12-07) */
        const int pdf = p->pdf_on && strain_here >= p->pdf_start - 0.5 * r->gd * r->dt && pdf_due;
        unsigned flags = (sample ? LUB_SAMPLE_STRESS : 0u) | (p->pressure ? LUB_SAMPLE_SYY : 0u) |
                         (pdf ? LUB_SAMPLE_PDF : 0u);
        lub_shear_sample smp;
        const double phi_here = lub_shear_phi(sys);
        const double ly = sys->cell.h[1][1];
        const double rate = sys->cell.L[1][1];
        const int rc = lub_shear_step(sys, flags, &smp);
        if (rc) {
            r->exit_code = ss_step_failed(r, rc, step, strain_here, ly, phi_here);
            break;
        }
        if (pdf) { /* the averaging window (/profiles/pdf_strain_range) */
            if (sys->pdf.snapshots == 1)
                sys->pdf.strain_first = strain_here;
            sys->pdf.strain_last = strain_here;
        }
        lp->strain += r->gd * r->dt;
        if (p->pressure) {
            if (step == 0)
                lp->p_f = -smp.syy;
            servo_step(sys, -smp.syy, &lp->p_f, r->dt, r->gd, p);
        }
        const double dt_of_step = r->dt; /* the step just taken (time of its sample row) */
        if ((r->exit_code = ss_follow_step_control(r, step)) != LUB_EXIT_OK)
            break;
        if (sample) {
            r->exit_code = ss_record_sample(r, step, &smp, strain_here, phi_here, ly, rate,
                                            sys->time - dt_of_step);
            if (r->exit_code != LUB_EXIT_OK)
                break;
            /* "run until the headline is known to target_rel_error": a check every strain,
             * whose strains a run without a target keeps too (its extension with a target
             * then checks where the run asked for it from the start does); the stop comes
             * after the step's snapshot (the loop's condition) */
            if (lp->strain >= lp->next_check) {
                lp->next_check = lp->strain + 1.0;
                if (p->target_rel_error > 0 && lub_ss_target_reached(p, &r->ser, NULL, NULL))
                    r->stopped_early = 1;
            }
        }
        if ((r->exit_code = ss_snapshot_if_due(r, step)) != LUB_EXIT_OK)
            break;
        lub_progress_update(ctx->progress, (double)(step + 1) / (double)lp->sched.nsteps, step + 1);
    }
    lub_progress_last_step(ctx->progress, step);
    r->step = step;
}

/* A stop between two steps (or the end, with --keep-checkpoint): the state before step
 * r->step into the checkpoint, with the rows and snapshots written so far (before the last
 * snapshot, which ss_final_frames writes). */
static void ss_final_checkpoint(ss_run_state *r)
{
    lub_run_ctx *ctx = r->ctx;
    if (!(ctx->checkpoint_path &&
          (r->stopped_by_request || (ctx->checkpoint_always && r->exit_code == LUB_EXIT_OK))))
        return;
    r->lp.step = r->step;
    const int64_t frames_in_file = r->lp.frames - lub_h5_snapshots_skipped(ctx->out, NULL, NULL, 0);
    const int64_t network_in_file = lub_h5_frames_written(r->network, NULL);
    ctx->checkpoint_written =
        ss_checkpoint_write(ctx->checkpoint_path, r->resolved, &r->lp, &r->ser, frames_in_file,
                            network_in_file, &r->sys, "result.h5", ctx->checkpoint_failure,
                            sizeof ctx->checkpoint_failure) == 0;
}

/* A numerical failure's advice: the step's where the step is the likely cause (not for a cell
 * squeezed below the listing distance, unless /dt was fixed above the bound); the servo's
 * instead where it moves L_y by 0.1 LUB_SS_SERVO_STEP_MAX of itself or more in one step,
 * unless the squeezed cell's diagnostic already names the servo. */
static void ss_failure_advice(ss_run_state *r)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_ss_params *p = &r->p;
    if (r->exit_code != LUB_EXIT_NUMERICAL)
        return;
    const double servo_jump = p->pressure ? p->servo_gain * r->gd * r->dt : 0.0;
    if (servo_jump >= 0.1 * LUB_SS_SERVO_STEP_MAX && !r->servo_squeezed) {
        const size_t len = strlen(ctx->diagnostic);
        snprintf(ctx->diagnostic + len, sizeof ctx->diagnostic - len,
                 ": the pressure servo changes L_y by up to %.3g of itself in one step "
                 "(/servo/gain times the shear rate times the step); lower /servo/gain (studied: "
                 "0.25-4; default 1)",
                 servo_jump);
    } else if (r->dt_adapts && r->step_unstable) {
        lub_diagnostic_adapted_dt_hint(ctx, r->dt, p->dt_safety, r->dt_el, "dt_elastic",
                                       r->lp.ctl.changes, p->dt_stiffness_safety,
                                       r->lp.ctl.ratio_max);
    } else if (r->step_unstable || p->dt > r->dt_el) {
        lub_diagnostic_dt_hint(ctx, p->dt, p->dt_safety, r->dt_el, "dt_elastic");
    }
}

/* The interaction network of the final state (unless a snapshot's frame already shows it),
 * before the last snapshot, which then shows the positions and box its branch vectors and
 * images refer to; then the final state's snapshot, unless the loop's last snapshot shows it
 * (a stop just after it). */
static void ss_final_frames(ss_run_state *r)
{
    int64_t network_last_step = -1;
    lub_h5_frames_written(r->network, &network_last_step);
    if (r->network && network_last_step != r->sys.step &&
        (r->exit_code == LUB_EXIT_OK || r->exit_code == LUB_EXIT_INTERRUPTED)) {
        const int rc = ss_network_frame(r->ctx, &r->sys, r->network, &r->net, 1);
        if (rc != LUB_EXIT_OK)
            r->exit_code = rc;
    }
    if (r->p.snapshots > 0 && r->exit_code != LUB_EXIT_IO &&
        r->lp.last_snapshot_step != r->sys.step)
        ss_snapshot(r->ctx, &r->sys);
}

/* The §2 law's values (physics-reference §2) of the run's headline observables, NaN where it
 * has none (friction below its range, mu_m < 0.36); mu_m: the contacts' friction coefficient as
 * the seed's laws read it (law.terms.friction off is mu_m = 0). */
static void ss_law_values(const lub_ss_params *p, double mu_m, double phi_m,
                          double ref_of[SS_OBS_COUNT])
{
    for (int k = 0; k < SS_OBS_COUNT; ++k)
        ref_of[k] = NAN;
    if (mu_m < 0.36)
        return;
    if (p->pressure) {
        ref_of[SS_OBS_MU] = lub_dem_mu(p->Iv, phi_m);
        ref_of[SS_OBS_PHI] = phi_m / (1.0 + sqrt(p->Iv));
    } else if (p->phi < phi_m) { /* none at and above phi_m */
        ref_of[SS_OBS_ETA] = lub_dem_eta_r(p->phi, phi_m);
    }
    for (int k = 0; k < SS_OBS_COUNT; ++k)
        if (!isfinite(ref_of[k]))
            ref_of[k] = NAN;
}

/* The steady-state means and errors of every observable into the summary's results, with the
 * law's value (ref_of) where it has a finite one. */
static void ss_put_results(ss_run_state *r, const lub_ss_steady_stats *st,
                           const double ref_of[SS_OBS_COUNT])
{
    lub_run_ctx *ctx = r->ctx;
    const char *su = r->p.pressure ? "P" : "eta*gd";
    lub_summary_put(ctx, "steady_drift_z", st->worst_drift_z, NAN, "1");
    for (int k = 0; k < SS_OBS_COUNT; ++k) {
        const char *unit = "1";
        if (k == SS_OBS_P || k == SS_OBS_SXY || (k >= SS_OBS_XY_NC && k <= SS_OBS_YY_KIN))
            unit = su;
        if (isfinite(ref_of[k])) {
            lub_summary_put_ref(ctx, lub_ss_obs_names[k], st->mean[k], unit, ref_of[k]);
            json_t *e = json_object_get(ctx->summary_results, lub_ss_obs_names[k]);
            if (e && isfinite(st->sem[k]))
                json_object_set_new(e, "stderr", json_real(st->sem[k]));
        } else {
            lub_summary_put(ctx, lub_ss_obs_names[k], st->mean[k], st->sem[k], unit);
        }
        /* a ratio's own window (simple_shear_series.h): its first strain and its sample count,
         * so that the value can be recomputed from result.h5 */
        json_t *e = json_object_get(ctx->summary_results, lub_ss_obs_names[k]);
        if (e && lub_ss_obs_is_ratio(k)) {
            const size_t from = st->from[k];
            const double x = from < r->ser.n ? r->ser.strain[from] : NAN;
            json_object_set_new(e, "from_strain", isfinite(x) ? json_real(x) : json_null());
            json_object_set_new(e, "samples", json_integer((json_int_t)(r->ser.n - from)));
        }
    }
}

/* The run's counters: its steady window, strain, steps and their changes, the neighbour
 * search's work, and whether it is steady or stopped on its target. */
static void ss_put_counters(ss_run_state *r, const lub_ss_steady_stats *st)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_ss_params *p = &r->p;
    const ss_loop *lp = &r->lp;
    const lub_shear_system *sys = &r->sys;
    const lub_ss_series *ser = &r->ser;
    const size_t start = st->start;
    const char *tu = p->pressure ? "eta/P" : "1/gd";
    lub_summary_put(ctx, "steady_from_strain", start < ser->n ? ser->strain[start] : NAN, NAN, "1");
    lub_summary_put(ctx, "steady_samples", (double)(ser->n - start), NAN, "1");
    lub_summary_put(ctx, "strain_reached", lp->strain, NAN, "1");
    lub_summary_put(ctx, "dt", r->dt, NAN, tu);
    lub_summary_put(ctx, "dt_elastic", r->dt_el, NAN, tu);
    lub_summary_put(ctx, "dt_min", lp->ctl.dt_min, NAN, tu);
    lub_summary_put(ctx, "dt_changes", (double)lp->ctl.changes, NAN, "1");
    lub_summary_put(ctx, "dt_stiffness_ratio", lp->ctl.ratio_max, NAN, "1");
    lub_summary_put(ctx, "neighbor_rebuilds", (double)sys->rebuilds, NAN, "1");
    lub_summary_put(ctx, "cell_flips", (double)sys->flips, NAN, "1");
    lub_summary_put(ctx, "lost_pairs", (double)sys->lost_pairs, NAN, "1");
    lub_summary_put(ctx, "packing_min_gap", lp->packing_min_gap, NAN, "a");
    lub_summary_put(ctx, "packing_min_gap_aij", lp->packing_min_gap_aij, NAN, "a_ij");
    lub_summary_put(ctx, "initial_contacts",
                    lp->packing_contacts < 0 ? NAN : (double)lp->packing_contacts, NAN, "1");
    const int steady_detected = st->steady && start < ser->n;
    json_object_set_new(ctx->summary_extra, "steady_state_detected", json_boolean(steady_detected));
    json_object_set_new(ctx->summary_extra, "stopped_on_target_error",
                        json_boolean(r->stopped_early));
}

/* The rms of series k about its mean over samples [start, n), over that mean (NaN without
 * samples or with a zero mean). */
static double ss_relative_rms(const lub_ss_series *ser, int k, size_t start)
{
    if (start >= ser->n)
        return NAN;
    const size_t m = ser->n - start;
    const double mean = lub_stats_mean(ser->v[k] + start, m);
    double sum = 0.0;
    for (size_t i = start; i < ser->n; ++i)
        sum += (ser->v[k][i] - mean) * (ser->v[k][i] - mean);
    return mean != 0.0 ? sqrt(sum / (double)m) / fabs(mean) : NAN;
}

/* A number of the summary's, null where it is not finite (JSON has no NaN). */
static json_t *ss_json_number(double x) { return isfinite(x) ? json_real(x) : json_null(); }

/* The record of the /target_rel_error check over the summary's series (the one the stop
 * tested when the run stopped on it): the headline's relative error, the one-sided 90 % upper
 * confidence bound of it that the stop compares with the target, and what the bound is made
 * of (lub_ss_target_reached, stats.h lub_stats_sem_upper_factor). */
static void ss_put_target_bound(lub_run_ctx *ctx, const lub_ss_target_check *t)
{
    json_t *o = json_object();
    json_object_set_new(o, "confidence", json_real(0.9));
    json_object_set_new(o, "relative_error", ss_json_number(t->rel_error));
    json_object_set_new(o, "relative_error_bound", ss_json_number(t->rel_bound));
    json_object_set_new(o, "batch_means", json_integer((json_int_t)t->batches));
    json_object_set_new(o, "lag1", ss_json_number(t->lag1));
    json_object_set_new(o, "dof", ss_json_number(t->dof));
    json_object_set_new(ctx->summary_extra, "target_error_bound", o);
}

/* The advisory checks (shear_run_checks.h: rigid limit, inertia, crushed asperities, ordering,
 * lost pairs, steady state, the law's tolerance, the target error) as the summary's warnings,
 * with the run's own (network frames skipped, no microstructure sampled, a zero headline), and
 * the elastic number. */
static void ss_put_warnings(ss_run_state *r, const lub_ss_steady_stats *st,
                            const double ref_of[SS_OBS_COUNT], double mu_m, double phi_m)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_ss_params *p = &r->p;
    const ss_loop *lp = &r->lp;
    const lub_shear_system *sys = &r->sys;
    const size_t start = st->start;
    const int steady_detected = st->steady && start < r->ser.n;
    /* SS_OBS_P is the pressure in units of s0 */
    const double *mean_of = st->mean, *sem_of = st->sem;
    /* the target's zero-mean verdict on the series the summary reports, not only as the last
     * check in this process saw it: a continuation that makes no check of its own said nothing
     * where the run it continues would have warned (until 2026-12-07) */
    const int failed = r->exit_code != LUB_EXIT_OK && !r->stopped_by_request;
    int target_zero_mean = 0; /* a failed run's diagnostic is its message */
    lub_ss_target_check target = {NAN, NAN, 0, NAN, NAN};
    if (p->target_rel_error > 0.0 && r->ser.n > 0) {
        int zero_mean = 0;
        (void)lub_ss_target_reached(p, &r->ser, &zero_mean, &target);
        if (!r->stopped_early && !failed)
            target_zero_mean = zero_mean;
        ss_put_target_bound(ctx, &target);
    }
    const lub_shear_run_state checks = {
        .elastic_number = p->stiffness / mean_of[SS_OBS_P],
        .kinetic_share = fabs(mean_of[SS_OBS_XY_KIN]) / fabs(mean_of[SS_OBS_SXY]),
        .kinetic_share_pressure = fabs(mean_of[SS_OBS_YY_KIN]) / fabs(mean_of[SS_OBS_P]),
        .crushed_fraction = mean_of[SS_OBS_CRUSHED],
        .bond_order_q6 = mean_of[SS_OBS_Q6],
        .bond_order_random =
            lp->bonds_sum > 0.0 ? sqrt((double)lp->bonds_samples / lp->bonds_sum) : NAN,
        .lost_pairs = (double)sys->lost_pairs,
        .steady = steady_detected,
        .steady_samples = (double)(r->ser.n - start),
        .strain_reached = lp->strain,
        .stopped = r->stopped_by_request,
        .failed = failed,
        .strain_target = p->strain,
        .checkpoint_kept = lub_run_resumable(ctx),
        .transient_strain = p->transient_strain,
        .sample_strain = p->sample_strain,
        .dt_over_elastic = p->dt > 0.0 ? p->dt / r->dt_el : 0.0,
        .dt_over_stiffness = p->dt > 0.0 ? lp->ctl.ratio_max : 0.0,
        .phi_imposed = p->pressure ? NAN : p->phi,
        .phi_jamming = phi_m,
        .mu_m = mu_m,
        .pressure_ratio = p->pressure ? mean_of[SS_OBS_P] : NAN, /* in units of s0 = P */
        .pressure_ratio_sem = p->pressure ? sem_of[SS_OBS_P] : NAN,
        .pressure_rms_ratio = p->pressure ? ss_relative_rms(&r->ser, SS_OBS_P, start) : NAN,
        .headline = p->pressure ? mean_of[SS_OBS_MU] : mean_of[SS_OBS_ETA],
        .headline_law = p->pressure ? ref_of[SS_OBS_MU] : ref_of[SS_OBS_ETA],
        .headline_is_mu = p->pressure,
        .phi_mean = p->pressure ? mean_of[SS_OBS_PHI] : NAN,
        .phi_law = p->pressure ? ref_of[SS_OBS_PHI] : NAN,
        .article_set = p->delaunay && !(p->law.params.terms & (LUB_TERM_ROLL | LUB_TERM_TWIST)),
        .headline_sem = p->pressure ? sem_of[SS_OBS_MU] : sem_of[SS_OBS_ETA],
        .target_rel_error = p->target_rel_error,
        .headline_rel_bound = target.rel_bound,
        .stopped_on_target = r->stopped_early,
        .target_zero_mean = target_zero_mean,
        .pdf_first_strain = p->pdf_on && sys->pdf.snapshots > 0 ? sys->pdf.strain_first : NAN,
        .steady_from_strain = steady_detected ? r->ser.strain[start] : NAN,
    };
    char warning_text[LUB_SHEAR_WARNINGS_MAX][LUB_SHEAR_WARNING_LEN];
    const int n_warnings = lub_shear_run_warnings(&checks, warning_text);
    json_t *warnings = json_array();
    for (int w = 0; w < n_warnings; ++w)
        json_array_append_new(warnings, json_string(warning_text[w]));
    lub_network_warn_skipped(r->network, warnings);
    if (p->pdf_on && sys->pdf.snapshots == 0) { /* no /profiles would be written */
        char text[400];
        if (lp->strain < p->pdf_start)
            snprintf(text, sizeof text,
                     "no microstructure was sampled and result.h5 has no /profiles: the run "
                     "ended at strain %.3g, before /microstructure/start_strain %.3g; lower "
                     "/microstructure/start_strain (or raise /strain)",
                     lp->strain, p->pdf_start);
        else
            snprintf(text, sizeof text,
                     "no microstructure was sampled and result.h5 has no /profiles: no "
                     "sample fell between /microstructure/start_strain %.3g and the end at "
                     "strain %.3g; lower /microstructure/interval_strain %.3g",
                     p->pdf_start, lp->strain, p->pdf_interval);
        json_array_append_new(warnings, json_string(text));
    }
    if (target_zero_mean) {
        char text[400];
        snprintf(text, sizeof text,
                 "%s averaged exactly 0 over the steady window, whose relative error is "
                 "undefined: the run did not stop on /target_rel_error; unset "
                 "/target_rel_error (or make the particles interact: raise "
                 "/phi or /cutoff)",
                 p->pressure ? "mu" : "eta_r");
        json_array_append_new(warnings, json_string(text));
    }
    json_object_set_new(ctx->summary_extra, "warnings", warnings);
    lub_summary_put(ctx, "elastic_number", checks.elastic_number, NAN, "1");
}

/* What ran: the active terms, the lubricated pairs (and the Delaunay updates), the steps, the
 * simulated time and the units. */
static void ss_put_description(ss_run_state *r)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_ss_params *p = &r->p;
    const lub_shear_system *sys = &r->sys;
    json_t *terms = json_array();
    lub_law_terms_append(terms, p->law.params.terms);
    if (p->drag_viscosity > 0.0)
        json_array_append_new(terms, json_string("affine_drag"));
    json_object_set_new(ctx->summary_extra, "active_terms", terms);
    json_object_set_new(ctx->summary_extra, "lubrication_pairs",
                        json_string(p->delaunay ? "delaunay" : "cutoff"));
    if (p->delaunay) {
        const lub_topology *tp = &sys->topo;
        lub_summary_put(ctx, "delaunay_updates", (double)tp->updates, NAN, "1");
        lub_summary_put(ctx, "delaunay_allowed_fraction",
                        tp->inside ? (double)tp->allowed / (double)tp->inside : NAN, NAN, "1");
        lub_summary_put(ctx, "delaunay_open_fraction",
                        tp->allowed ? (double)tp->open / (double)tp->allowed : NAN, NAN, "1");
    }
    json_object_set_new(ctx->summary_extra, "steps", json_integer(r->step));
    json_object_set_new(ctx->summary_extra, "simulated_time", json_real(sys->time));
    json_object_set_new(ctx->summary_extra, "units",
                        json_pack("{s:s, s:s, s:s, s:s, s:s}", "length", "a (mean particle radius)",
                                  "viscosity", "eta (fluid)", "stress",
                                  p->pressure ? "P (imposed particle pressure)" : "eta*gd", "time",
                                  p->pressure ? "eta/P (shear rate gd = Iv)" : "1/gd", "density",
                                  "rho = St*eta/(gd*a^2)"));
}

/* The summary (ss_put_*; also for partial and failed runs). */
static void ss_write_summary(ss_run_state *r)
{
    lub_ss_steady_stats st;
    lub_ss_series_statistics(&r->p, r->gd, r->s0, &r->ser, &st);
    const double mu_m = (r->p.law.params.terms & LUB_TERM_FRICTION) ? r->p.law.params.mu : 0.0;
    const double phi_m = lub_dem_phi_m(mu_m);
    double ref_of[SS_OBS_COUNT];
    ss_law_values(&r->p, mu_m, phi_m, ref_of);
    ss_put_results(r, &st, ref_of);
    ss_put_counters(r, &st);
    ss_put_warnings(r, &st, ref_of, mu_m, phi_m);
    ss_put_description(r);
}

/* The microstructure distributions (microstructure.h) into result.h5's /profiles, when any
 * was sampled: [n_theta][n_phi] maps; vectors and tensors as [n_theta * n_phi][3 or 9] rows
 * (bin index = i_theta * n_phi + i_phi); the bin edges (with the angle convention as their
 * "convention" attribute), the pair counts, the snapshot count and the strains of the first
 * and last snapshot. */
static void ss_write_profiles(ss_run_state *r)
{
    lub_run_ctx *ctx = r->ctx;
    const lub_ss_params *p = &r->p;
    lub_shear_system *sys = &r->sys;
    if (!(p->pdf_on && sys->pdf.snapshots > 0))
        return;
    lub_pdf_finish(&sys->pdf);
    const int nt = (int)p->pdf_nt, np = (int)p->pdf_np;
    size_t nb = (size_t)nt * (size_t)np;
    int64_t dims[2] = {nt, np};
    int64_t dims3[2] = {(int64_t)nb, 3};
    int64_t dims9[2] = {(int64_t)nb, 9};
    const char *vu = p->pressure ? "a*P/eta" : "a*gd";
    int io = lub_h5_write_array(ctx->out, "pdf_interaction_density", 2, dims, sys->pdf.density,
                                "1/sr") ||
             lub_h5_write_array(ctx->out, "pdf_contact_density", 2, dims, sys->pdf.contact_density,
                                "1/sr") ||
             lub_h5_write_array(ctx->out, "pdf_pair_count", 2, dims, sys->pdf.count, "1") ||
             /* u_n/a_ij: dimensionless (its unit said "a" until 2026-12-07) */
             lub_h5_write_array(ctx->out, "pdf_mean_gap", 2, dims, sys->pdf.gap_sum, "1") ||
             lub_h5_write_array(ctx->out, "pdf_mean_relative_velocity", 2, dims3, sys->pdf.vel_sum,
                                vu) ||
             lub_h5_write_array(ctx->out, "pdf_mean_centre_relative_velocity", 2, dims3,
                                sys->pdf.vel_com_sum, vu);
    const char *pn[4] = {"pdf_stress_normal_contact", "pdf_stress_tangential_contact",
                         "pdf_stress_normal_lubrication", "pdf_stress_tangential_lubrication"};
    for (int k = 0; k < 4 && !io; ++k)
        io = lub_h5_write_array(ctx->out, pn[k], 2, dims9, sys->pdf.stress + k * nb * 9,
                                p->pressure ? "P/sr" : "eta*gd/sr");
    /* the bin edges, theta_i = i pi/n_theta and phi_i = i pi/n_phi (360 bins at most) */
    const double pi = 3.14159265358979323846;
    double edges[361];
    const char *convention =
        "pair normal n from i to j; theta = arccos(n_y) (gradient y at theta = 0), phi = "
        "atan2(n_x, n_z) (vorticity z at phi = 0, flow x at phi = pi/2); a pair with phi < 0 "
        "is counted as -n (theta -> pi - theta, phi -> phi + pi, its velocities' sign "
        "flipped); bin = i_theta * n_phi + i_phi, solid angle (cos theta_i - cos theta_i+1) "
        "(phi_i+1 - phi_i)";
    for (int k = 0; k <= nt; ++k)
        edges[k] = k * pi / nt;
    int64_t de = nt + 1;
    io = io || lub_h5_write_array(ctx->out, "pdf_theta_edges", 1, &de, edges, "rad") ||
         lub_h5_profile_note(ctx->out, "pdf_theta_edges", "convention", convention);
    for (int k = 0; k <= np; ++k)
        edges[k] = k * pi / np;
    de = np + 1;
    io = io || lub_h5_write_array(ctx->out, "pdf_phi_edges", 1, &de, edges, "rad") ||
         lub_h5_profile_note(ctx->out, "pdf_phi_edges", "convention", convention);
    const double snaps = (double)sys->pdf.snapshots;
    const double range[2] = {sys->pdf.strain_first, sys->pdf.strain_last};
    const int64_t one = 1, two = 2;
    io = io || lub_h5_write_array(ctx->out, "pdf_snapshots", 1, &one, &snaps, "1") ||
         lub_h5_write_array(ctx->out, "pdf_strain_range", 1, &two, range, "1");
    if (io && r->exit_code == LUB_EXIT_OK) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        r->exit_code = LUB_EXIT_IO;
    }
    lub_summary_put(ctx, "pdf_snapshots", (double)sys->pdf.snapshots, NAN, "1");
    lub_summary_put(ctx, "pdf_first_strain", sys->pdf.strain_first, NAN, "1");
    lub_summary_put(ctx, "pdf_last_strain", sys->pdf.strain_last, NAN, "1");
}

static int ss_run(const json_t *resolved, lub_run_ctx *ctx)
{
    ss_run_state *r = calloc(1, sizeof *r);
    if (!r) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory (run state)");
        return LUB_EXIT_INTERNAL;
    }
    r->resolved = resolved;
    r->ctx = ctx;
    lub_error err;
    memset(&err, 0, sizeof err);
    if (lub_ss_read_resolved(resolved, &r->p, &err)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s: %s", err.pointer, err.message);
        free(r);
        return LUB_EXIT_INTERNAL;
    }
    r->n = (int)r->p.n;
    r->gd = r->p.pressure ? r->p.Iv : 1.0; /* shear rate in the scene units */
    r->s0 = r->p.pressure ? 1.0 : r->gd;   /* stress unit: P or eta gd (eta = 1) */
    lub_law_spec_scale(&r->p.law, 1.0, r->p.stiffness * r->s0);

    r->exit_code = ss_setup_system(r);
    if (r->exit_code == LUB_EXIT_OK)
        r->exit_code = ss_setup_series(r);
    if (r->exit_code == LUB_EXIT_OK)
        r->exit_code = ss_open_outputs(r);
    if (r->exit_code == LUB_EXIT_OK) {
        ss_time_loop(r);
        ss_final_checkpoint(r);
        ss_failure_advice(r);
        ss_final_frames(r);
        ss_write_summary(r);
        ss_write_profiles(r);
    }
    const int exit_code = r->exit_code;
    ctx->threads_used = r->sys.team_min; /* the smallest team the steps got (0: no step) */
    if (r->resume)
        lub_ckpt_close(r->resume, NULL, 0);
    lub_ss_series_free(&r->ser);
    free(r->radius);
    lub_shear_free(&r->sys);
    lub_pair_network_free(&r->net);
    free(r);
    return exit_code;
}

/* The system after its first rebuild, or its second when the run certainly shears far enough
 * (lub_shear_min_bytes, lub_shear_rebuild_strain): /strain, or with /target_rel_error at
 * least /transient_strain + /target_min_strain, before which it cannot stop early. The time
 * series (LUB_SS_SAMPLE_BYTES per sample, up to 348 MB: 1.5e6 samples, ss_setup_series) is
 * left out: its sample count depends on the time step, which may exceed /sample_strain. */
static int ss_memory_need(const json_t *resolved, int threads, lub_memory_need *need)
{
    lub_ss_params p;
    lub_error err;
    if (lub_ss_read_resolved(resolved, &p, &err))
        return -1;
    const double n = (double)p.n;
    const double sheared = p.target_rel_error > 0.0
                               ? fmin(p.strain, p.transient_strain + p.target_min_strain)
                               : p.strain;
    const double listed =
        lub_shear_list_range(p.cutoff, p.radius_std, p.delaunay); /* the list's range */
    const int rebuilt = sheared > 1.01 * lub_shear_rebuild_strain(listed, p.skin);
    need->bytes = lub_shear_min_bytes(n, p.phi, p.radius_std, listed, p.skin, threads, rebuilt);
    if (p.pair_network != LUB_NETWORK_NONE) /* the pairs inside the cut-off, and a quarter more */
        need->bytes += 1.25 * 0.9 * n *
                       lub_shear_listed_pairs_estimate(p.phi, p.radius_std, p.cutoff, 0.0) *
                       LUB_PAIR_NETWORK_PAIR_BYTES;
    /* the microstructure's sums: the run's and one per thread (lub_shear_init; 102 MB at 360 x
     * 360 bins and 2 threads, uncounted until 2026-12-07) */
    const double pdf_bytes =
        p.pdf_on ? (threads + 1.0) * lub_pdf_bytes((int)p.pdf_nt, (int)p.pdf_np) : 0.0;
    if (pdf_bytes > need->bytes) { /* the bins, not the particles, set the size */
        need->bytes += pdf_bytes;
        need->per_item = 0.0;
        need->member = "/microstructure/n_theta";
        snprintf(need->what, sizeof need->what,
                 "%lld particles with %lld x %lld microstructure bins on %d thread%s",
                 (long long)p.n, p.pdf_nt, p.pdf_np, threads, threads == 1 ? "" : "s");
        return 0;
    }
    need->bytes += pdf_bytes;
    need->per_item = need->bytes / n;
    need->member = "/n_particles";
    snprintf(need->what, sizeof need->what,
             "%lld particles at phi %.3g, cut-off %.3g a and skin %.3g a", (long long)p.n, p.phi,
             p.cutoff, p.skin);
    return 0;
}

/* the members that only decide when the run ends, or what it writes there: a continuation
 * may change them */
static const char *const ss_resume_may_differ[] = {"strain", "target_rel_error",
                                                   "target_min_strain", "pair_network", NULL};

const lub_scene lub_scene_simple_shear = {
    .name = "simple_shear",
    .title = "Periodic simple-shear rheometer (imposed volume or imposed particle pressure)",
    .description =
        "Tri-periodic simple shear (deforming cell with flips) of N polydisperse rough, "
        "frictional spheres with the lubricated contact law. Control 'volume' imposes phi and "
        "measures the pressure (units: a, eta, gd = 1); control 'pressure' imposes the particle "
        "pressure P = -sigma_yy through a servo on the gradient-direction cell size at the "
        "viscous number Iv = eta gd/P (units: a, eta, P = 1). Reports phi, P, mu = sigma_xy/P, "
        "eta_r, Iv, normal viscosities eta_ii, normal-stress ratios, coordination and contact "
        "numbers, the bond order Q6 (ordering indicator) and the stress split (normal/tangential "
        "contact/lubrication, kinetic) with "
        "steady-state detection (MSER) and AR(1)-corrected batch-means error bars.",
    .resolve = ss_resolve,
    .run = ss_run,
    .memory_need = ss_memory_need,
    .resumable = 1,
    .resume_may_differ = ss_resume_may_differ,
};

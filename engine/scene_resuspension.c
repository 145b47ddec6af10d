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
 * lambda_33 eta_22 with eq. 8) at that averaged phi for comparison.
 * y in all outputs is measured from the floor centre plane.
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
#include "resuspension_system.h"
#include "run_context.h"
#include "scene.h"
#include "scene_summary.h"
#include "shear_run_checks.h"
#include "state_checkpoint.h"
#include "stats.h"
#include "step_count.h"
#include "step_schedule.h"
#include "step_stiffness.h"

#define RS_PI 3.14159265358979323846

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

/* Everything allocated for a run (freed in one place). */
typedef struct {
    double *radius, *floor_r, *samples, *scratch, *series_h, *phi_inst, *vol;
    double *phi, *phi_err, *eta, *eta_err, *ybin, *keepd, *law, *pairs_out, *scratch2, *vx_vol,
        *vx_sum, *vx_inst, *phi_cg, *phi_cg_err;
    vec3 *pos, *floor_pos;
    int *keep;
    double *snap_x, *snap_v, *snap_w;
} rs_buffers;

static void rs_buffers_free(rs_buffers *b)
{
    double *d[] = {b->radius,  b->floor_r, b->samples,   b->scratch,  b->series_h, b->phi_inst,
                   b->vol,     b->phi,     b->phi_err,   b->eta,      b->eta_err,  b->ybin,
                   b->keepd,   b->law,     b->pairs_out, b->scratch2, b->vx_vol,   b->vx_sum,
                   b->vx_inst, b->snap_x,  b->snap_v,    b->snap_w,   b->phi_cg,   b->phi_cg_err};
    for (size_t i = 0; i < sizeof d / sizeof d[0]; ++i)
        free(d[i]);
    free(b->pos);
    free(b->floor_pos);
    free(b->keep);
    memset(b, 0, sizeof *b);
}

/* Grows the sample buffers so that the series holds `total` height samples and the average
 * `avg` profiles (the statistics' scratch max(total, avg) + 1); 0 or -1 (no memory: the buffers
 * keep their contents). Called when the step changes. */
static int rs_samples_reserve(rs_buffers *b, int nb, int64_t total, int64_t avg,
                              int64_t *nsamp_total, int64_t *nsamp_avg)
{
    if (total > *nsamp_total) {
        double *h = realloc(b->series_h, (size_t)total * sizeof *h);
        if (!h)
            return -1;
        b->series_h = h;
        *nsamp_total = total;
    }
    if (avg > *nsamp_avg) {
        double *sm = realloc(b->samples, (size_t)(avg * nb) * sizeof *sm);
        if (!sm)
            return -1;
        b->samples = sm;
        *nsamp_avg = avg;
    }
    const size_t scratch = (size_t)(*nsamp_avg > *nsamp_total ? *nsamp_avg : *nsamp_total) + 1;
    double *s1 = realloc(b->scratch, scratch * sizeof *s1);
    if (!s1)
        return -1;
    b->scratch = s1;
    double *s2 = realloc(b->scratch2, scratch * sizeof *s2);
    if (!s2)
        return -1;
    b->scratch2 = s2;
    return 0;
}

static int write_profiles(lub_h5 *h5, const char *name, int n, const double *data, const char *unit)
{
    int64_t dims[1] = {n};
    return lub_h5_write_array(h5, name, 1, dims, data, unit);
}

/* The time loop's state besides the system and the sample buffers: what a checkpoint holds
 * with them, so that a stopped run continues as if it had not stopped. */
typedef struct {
    int64_t step;           /* loop index to continue at (its sample is taken) */
    int64_t avg_start_step; /* first step averaged into the profiles */
    int64_t nh, navg;       /* height samples (= time-series rows) and averaged profiles */
    int64_t below_floor_max, frames_in_file;
    int64_t network_frames_in_file; /* /pair_network frames in the output file */
    double max_ke, min_lowest, contacts_sum, crushed_sum;
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
        lub_step_control_save(c, "run/step_control", &lp->ctl) ||
        lub_schedule_save(c, "run/schedule", &lp->sched) ||
        lub_ckpt_put(c, "series/height", LUB_CKPT_F64, (size_t)lp->nh, b->series_h) ||
        lub_ckpt_put(c, "profiles/samples", LUB_CKPT_F64, (size_t)(lp->navg * nb), b->samples) ||
        lub_ckpt_put(c, "profiles/vx_volume", LUB_CKPT_F64, (size_t)nb, b->vx_vol) ||
        lub_ckpt_put(c, "profiles/vx_sum", LUB_CKPT_F64, (size_t)nb, b->vx_sum) ||
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
    /* none in a checkpoint older than the frames */
    if (lub_ckpt_get_i64_or(c, "run/network_frames_in_file", 0, &lp->network_frames_in_file)) {
        snprintf(why, len, "%s", lub_ckpt_error(c));
        return -1;
    }
    return 0;
}

/* The samples of checkpoint c into b (room reserved). 0 or -1. */
static int rs_checkpoint_read_samples(lub_ckpt *c, const rs_loop *lp, rs_buffers *b, int nb)
{
    return lub_ckpt_get(c, "series/height", LUB_CKPT_F64, (size_t)lp->nh, b->series_h) ||
                   lub_ckpt_get(c, "profiles/samples", LUB_CKPT_F64, (size_t)(lp->navg * nb),
                                b->samples) ||
                   lub_ckpt_get(c, "profiles/vx_volume", LUB_CKPT_F64, (size_t)nb, b->vx_vol) ||
                   lub_ckpt_get(c, "profiles/vx_sum", LUB_CKPT_F64, (size_t)nb, b->vx_sum)
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

static int rs_run(const json_t *resolved, lub_run_ctx *ctx)
{
    lub_rs_spec p;
    lub_error err;
    json_t *spec = json_deep_copy(resolved);
    int rr = lub_rs_spec_read(spec, &p, &err);
    json_decref(spec);
    if (rr) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s: %s", err.pointer, err.message);
        return LUB_EXIT_INTERNAL;
    }
    /* units: a = eta = gd = 1 */
    const double a = 1.0, eta = 1.0, gd = 1.0;
    const double grav = a * gd * gd / (p.I * p.I);
    const double drho = eta * gd / (p.Sh * grav * a);
    const double rho = p.density_ratio * drho;
    const double St = rho * gd * a * a / eta;
    const int N = (int)p.n;

    rs_buffers B;
    memset(&B, 0, sizeof B);
    lub_rs_system S;
    memset(&S, 0, sizeof S);
    int rc = LUB_EXIT_OK;
    /* the failure is one the time step causes (non-finite, escape, runaway) */
    int step_unstable = 0;
    B.radius = malloc((size_t)N * sizeof *B.radius);
    B.pos = malloc((size_t)N * sizeof *B.pos);
    if (!B.radius || !B.pos) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory");
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    lub_bed_params bp = {.n = N,
                         .width = p.width,
                         .phi_target = p.initial_phi,
                         .radius_std = p.radius_std,
                         .seed = (uint64_t)p.seed};
    lub_bed_info binfo;
    int brc = lub_bed_build(&bp, B.radius, B.pos, &binfo);
    if (brc) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "initial bed failed (%s; packing code %d, %d per layer, phi %.4g)",
                 brc == -1 ? "out of memory" : "packing", binfo.info_code, binfo.per_layer,
                 binfo.layer_phi);
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    const double L = binfo.side;
    /* floor: square lattice fitted to the cell width */
    const int nside = lub_floor_side_count(L, p.floor_radius, 4);
    const double rf = L / (2.0 * nside);
    const int nfloor = nside * nside;
    double rmax = 0.0, rmin = INFINITY, vsum = 0.0, ylow = INFINITY;
    for (int i = 0; i < N; ++i) {
        rmax = fmax(rmax, B.radius[i]);
        rmin = fmin(rmin, B.radius[i]);
        vsum += 4.0 / 3.0 * RS_PI * pow(B.radius[i], 3.0);
        ylow = fmin(ylow, B.pos[i].y - B.radius[i]);
    }
    if (!(lub_floor_max_passing_radius(rf, p.floor_jitter) < rmin)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "fitted floor radius %.4g lets particles of radius %.4g through", rf, rmin);
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    const double y_floor = rf * (1.0 + p.floor_jitter) + 1.0;
    const double y_start = y_floor + rf * (1.0 + p.floor_jitter) + 0.05;
    double ytop = 0.0;
    for (int i = 0; i < N; ++i) {
        B.pos[i].y += y_start - ylow;
        ytop = fmax(ytop, B.pos[i].y + B.radius[i]);
    }
    const double h_init = ytop - y_floor;
    const double y_lid = y_floor + p.lid_height * h_init;
    const double d_list = 2.0 * rmax * (1.0 + 0.5 * p.cutoff) + p.skin;
    const double Ly = y_lid + d_list + 2.0 * rmax + 1.0;

    B.floor_r = malloc((size_t)nfloor * sizeof *B.floor_r);
    B.floor_pos = malloc((size_t)nfloor * sizeof *B.floor_pos);
    if (!B.floor_r || !B.floor_pos) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory");
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    for (int i = 0; i < nfloor; ++i)
        B.floor_r[i] = rf;
    lub_floor_build(nside, rf, y_floor, p.floor_jitter, (uint64_t)p.seed + 7919u, B.floor_pos);

    lub_law_spec_scale(&p.law, eta, p.stiffness * eta * gd * a);
    lub_rs_params sp = {.orientation = p.orientation,
                        .shear_rate = gd,
                        .gravity = grav,
                        .drho = drho,
                        .rho = rho,
                        .eta_shear = p.eta_shear * eta,
                        .eta_dilute = p.eta_dilute * eta,
                        .dilute_max_interactions = (int)p.dilute_max,
                        .y_floor = y_floor,
                        .y_lid = y_lid,
                        .cutoff = p.cutoff,
                        .skin = p.skin,
                        .dt = 1.0,
                        .threads = ctx->threads};
    /* time step: elastic bound on the lightest particle (normal and tangential), notes §7 */
    const double mmin = rho * 4.0 / 3.0 * RS_PI * rmin * rmin * rmin;
    double dt_crit = sqrt(mmin / p.law.params.k_bulk);
    if (p.law.params.k_t > 0.0)
        dt_crit = fmin(dt_crit, sqrt(0.4 * mmin / p.law.params.k_t));
    sp.dt = p.dt > 0.0 ? p.dt : p.dt_safety * dt_crit;
    int src = lub_rs_init(&S, &sp, &p.law.params, N, B.radius, B.pos, nfloor, B.floor_r,
                          B.floor_pos, L, Ly, L);
    if (src == LUB_RS_NOMEM) {
        lub_diagnostic_out_of_memory(ctx, "system", N, 0.0, "/n");
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    if (src) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "system init failed (%d)", src);
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    /* the step: fixed (/dt), or /dt_safety of the single-pair bound, lowered while the pairs'
     * summed stiffness needs it (/dt_stiffness_safety; step_stiffness.h, checked at every
     * neighbour-list rebuild) */
    const int dt_adapts = p.dt <= 0.0 && p.dt_stiffness_safety > 0.0;
    rs_loop lp; /* the loop's state: a fresh start, or the checkpoint's (resumed) */
    memset(&lp, 0, sizeof lp);
    lub_step_control_init(&lp.ctl, sp.dt, dt_adapts ? p.dt_stiffness_safety : 0.0);
    double dt = lp.ctl.dt;
    if (!ctx->resume_path && !lub_step_count_ok(lub_step_count(p.strain / gd, dt))) {
        /* the step-count rule (step_count.h) with this bed's lightest particle, which
         * validation could only bound: refused before the first step, exit 2 */
        const double r_eff =
            p.dt > 0.0 ? 1.0 : pow(dt_crit / lub_rs_elastic_dt(&p, 1.0), 2.0 / 3.0);
        lub_rs_step_refusal(&p, r_eff, lub_step_count(p.strain / gd, dt), dt, "", &err);
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s: %s", err.pointer, err.message);
        lub_rs_free(&S);
        rs_buffers_free(&B);
        return LUB_EXIT_BAD_SPEC;
    }
    const double area = lub_rs_area(&S);

    /* profile bins from the floor centre plane to the lid */
    const double dy = p.bin_width;
    const int nb = (int)ceil((y_lid - y_floor) / dy);
    lub_schedule_init(&lp.sched, dt, p.strain / gd);
    const int64_t sample_every = lub_schedule_period(p.sample_strain / gd, dt);
    const int ev_sample = lub_schedule_add(&lp.sched, sample_every, 0, p.sample_strain / gd);
    int64_t nsamp_total = lp.sched.nsteps / sample_every + 2;
    lp.avg_start_step = (int64_t)ceil(p.average_from / (gd * dt) - 1e-9);
    int64_t nsamp_avg = (lp.sched.nsteps - lp.avg_start_step) / sample_every + 2;
    char profiles_what[128];
    snprintf(profiles_what, sizeof profiles_what,
             "the profiles of %d bins over %lld samples from /average_from on", nb,
             (long long)nsamp_avg);
    if (!lub_memory_fits(ctx, (double)nsamp_avg * nb * sizeof *B.samples, profiles_what,
                         "/strain - /average_from (or raise /bin_width or /sample_strain)")) {
        lub_rs_free(&S);
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    B.samples = calloc((size_t)(nsamp_avg * nb), sizeof *B.samples);
    B.scratch =
        calloc((size_t)(nsamp_avg > nsamp_total ? nsamp_avg : nsamp_total) + 1, sizeof *B.scratch);
    B.scratch2 =
        calloc((size_t)(nsamp_avg > nsamp_total ? nsamp_avg : nsamp_total) + 1, sizeof *B.scratch2);
    B.series_h = calloc((size_t)nsamp_total, sizeof *B.series_h);
    B.phi_inst = calloc((size_t)nb, sizeof *B.phi_inst);
    B.vx_vol = calloc((size_t)nb, sizeof *B.vx_vol);
    B.vx_sum = calloc((size_t)nb, sizeof *B.vx_sum);
    B.vx_inst = calloc((size_t)nb, sizeof *B.vx_inst);
    B.vol = calloc((size_t)nb, sizeof *B.vol);
    B.phi = calloc((size_t)nb, sizeof *B.phi);
    B.phi_err = calloc((size_t)nb, sizeof *B.phi_err);
    B.eta = calloc((size_t)nb, sizeof *B.eta);
    B.eta_err = calloc((size_t)nb, sizeof *B.eta_err);
    B.ybin = calloc((size_t)nb, sizeof *B.ybin);
    B.keepd = calloc((size_t)nb, sizeof *B.keepd);
    B.law = calloc((size_t)nb, sizeof *B.law);
    B.pairs_out = calloc((size_t)nb * 4, sizeof *B.pairs_out);
    B.phi_cg = calloc((size_t)nb, sizeof *B.phi_cg);
    B.phi_cg_err = calloc((size_t)nb, sizeof *B.phi_cg_err);
    B.keep = calloc((size_t)nb, sizeof *B.keep);
    B.snap_x = calloc((size_t)N * 3, sizeof *B.snap_x);
    B.snap_v = calloc((size_t)N * 3, sizeof *B.snap_v);
    B.snap_w = calloc((size_t)N * 3, sizeof *B.snap_w);
    if (!B.samples || !B.scratch || !B.scratch2 || !B.vx_vol || !B.vx_sum || !B.vx_inst ||
        !B.series_h || !B.phi_inst || !B.vol || !B.phi || !B.phi_err || !B.eta || !B.eta_err ||
        !B.ybin || !B.keepd || !B.law || !B.pairs_out || !B.keep || !B.snap_x || !B.snap_v ||
        !B.snap_w || !B.phi_cg || !B.phi_cg_err) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "out of memory for the profiles (%d bins x %lld samples): raise /bin_width or "
                 "/sample_strain, or lower /strain - /average_from",
                 nb, (long long)nsamp_avg);
        lub_rs_free(&S);
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }

    const char *names[] = {"suspension_height", "center_of_mass_height", "mean_phi",
                           "kinetic_energy",    "max_fluctuation_speed", "dilute_particles"};
    const int ncomp[] = {1, 1, 1, 1, 1, 1};
    const char *units[] = {"a", "a", "1", "eta gd a^3", "a gd", "1"};
    lub_h5_table *tab = lub_h5_set_units(ctx->out, "1/gd", "a", "a gd", "gd") == 0
                            ? lub_h5_table_create(ctx->out, 6, names, ncomp, units)
                            : NULL;
    const char *bnd[3] = {"periodic", "none", "periodic"};
    int snap_ok = p.snapshots == 0 || lub_h5_particles_define(ctx->out, N, B.radius, bnd) == 0;
    /* /pair_network: its arrays (about 3 kB a particle at phi 0.5) are kept from frame to frame */
    lub_h5_frames *network = p.pair_network != LUB_NETWORK_NONE && tab && snap_ok
                                 ? lub_network_define(ctx->out, "eta*gd*a^2", "eta*gd*a^3", "1/gd")
                                 : NULL;
    lub_pair_network net = {0};
    int64_t network_last_step = -1;
    if (!tab || !snap_ok || (p.pair_network != LUB_NETWORK_NONE && !network)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        lub_rs_free(&S);
        rs_buffers_free(&B);
        return LUB_EXIT_IO;
    }
    if (network &&
        !lub_memory_fits(ctx, 1.25 * 20.0 * (double)S.n * (double)LUB_PAIR_NETWORK_PAIR_BYTES,
                         "the interaction network (/pair_network, 20 pairs a particle)",
                         "/pair_network")) {
        lub_rs_free(&S);
        rs_buffers_free(&B);
        return LUB_EXIT_INTERNAL;
    }
    const int64_t snap_every = p.snapshots > 1
                                   ? (lp.sched.nsteps + p.snapshots - 2) / (p.snapshots - 1)
                                   : lp.sched.nsteps + 1;
    const int ev_snap =
        p.snapshots > 0 ? lub_schedule_add(&lp.sched, snap_every, 0, (double)snap_every * dt) : -1;

    lp.min_lowest = INFINITY;
    lp.y_floor = y_floor;
    lp.y_lid = y_lid;
    int64_t first_step = 0, frames = 0; /* loop start; snapshots asked for */
    if (ctx->resume_path) {             /* the stopped run's state replaces the fresh one */
        char why[600] = "";
        rs_loop saved;
        memset(&saved, 0, sizeof saved);
        lub_ckpt *ck = lub_ckpt_open(ctx->resume_path, why, sizeof why);
        if (ck && rs_checkpoint_read_loop(ck, &saved, why, sizeof why) == 0) {
            if (saved.y_floor != y_floor || saved.y_lid != y_lid ||
                saved.sched.n_events != lp.sched.n_events) {
                snprintf(why, sizeof why,
                         "the bed or the events differ from the stopped run's (another build?)");
            } else if (lub_rs_restore(ck, &S)) {
                snprintf(why, sizeof why, "%s",
                         lub_ckpt_error(ck)[0] ? lub_ckpt_error(ck) : "inconsistent pairs");
            } else if (saved.sched.t_end != p.strain / gd &&
                       p.strain < S.time * gd * (1.0 - 1e-12)) {
                /* a continuation may ask for another /strain (resume_may_differ), not for less
                 * than the stopped run has done */
                snprintf(why, sizeof why,
                         "/strain: %g here, but the stopped run has already sheared to %.6g",
                         p.strain, S.time * gd);
            } else {
                /* ... and then takes the steps of a run asked for that strain from the start
                 * (lub_schedule_set_end; the checkpoint of a completed run is taken before its
                 * last sample, which only the run's end forces) */
                if (saved.sched.t_end != p.strain / gd)
                    lub_schedule_set_end(&saved.sched, p.strain / gd);
                const int64_t left =
                    (saved.sched.nsteps - saved.step) / saved.sched.ev[ev_sample].every + 2;
                if ((double)saved.sched.nsteps > LUB_MAX_STEPS) /* at the stopped run's step */
                    snprintf(why, sizeof why,
                             "/strain: %g would take the run to %.3g steps at its step of %.3g, "
                             "more than the %.0e a run may take (README, CLI contract, \"Step "
                             "count\")",
                             p.strain, (double)saved.sched.nsteps, saved.ctl.dt, LUB_MAX_STEPS);
                else if (rs_samples_reserve(&B, nb, saved.nh + left, saved.navg + left,
                                            &nsamp_total, &nsamp_avg) ||
                         rs_checkpoint_read_samples(ck, &saved, &B, nb)) {
                    snprintf(why, sizeof why, "%s",
                             lub_ckpt_error(ck)[0] ? lub_ckpt_error(ck)
                                                   : "out of memory (samples)");
                } else if (lub_h5_continue_output(
                               ctx->resume_result, tab, 6, names, ncomp, saved.nh, ctx->out, N,
                               p.snapshots > 0 ? saved.frames_in_file : 0, why, sizeof why) == 0 &&
                           (!network || lub_h5_continue_frames(ctx->resume_result, network,
                                                               saved.network_frames_in_file, why,
                                                               sizeof why) == 0)) {
                    why[0] = '\0';
                }
            }
        }
        if (ck)
            lub_ckpt_close(ck, NULL, 0);
        if (!ck || why[0]) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "cannot continue from %s: %s",
                     ctx->resume_path, why[0] ? why : "unreadable");
            ctx->resume_rejected = 1;
            lub_rs_free(&S);
            rs_buffers_free(&B);
            return LUB_EXIT_BAD_SPEC;
        }
        lp = saved;
        dt = lp.ctl.dt;
        first_step = saved.step;
        frames = saved.frames_in_file;
        ctx->resumed_from_step = S.step;
        ctx->resume_begun = 1;
    }
    int64_t stopped_at = -1; /* the loop index a stop request ended the loop at */
    int end_checkpoint = 0;  /* --keep-checkpoint: written at the last step, before its sample */
    for (int64_t step = first_step; step <= lp.sched.nsteps; ++step) {
        const double t = S.time;
        if (step == lp.sched.nsteps && ctx->checkpoint_always && ctx->checkpoint_path) {
            /* A completed run keeps its state before the samples of its last step, which the
             * end forces (a sample, a snapshot) and a longer run would not take: its extension
             * (a larger /strain) then takes the steps and samples of the longer run. */
            lp.step = step;
            lp.frames_in_file = frames - lub_h5_snapshots_skipped(ctx->out, NULL, NULL, 0);
            lp.network_frames_in_file = lub_h5_frames_written(network, NULL);
            end_checkpoint =
                rs_checkpoint_write(ctx->checkpoint_path, resolved, &lp, &B, nb, &S, "result.h5",
                                    ctx->checkpoint_failure, sizeof ctx->checkpoint_failure) == 0;
        }
        const int sample = lub_schedule_due(&lp.sched, ev_sample, step) || step == lp.sched.nsteps;
        const int snap =
            ev_snap >= 0 && (lub_schedule_due(&lp.sched, ev_snap, step) || step == lp.sched.nsteps);
        if (sample || snap) {
            int below = 0;
            double low = lub_rs_lowest(&S, &below);
            lp.min_lowest = fmin(lp.min_lowest, low - y_floor);
            if (below > lp.below_floor_max)
                lp.below_floor_max = below;
        }
        if (sample) {
            memset(B.vol, 0, (size_t)nb * sizeof *B.vol);
            double ysum = 0.0, msum = 0.0;
            int dilute = 0;
            const int in_avg = step >= lp.avg_start_step;
            memset(B.vx_inst, 0, (size_t)nb * sizeof *B.vx_inst);
            for (int i = 0; i < N; ++i) {
                /* velocity along the flow relative to the floor-plane mean flow: v_x for the
                 * gradient orientation, v_x - gd z for the vorticity one (should be ~ 0) */
                const double vrel = p.orientation == LUB_RS_VORTICITY
                                        ? S.v[i].x - lub_rs_mean_velocity(&S, S.x[i]).x
                                        : S.v[i].x;
                lub_profile_add_sphere_weighted(B.vol, B.vx_inst, nb, y_floor, dy, S.x[i].y, S.r[i],
                                                vrel);
                ysum += S.m[i] * (S.x[i].y - y_floor);
                msum += S.m[i];
                dilute += step > 0 && S.nint[i] <= (int)p.dilute_max;
            }
            if (in_avg) {
                lp.contacts_sum += (double)S.n_contacts;
                lp.crushed_sum += (double)S.n_crushed;
                for (int i = 0; i < nb; ++i) {
                    B.vx_vol[i] += B.vol[i];
                    B.vx_sum[i] += B.vx_inst[i];
                }
            }
            lub_profile_normalise(B.vol, nb, dy, area, B.phi_inst);
            double pmax = 0.0;
            for (int i = 0; i < nb; ++i)
                pmax = fmax(pmax, B.phi_inst[i]);
            const double hs = lub_profile_height(B.phi_inst, nb, 0.0, dy, 0.5 * pmax);
            const double inv = lub_profile_inventory(B.phi_inst, nb, dy);
            const double ke = lub_rs_kinetic_energy(&S);
            lp.max_ke = fmax(lp.max_ke, ke);
            double row[6] = {hs, ysum / msum, inv / hs, ke, S.max_speed, (double)dilute};
            if (lub_h5_table_append(tab, S.step, t * gd, row)) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s",
                         lub_h5_last_error(ctx->out));
                rc = LUB_EXIT_IO;
                break;
            }
            if (lp.nh < nsamp_total)
                B.series_h[lp.nh++] = hs;
            if (step >= lp.avg_start_step && lp.navg < nsamp_avg) {
                memcpy(&B.samples[lp.navg * nb], B.phi_inst, (size_t)nb * sizeof *B.phi_inst);
                lp.navg++;
            }
        }
        /* the network first: its list completion may wrap positions (the snapshot's are
         * unwrapped, lub_rs_unwrapped) */
        if (snap && p.pair_network == LUB_NETWORK_SNAPSHOTS &&
            (rc = rs_network_frame(ctx, &S, network, &net, gd, step == lp.sched.nsteps)) !=
                LUB_EXIT_OK)
            break;
        if (snap) {
            for (int i = 0; i < N; ++i) {
                vec3 xu, vu;
                lub_rs_unwrapped(&S, i, &xu, &vu);
                memcpy(&B.snap_x[3 * i], &xu, 3 * sizeof(double));
                memcpy(&B.snap_v[3 * i], &vu, 3 * sizeof(double));
                memcpy(&B.snap_w[3 * i], &S.w[i], 3 * sizeof(double));
            }
            double edges[9];
            for (int r = 0; r < 3; ++r) /* rows = edge vectors = columns of H */
                for (int c = 0; c < 3; ++c)
                    edges[3 * r + c] = S.cell.h[c][r];
            if (lub_h5_particles_snapshot(ctx->out, S.step, t, edges, B.snap_x, B.snap_v, B.snap_w,
                                          NULL)) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s",
                         lub_h5_last_error(ctx->out));
                rc = LUB_EXIT_IO;
                break;
            }
            frames++;
        }
        if (step == lp.sched.nsteps)
            break;
        if (ctx->periodic && lub_periodic_due(ctx->periodic, step)) {
            /* the state after the sample of step `step`, as at a stop (the run then goes on) */
            lp.step = step;
            lp.frames_in_file = frames - lub_h5_snapshots_skipped(ctx->out, NULL, NULL, 0);
            lp.network_frames_in_file = lub_h5_frames_written(network, NULL);
            char why[400] = "";
            if (lub_periodic_copy_output(ctx->periodic, ctx->out) == 0) {
                if (rs_checkpoint_write(ctx->periodic->ckpt_tmp, resolved, &lp, &B, nb, &S,
                                        LUB_PERIODIC_OUTPUT, why, sizeof why) == 0)
                    lub_periodic_publish(ctx->periodic);
                else
                    lub_periodic_failed(ctx->periodic, why);
            }
        }
        if (ctx->stop_requested && *ctx->stop_requested) {
            rc = LUB_EXIT_INTERRUPTED;
            stopped_at = step;
            break;
        }
        int e = lub_rs_step(&S);
        if (e != LUB_RS_OK) {
            if (e == LUB_RS_NOMEM && !S.fail_msg[0]) { /* the pair lists could not grow */
                char what[96];
                snprintf(what, sizeof what, "pair lists, step %lld", (long long)S.step);
                lub_diagnostic_out_of_memory(ctx, what, N, 0.0, "/n");
            } else {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s (code %d)", S.fail_msg, e);
            }
            rc = e == LUB_RS_NOMEM ? LUB_EXIT_INTERNAL : LUB_EXIT_NUMERICAL;
            step_unstable = e == LUB_RS_NONFINITE || e == LUB_RS_ESCAPED || e == LUB_RS_RUNAWAY;
            if (e == LUB_RS_ESCAPED && S.escaped_below &&
                lub_rs_weight_overlap(&p) >= LUB_RS_WEIGHT_OVERLAP_BLAMED) {
                /* heavy spheres on soft contacts sink through the floor: not the step's doing */
                const size_t len = strlen(ctx->diagnostic);
                snprintf(ctx->diagnostic + len, sizeof ctx->diagnostic - len,
                         ": the contacts give way under the bed's weight (a sphere's own weight "
                         "compresses a contact by %.3g a, (4/3) pi / (/shields /stiffness)); "
                         "raise /stiffness",
                         lub_rs_weight_overlap(&p));
                step_unstable = 0;
            }
            break;
        }
        if (lub_rs_step_control(&S, &lp.ctl)) {
            dt = lp.ctl.dt;
            S.p.dt = dt;
            lub_schedule_set_dt(&lp.sched, step + 1, S.time, dt);
            if ((double)lp.sched.nsteps > LUB_MAX_STEPS) { /* step-count rule (step_count.h) */
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                         "the automatic step fell to %.3g at strain %.4f (the pairs' summed "
                         "stiffness, /dt_stiffness_safety %g; %ld changes), which would take the "
                         "run to %.3g steps, more than the %.0e a run may take (README, CLI "
                         "contract, \"Step count\"); lower /strain or /stiffness",
                         dt, S.time * gd, p.dt_stiffness_safety, lp.ctl.changes,
                         (double)lp.sched.nsteps, LUB_MAX_STEPS);
                rc = LUB_EXIT_NUMERICAL;
                break;
            }
            if (lp.avg_start_step > step + 1)
                lp.avg_start_step =
                    step + 1 + (int64_t)ceil((p.average_from / gd - S.time) / dt - 1e-9);
            const int64_t left = (lp.sched.nsteps - step) / lp.sched.ev[ev_sample].every + 2;
            if (rs_samples_reserve(&B, nb, lp.nh + left, lp.navg + left, &nsamp_total,
                                   &nsamp_avg)) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory (samples)");
                rc = LUB_EXIT_INTERNAL;
                break;
            }
        }
        if ((step & 255) == 0)
            lub_progress_update(ctx->progress, (double)step / (double)lp.sched.nsteps, S.step);
    }
    lub_progress_last_step(ctx->progress, S.step);
    ctx->checkpoint_written = end_checkpoint && rc == LUB_EXIT_OK;
    /* a stop between the sample of a step and the step: that state into the checkpoint */
    if (stopped_at >= 0 && ctx->checkpoint_path) {
        lp.step = stopped_at;
        lp.frames_in_file = frames - lub_h5_snapshots_skipped(ctx->out, NULL, NULL, 0);
        lp.network_frames_in_file = lub_h5_frames_written(network, NULL);
        ctx->checkpoint_written =
            rs_checkpoint_write(ctx->checkpoint_path, resolved, &lp, &B, nb, &S, "result.h5",
                                ctx->checkpoint_failure, sizeof ctx->checkpoint_failure) == 0;
    }
    /* the network of the final state (after the checkpoint, which keeps the state before the
     * rebuild the network may do), unless a snapshot's frame already shows it */
    lub_h5_frames_written(network, &network_last_step);
    if (network && network_last_step != S.step &&
        (rc == LUB_EXIT_OK || rc == LUB_EXIT_INTERRUPTED)) {
        const int nrc = rs_network_frame(ctx, &S, network, &net, gd, 1);
        if (nrc != LUB_EXIT_OK)
            rc = nrc;
    }
    lub_pair_network_free(&net);
    if (rc == LUB_EXIT_NUMERICAL && dt_adapts && step_unstable)
        lub_diagnostic_adapted_dt_hint(ctx, dt, p.dt_safety, dt_crit, "dt_critical", lp.ctl.changes,
                                       p.dt_stiffness_safety, lp.ctl.ratio_max);
    else if (rc == LUB_EXIT_NUMERICAL && (step_unstable || p.dt > dt_crit))
        lub_diagnostic_dt_hint(ctx, p.dt, p.dt_safety, dt_crit, "dt_critical");

    /* ---- steady-state analysis (also for a partial run: whatever was averaged) ---- */
    int steady = 0;
    const size_t mser = lp.nh >= 10 ? lub_stats_mser(B.series_h, (size_t)lp.nh, 5, &steady) : 0;
    int sem_batch_means = 1;
    for (int i = 0; i < nb; ++i) {
        B.ybin[i] = (i + 0.5) * dy;
        for (int64_t j = 0; j < lp.navg; ++j)
            B.scratch[j] = B.samples[j * nb + i];
        B.phi[i] = lp.navg > 0 ? lub_stats_mean(B.scratch, (size_t)lp.navg) : NAN;
        /* NaN below LUB_STATS_MIN_BATCHES samples: then the naive SEM */
        double sem = lp.navg > 0 ? lub_stats_sem(B.scratch, (size_t)lp.navg, B.scratch2) : NAN;
        if (!(sem >= 0.0) && lp.navg >= 2) {
            sem = sqrt(lub_stats_var(B.scratch, (size_t)lp.navg) / (double)lp.navg);
            sem_batch_means = 0;
        }
        B.phi_err[i] = sem;
    }
    double hs_mean = NAN, hs_sem = NAN, inv = NAN, pmax = 0.0;
    int nkeep = 0;
    double law_rms = NAN, bulk_rate = NAN;
    if (lp.navg > 0) {
        for (int i = 0; i < nb; ++i)
            pmax = fmax(pmax, B.phi[i]);
        hs_mean = lub_profile_height(B.phi, nb, 0.0, dy, 0.5 * pmax);
        /* error of the height: stats.h standard error of the instantaneous heights */
        size_t h0i = (size_t)(lp.nh - lp.navg);
        lub_stats_result hr;
        lub_stats_analyse(B.series_h + h0i, (size_t)lp.navg, 0, B.scratch2, &hr);
        hs_sem = hr.sem;
        if (!(hs_sem >= 0.0) && lp.navg >= LUB_STATS_MIN_BATCHES) {
            /* too few samples after the MSER cut: batch means over the whole averaging
             * window, as phi_err */
            lub_stats_analyse_window(B.series_h + h0i, (size_t)lp.navg, 0, B.scratch2, &hr);
            hs_sem = hr.sem;
        } else if (!(hs_sem >= 0.0) && lp.navg >= 2) {
            /* fewer than 32 averaged samples: the naive SEM, as phi_err (phi_err_method) */
            hs_sem = sqrt(lub_stats_var(B.series_h + h0i, (size_t)lp.navg) / (double)lp.navg);
        }
        inv = lub_profile_inventory(B.phi, nb, dy);
        lub_profile_normal_viscosity(B.phi, B.phi_err, nb, dy, p.Sh, B.eta, B.eta_err);
        nkeep = lub_profile_select_bulk(B.phi, nb, 0.0, dy, p.interface_width, p.floor_skip,
                                        p.phi_min, B.keep);
        /* eta_ii(phi) pairs the exact eta_ii(y) with phi averaged over phi_window (layering) */
        lub_profile_coarse_grain(B.phi, B.phi_err, nb, dy, p.phi_window, B.phi_cg, B.phi_cg_err);
        double s2 = 0.0;
        int nl = 0, q = 0;
        for (int i = 0; i < nb; ++i) {
            double lw = eta22_law(B.phi_cg[i], p.phi_m);
            if (p.orientation == LUB_RS_VORTICITY)
                lw *= lambda33_law(B.phi_cg[i]);
            B.law[i] = isfinite(lw) ? lw : NAN;
            B.keepd[i] = B.keep[i];
            if (B.keep[i]) {
                B.pairs_out[4 * q + 0] = B.phi_cg[i];
                B.pairs_out[4 * q + 1] = B.phi_cg_err[i];
                B.pairs_out[4 * q + 2] = B.eta[i];
                B.pairs_out[4 * q + 3] = B.eta_err[i];
                ++q;
                if (isfinite(lw) && lw > 0.0 && B.eta[i] > 0.0) {
                    double d = log(B.eta[i] / lw);
                    s2 += d * d;
                    ++nl;
                }
            }
        }
        law_rms = nl > 0 ? sqrt(s2 / nl) : NAN;
        /* mean flow-direction velocity per bin and its least-squares slope over bulk bins */
        double sw = 0, sy = 0, sv = 0, syy = 0, syv = 0;
        for (int i = 0; i < nb; ++i) {
            B.vx_inst[i] = B.vx_vol[i] > 0.0 ? B.vx_sum[i] / B.vx_vol[i] : NAN;
            if (B.keep[i] && isfinite(B.vx_inst[i])) {
                sw += 1.0;
                sy += B.ybin[i];
                sv += B.vx_inst[i];
                syy += B.ybin[i] * B.ybin[i];
                syv += B.ybin[i] * B.vx_inst[i];
            }
        }
        if (sw >= 3.0)
            bulk_rate = (sw * syv - sy * sv) / (sw * syy - sy * sy);
        int wr = write_profiles(ctx->out, "y", nb, B.ybin, "a") ||
                 write_profiles(ctx->out, "phi", nb, B.phi, "1") ||
                 write_profiles(ctx->out, "phi_err", nb, B.phi_err, "1") ||
                 write_profiles(ctx->out, "phi_coarse", nb, B.phi_cg, "1") ||
                 write_profiles(ctx->out, "phi_coarse_err", nb, B.phi_cg_err, "1") ||
                 write_profiles(ctx->out, "eta_normal", nb, B.eta, "1") ||
                 write_profiles(ctx->out, "eta_normal_err", nb, B.eta_err, "1") ||
                 write_profiles(ctx->out, "bulk_mask", nb, B.keepd, "1") ||
                 write_profiles(ctx->out, "eta_normal_law", nb, B.law, "1") ||
                 write_profiles(ctx->out, "velocity_x", nb, B.vx_inst, "a gd");
        if (!wr && q > 0) {
            int64_t dims[2] = {q, 4};
            wr = lub_h5_write_array(ctx->out, "eta_vs_phi", 2, dims, B.pairs_out, "1");
        }
        if (wr && rc == LUB_EXIT_OK) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
            rc = LUB_EXIT_IO;
        }
    }

    const double h0 = inv / p.phi_m;
    const double A = lub_acrivos_number(eta, gd, drho, grav, h0 * a);
    lub_summary_put(ctx, "shields", lub_shields_number(eta, gd, drho, grav, a), NAN, "1");
    lub_summary_put(ctx, "acrivos", A, NAN, "1");
    lub_summary_put(ctx, "inertial_number", gd * sqrt(a / grav), NAN, "1");
    lub_summary_put(ctx, "stokes_number", St, NAN, "1");
    lub_summary_put(ctx, "suspension_height", hs_mean, hs_sem, "a");
    lub_summary_put(ctx, "settled_height", h0, NAN, "a");
    lub_summary_put(ctx, "relative_height_increase", (hs_mean - h0) / h0, hs_sem / h0, "1");
    lub_summary_put(ctx, "inventory", inv, NAN, "a");
    lub_summary_put(ctx, "max_phi", pmax, NAN, "1");
    lub_summary_put(ctx, "bulk_bins", nkeep, NAN, "1");
    lub_summary_put(ctx, "bulk_velocity_slope", bulk_rate, NAN, "gd");
    lub_summary_put(ctx, "eta_vs_law_log_rms", law_rms, NAN, "1");
    lub_summary_put(ctx, "averaged_samples", (double)lp.navg, NAN, "1");
    lub_summary_put(ctx, "min_clearance_above_floor", lp.min_lowest, NAN, "a");
    lub_summary_put(ctx, "particles_below_floor", lp.below_floor_max, NAN, "1");
    lub_summary_put(ctx, "lid_reflections", (double)S.lid_hits, NAN, "1");
    const double crushed_fraction = lp.contacts_sum > 0 ? lp.crushed_sum / lp.contacts_sum : 0.0;
    lub_summary_put(ctx, "crushed_contact_fraction", crushed_fraction, NAN, "1");
    lub_summary_put(ctx, "max_kinetic_energy", lp.max_ke, NAN, "eta gd a^3");
    lub_summary_put(ctx, "cell_width", L, NAN, "a");
    lub_summary_put(ctx, "floor_radius", rf, NAN, "a");
    lub_summary_put(ctx, "lid_height", y_lid - y_floor, NAN, "a");
    lub_summary_put(ctx, "initial_height", h_init, NAN, "a");
    lub_summary_put(ctx, "dt", dt, NAN, "1/gd");
    lub_summary_put(ctx, "dt_min", lp.ctl.dt_min, NAN, "1/gd");
    lub_summary_put(ctx, "dt_changes", (double)lp.ctl.changes, NAN, "1");
    lub_summary_put(ctx, "dt_critical", dt_crit, NAN, "1/gd");
    lub_summary_put(ctx, "rebuilds", (double)S.rebuilds, NAN, "1");
    lub_summary_put(ctx, "dt_stiffness_ratio", lp.ctl.ratio_max, NAN, "1");
    lub_summary_put(ctx, "solid_volume", vsum, NAN, "a^3");
    lub_summary_put(ctx, "initial_phi", binfo.layer_phi, NAN, "1");

    json_t *terms = json_array();
    json_array_append_new(terms, json_string("gravity"));
    lub_law_terms_append(terms, S.law.terms);
    if (S.law.eps > 0.0)
        json_array_append_new(terms, json_string("normal_contact"));
    if (p.orientation == LUB_RS_GRADIENT && p.eta_shear > 0.0)
        json_array_append_new(terms, json_string("shear_drag"));
    if (p.eta_dilute > 0.0 && p.dilute_max >= 0)
        json_array_append_new(terms, json_string("dilute_drag"));
    json_array_append_new(terms, json_string("rough_floor"));
    json_array_append_new(terms, json_string("reflecting_lid"));
    json_object_set_new(ctx->summary_extra, "active_terms", terms);
    json_object_set_new(ctx->summary_extra, "steps", json_integer(S.step));
    json_object_set_new(ctx->summary_extra, "simulated_time", json_real(S.time));
    json_object_set_new(ctx->summary_extra, "orientation",
                        json_string(p.orientation == LUB_RS_VORTICITY ? "vorticity" : "gradient"));
    json_object_set_new(ctx->summary_extra, "height_steady", json_boolean(steady));
    json_object_set_new(ctx->summary_extra, "height_transient_end_strain",
                        json_real((double)mser * p.sample_strain));
    json_object_set_new(ctx->summary_extra, "phi_err_method",
                        json_string(lp.navg < 2            ? "none (fewer than 2 samples)"
                                    : sem_batch_means == 1 ? "batch_means_ar1"
                                                           : "naive (fewer than 32 samples)"));
    json_t *warn = json_array();
    if (gd * sqrt(a / grav) > 5e-2)
        json_array_append_new(warn, json_string("inertial number gd sqrt(a/g) above 5e-2: "
                                                "inertia enhances resuspension (seed 000 §IV.C)"));
    if (!steady) {
        const char *why = stopped_at < 0 ? "suspension height not steady (MSER-5): increase "
                                           "/strain"
                          : lub_run_resumable(ctx)
                              ? "suspension height not steady (MSER-5) when the run was "
                                "stopped by a signal: " LUB_RESUME_ADVICE
                              : "suspension height not steady (MSER-5) when the run was "
                                "stopped by a signal, whose checkpoint could not be written: "
                                "run it again";
        json_array_append_new(warn, json_string(why));
    }
    if (p.orientation == LUB_RS_GRADIENT && isfinite(bulk_rate) && fabs(bulk_rate - gd) > 0.2 * gd)
        json_array_append_new(warn, json_string("the bed is not sheared homogeneously (bulk "
                                                "dv_x/dy differs from gd by more than 20 %, see "
                                                "results/bulk_velocity_slope): raise "
                                                "/shear_drag_viscosity"));
    if (S.lid_hits > 0)
        json_array_append_new(warn, json_string("particles reached the lid: raise /lid_height"));
    lub_warn_fixed_dt(warn, p.dt, dt_crit, "dt_critical");
    lub_warn_fixed_dt_stiffness(warn, p.dt, dt_crit, lp.ctl.ratio_max, LUB_SHEAR_DT_STIFFNESS_MAX);
    if (crushed_fraction > LUB_CRUSHED_CONTACT_FRACTION_MAX) /* the message's "1 %" */
        json_array_append_new(warn,
                              json_string("asperities crushed in more than 1 % of the contacts "
                                          "(crushed_contact_fraction; u_n < -alpha eps a): "
                                          "contact forces exceed alpha stiffness eps, the "
                                          "results depend on /stiffness: raise it"));
    lub_network_warn_skipped(network, warn);
    json_object_set_new(ctx->summary_extra, "warnings", warn);
    json_object_set_new(
        ctx->summary_extra, "units",
        json_pack("{s:s, s:s, s:s, s:s, s:s, s:s}", "length", "a (mean particle radius)",
                  "viscosity", "eta (fluid viscosity)", "time", "1/gd (inverse shear rate)",
                  "stress", "eta gd", "energy", "eta gd a^3", "note",
                  "drho g = 1/Sh, g = 1/I^2, rho_p = density_ratio drho; y from the floor "
                  "centre plane"));
    lub_rs_free(&S);
    rs_buffers_free(&B);
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

/* scene_falling_sphere.c — a free sphere falling under gravity onto a fixed sphere
 * (physics-reference §1a; seed 000, contact-model article §3.1, eqs. 34–39).
 *
 * Units (dimensionless): length a (both radii = 1), viscosity eta = 1, time
 * tau_c = eta/(a rho g). Hence rho g = 1, the weight W = m g = (4/3) pi, forces are reported
 * in units of W. Inputs are the dimensionless groups
 *     St = a rho sqrt(2 u0 g)/eta  ->  rho = St^2/(2 u0), g = 2 u0/St^2 (u0 in a);
 *                                      the free-fall time sqrt(2 u0/g) equals St tau_c
 *     stiffness G = g_bulk a / W   ->  g_bulk = G W   (or the contact number K = alpha G eps)
 *     u0/a, eps (physical: contact when u < eps a), alpha = k_n/g_bulk.
 * Viscous rigid limit: u(t) = u0 exp(-(8/9) t/tau_c); rough equilibrium (K > 1):
 * u_eq = eps a - W/k_n = eps - 1/(alpha G).
 *
 * Active terms: gravity on the free sphere, normal lubrication (switchable) and normal
 * contact (eps > 0) through the contact law. No drag, no rotation, no cell: the motion is
 * along the line of centres, so tangential forces and torques are identically zero and are
 * not computed. The lubrication pair exists for the whole run (no cut-off).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "few_body.h"
#include "json_text.h"
#include "law_spec.h"
#include "run_context.h"
#include "scene.h"
#include "scene_summary.h"
#include "step_count.h"

#define LUB_PI 3.14159265358979323846

typedef struct {
    double St, G, K, u0, duration, dt, dt_safety;
    int64_t samples;
    int log_sampling;
    lub_law_spec law;
} fs_params;

static const lub_law_spec_opts fs_law_opts = {
    .allowed_terms = LUB_TERM_NORMAL_LUB,
    .default_terms = LUB_TERM_NORMAL_LUB,
    .tangential = 0,
    .default_eps = 0.0,
    .default_alpha = 1.0,
};

/* Defaults of the members the step count depends on (fs_read, fs_check_steps). */
#define FS_DEFAULT_ST 1e-3
#define FS_DEFAULT_U0 1.0
#define FS_DEFAULT_DURATION 10.0
#define FS_DEFAULT_DT_SAFETY 0.5
/* above this step (in dt_critical) a swinging sphere's summary warns that its amplitudes are
 * not converged (3 % at 0.02 in the README's case) */
#define FS_SWING_DT_FRACTION 0.02
#define FS_DEFAULT_STIFFNESS 1e4

/* The system of a spec at t = 0 (the free sphere at rest above the fixed one) and its step:
 * what fs_run integrates and what fs_read counts the steps of. Dimensionless set: a = 1,
 * eta = 1, tau_c = 1 (rho g = 1). */
typedef struct {
    double rho, grav, m, W; /* density, gravity, mass and weight of the free sphere */
    double dt_crit, dt;     /* the elastic bound and the step (/dt, or /dt_safety dt_crit) */
    lub_law_spec law;       /* the spec's law with its scales set */
    lub_fb_system s;
} fs_setup;

static void fs_build(const fs_params *p, fs_setup *o)
{
    const double a = 1.0, eta = 1.0;
    o->rho = p->St * p->St / (2.0 * p->u0);
    o->grav = 2.0 * p->u0 / (p->St * p->St);
    o->m = 4.0 / 3.0 * LUB_PI * o->rho * a * a * a;
    o->W = o->m * o->grav;
    o->law = p->law;
    lub_law_spec_scale(&o->law, eta, p->G * o->W / a);
    lub_fb_system *s = &o->s;
    memset(s, 0, sizeof *s);
    s->nb = 2;
    s->np = 1;
    s->law = o->law.params;
    s->env.gravity = v3(0.0, -o->grav, 0.0);
    s->env.rotation = 0;
    s->b[0] = (lub_fb_body){.r = a, .inv_m = 0.0, .inv_I = 0.0, .x = v3(0, 0, 0)};
    s->b[1] =
        (lub_fb_body){.r = a, .inv_m = 1.0 / o->m, .inv_I = 0.0, .x = v3(0, 2 * a + p->u0, 0)};
    s->p[0] = (lub_fb_pair){.i = 0, .j = 1, .cutoff = INFINITY};
    o->dt_crit = lub_fb_critical_dt(s);
    o->dt = p->dt > 0.0 ? p->dt : p->dt_safety * o->dt_crit;
}

static double fs_steps(const fs_params *p)
{
    fs_setup o;
    fs_build(p, &o);
    return lub_step_count(p->duration, o.dt);
}

/* The step-count rule (step_count.h): the member named is the one whose default brings the
 * count nearest the allowed range. */
static int fs_check_steps(const fs_params *p, int stiffness_from_K, lub_error *err)
{
    fs_setup o;
    fs_build(p, &o);
    const double count = lub_step_count(p->duration, o.dt);
    if (lub_step_count_ok(count))
        return 0;
    const char *stiff = stiffness_from_K ? "/K" : "/stiffness";
    lub_step_alt alt[5];
    int n = 0;
    fs_params q;
/* alt[n++]: the count with member `field` of the spec at `value`, the rest as it is */
#define FS_ALT(name, field, value)                                                                 \
    (q = *p, q.field = (value), alt[n++] = (lub_step_alt){(name), fs_steps(&q)})
    if (p->dt > 0.0) {
        FS_ALT("/dt", dt, 0.0);
    } else {
        FS_ALT(stiff, G, FS_DEFAULT_STIFFNESS);
        FS_ALT("/St", St, FS_DEFAULT_ST);
        FS_ALT("/u0", u0, FS_DEFAULT_U0);
        FS_ALT("/dt_safety", dt_safety, FS_DEFAULT_DT_SAFETY);
    }
    FS_ALT("/duration", duration, FS_DEFAULT_DURATION);
    char origin[200];
    if (p->dt > 0.0)
        snprintf(origin, sizeof origin, "fixed by /dt");
    else
        snprintf(origin, sizeof origin,
                 "/dt_safety %g times dt_critical %.3g, which %s, /St and /u0 set", p->dt_safety,
                 o.dt_crit, stiffness_from_K ? "/K (the stiffness K/(alpha eps))" : "/stiffness");
    char duration[48];
    snprintf(duration, sizeof duration, "/duration %.6g", p->duration);
#undef FS_ALT
    return lub_step_count_fail(err, lub_step_count_culprit(count, alt, n), count, "", "/duration",
                               duration, o.dt, origin);
}

static int fs_read(json_t *spec, fs_params *p, lub_error *err)
{
    static const char *keys[] = {"scene",    "St", "stiffness", "K",       "u0",
                                 "duration", "dt", "dt_safety", "samples", "sample_spacing",
                                 "law",      NULL};
    static const char *spacing[] = {"linear", "log", NULL};
    if (lub_spec_only_keys(spec, "", keys, err))
        return -1;
    json_t *law = lub_spec_object(spec, "", "law", err);
    if (!law || lub_law_spec_resolve(law, "/law", &fs_law_opts, &p->law, err))
        return -1;
    const double eps = p->law.params.eps, alpha = p->law.params.alpha;
    const lub_range unit_interval = {0.0, 1.0, 1, 0};
    long long ns = 0;
    const char *sp = NULL;
    if (lub_spec_number(spec, "", "St", LUB_POSITIVE, 1, FS_DEFAULT_ST, &p->St, err) ||
        lub_spec_number(spec, "", "u0", LUB_POSITIVE, 1, FS_DEFAULT_U0, &p->u0, err) ||
        lub_spec_number(spec, "", "duration", LUB_POSITIVE, 1, FS_DEFAULT_DURATION, &p->duration,
                        err) ||
        lub_spec_number(spec, "", "dt", LUB_NONNEGATIVE, 1, 0.0, &p->dt, err) ||
        lub_spec_number(spec, "", "dt_safety", unit_interval, 1, FS_DEFAULT_DT_SAFETY,
                        &p->dt_safety, err) ||
        lub_spec_integer(spec, "", "samples", 2, 10000000, 1, 1000, &ns, err) ||
        lub_spec_enum(spec, "", "sample_spacing", spacing, "linear", &sp, err))
        return -1;
    p->samples = ns;
    p->log_sampling = strcmp(sp, "log") == 0;

    /* stiffness: either "stiffness" (G) or "K" (needs eps > 0); if both, they must agree */
    json_t *jK = json_object_get(spec, "K");
    json_t *jG = json_object_get(spec, "stiffness");
    p->K = NAN;
    if (jK) {
        if (lub_spec_number(spec, "", "K", LUB_POSITIVE, 0, 0.0, &p->K, err))
            return -1;
        if (!(eps > 0.0))
            return lub_fail(err, "/K",
                            "the contact number K = k_n eps/((4/3) pi a^2 rho g) "
                            "needs /law/eps > 0; give /stiffness instead");
        double G = p->K / (alpha * eps);
        if (!(G > 0.0) || !isfinite(G)) {
            char k[40], a[40], e[40];
            return lub_fail(err, "/K",
                            "sets the stiffness K/(alpha eps) = %g, which must be positive and "
                            "finite (/K %s, /law/alpha %s, /law/eps %s); give /stiffness "
                            "instead, or a /K nearer alpha eps",
                            G, lub_real_text(p->K, k), lub_real_text(alpha, a),
                            lub_real_text(eps, e));
        }
        if (jG) {
            if (lub_spec_number(spec, "", "stiffness", LUB_POSITIVE, 0, 0.0, &p->G, err))
                return -1;
            char need[40], got[40];
            if (fabs(p->G - G) > 1e-9 * G)
                return lub_fail(err, "/stiffness",
                                "inconsistent with /K: K = alpha*stiffness*eps requires "
                                "stiffness = %s (got %s)",
                                lub_real_text(G, need), lub_real_text(p->G, got));
        } else {
            json_object_set_new(spec, "stiffness", json_real(G));
            p->G = G;
        }
    } else if (lub_spec_number(spec, "", "stiffness", LUB_POSITIVE, 1, FS_DEFAULT_STIFFNESS, &p->G,
                               err)) {
        return -1;
    }
    if (eps > 0.0)
        p->K = alpha * p->G * eps;
    /* the sphere starts at gap u0 a and touches below eps a: eps >= u0 starts it inside the
     * roughness (eps 2 "bounced", eps 1e3 ended "damped" at gap 1e8 a, eps 1e300 exited 3) */
    if (!(eps < p->u0)) {
        char e[40], u[40];
        return lub_fail(err, "/law/eps",
                        "must be below /u0 (%s): the sphere starts at the gap u0 a and touches "
                        "the fixed one at u < eps a, so it would start in contact (got %s)",
                        lub_real_text(p->u0, u), lub_real_text(eps, e));
    }
    return fs_check_steps(p, jK != NULL, err);
}

static int fs_resolve(json_t *spec, lub_error *err)
{
    fs_params p;
    return fs_read(spec, &p, err);
}

/* Online least-squares slope of y(t) (Welford co-moments: no cancellation over 1e7 points). */
typedef struct {
    double n, mt, my, ctt, cty;
} lsq;
static void lsq_add(lsq *s, double t, double y)
{
    s->n += 1.0;
    double dt = t - s->mt;
    s->mt += dt / s->n;
    double dy = y - s->my;
    s->my += dy / s->n;
    s->ctt += dt * (t - s->mt);
    s->cty += dt * (y - s->my);
}
static double lsq_slope(const lsq *s) { return s->n >= 3 && s->ctt > 0 ? s->cty / s->ctt : NAN; }

/* Rebound bookkeeping for the regime (damped / oscillating / bouncing / mixed). */
typedef struct {
    int ascending;
    double gmin, gmax, unmin, unmax; /* extrema of the gap and centre gap in the current phase */
    double gmin_prev, unmin_prev;    /* minima of the last descending phase */
    int bounces, oscillations;
} rebound_tracker;

static void rebound_update(rebound_tracker *r, double vy, double gap, double un, double eps,
                           double osc_threshold)
{
    int asc = vy > 0.0;
    if (asc != r->ascending) {
        if (asc) { /* lowest point reached: remember the minima */
            r->gmin_prev = r->gmin;
            r->unmin_prev = r->unmin;
        } else if (!isnan(r->unmin_prev)) { /* apex after a recorded lowest point */
            /* bounce: the film opens by more than a factor 2 and the surfaces separate
             * beyond the roughness; oscillation: the centres swing, the gap stays trapped */
            if (r->gmax > 2.0 * r->gmin_prev && r->gmax > eps)
                r->bounces++;
            else if (r->unmax - r->unmin_prev > osc_threshold)
                r->oscillations++;
        }
        r->ascending = asc;
        r->gmin = r->gmax = gap;
        r->unmin = r->unmax = un;
    }
    if (gap < r->gmin)
        r->gmin = gap;
    if (gap > r->gmax)
        r->gmax = gap;
    if (un < r->unmin)
        r->unmin = un;
    if (un > r->unmax)
        r->unmax = un;
}

static const char *regime_name(int code)
{
    static const char *names[] = {"damped", "oscillating", "bouncing", "mixed"};
    return names[code];
}

static int fs_run(const json_t *resolved, lub_run_ctx *ctx)
{
    fs_params p;
    lub_error err;
    json_t *spec = json_deep_copy(resolved);
    int rr = fs_read(spec, &p, &err);
    json_decref(spec);
    if (rr) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s: %s", err.pointer, err.message);
        return LUB_EXIT_INTERNAL;
    }

    /* dimensionless set: a = 1, eta = 1, tau_c = 1 (rho g = 1) */
    const double a = 1.0, eta = 1.0;
    fs_setup setup;
    fs_build(&p, &setup);
    const double grav = setup.grav, W = setup.W;
    const double eps = p.law.params.eps;
    p.law = setup.law;
    const double kn = p.law.params.alpha * p.law.params.k_bulk;
    const double u_eq = (eps > 0.0 && p.K > 1.0) ? eps * a - W / kn : NAN;

    lub_fb_system s = setup.s;
    const double dt_crit = setup.dt_crit;
    const double dt = setup.dt;
    /* at rest at t = 0: the half-step velocity v(-dt/2) = +g dt/2 */
    s.b[1].v = v3(0.0, 0.5 * grav * dt, 0.0);

    const char *names[] = {"gap",      "log_gap",       "center_gap",
                           "velocity", "force_contact", "force_lubrication"};
    const int ncomp[] = {1, 1, 1, 1, 1, 1};
    const char *units[] = {"a", "1", "a", "a/tau_c", "m g", "m g"};
    lub_h5_table *tab = lub_h5_set_units(ctx->out, "tau_c", "a", "a/tau_c", "1/tau_c") == 0
                            ? lub_h5_table_create(ctx->out, 6, names, ncomp, units)
                            : NULL;
    if (!tab) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }
    lub_sampler smp;
    lub_sampler_init(&smp, p.duration, p.samples, p.log_sampling, fmin(dt, p.duration * 1e-6));
    double row[6] = {p.u0, log(p.u0 / a), p.u0, 0.0, 0.0, 0.0};
    int rc = LUB_EXIT_OK;
    if (lub_sampler_due(&smp, 0.0) && lub_h5_table_append(tab, 0, 0.0, row))
        rc = LUB_EXIT_IO;

    const double ln_u0 = log(p.u0 / a), rate_ref = 8.0 / 9.0;
    const double contact_floor = 2.0 * eps * a; /* exponential window ends before contact */
    lsq fit = {0}, fit_contact = {0};
    double max_dev = 0.0, window_end = 0.0;
    int in_window = 1;
    double min_delta = ln_u0, min_un = p.u0;
    rebound_tracker rb = {.gmin = p.u0,
                          .gmax = p.u0,
                          .unmin = p.u0,
                          .unmax = p.u0,
                          .gmin_prev = -1.0,
                          .unmin_prev = NAN};
    const double osc_threshold = 1e-2 * W / p.law.params.k_bulk;
    int late_bounces = -1, late_oscillations = -1;
    double late_unmin = INFINITY, late_unmax = -INFINITY;
    /* from 1 to LUB_MAX_STEPS: fs_read refuses other counts (step_count.h) */
    const int64_t nsteps = (int64_t)ceil(p.duration / dt - 1e-9);

    for (int64_t n = 0; n < nsteps && rc == LUB_EXIT_OK; ++n) {
        if (ctx->stop_requested && *ctx->stop_requested) {
            rc = LUB_EXIT_INTERRUPTED;
            break;
        }
        if (lub_fb_step(&s, dt, ctx->diagnostic, sizeof ctx->diagnostic)) {
            rc = LUB_EXIT_NUMERICAL;
            break;
        }
        const lub_pair_output *o = &s.p[0].out;
        const double t = s.t - dt; /* time of the positions the law just evaluated */
        const double vy = s.b[1].v.y;
        if (!(o->gap >= 0.0) || !isfinite(o->delta)) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                     "invalid gap %.17g (delta %.17g) at step %lld, t = %.17g tau_c", o->gap,
                     o->delta, (long long)n, t);
            rc = LUB_EXIT_NUMERICAL;
            break;
        }
        if (o->delta < min_delta)
            min_delta = o->delta;
        if (o->un < min_un)
            min_un = o->un;
        rebound_update(&rb, vy, o->gap, o->un, eps * a, osc_threshold);
        /* deep in contact (u < 1e-3 eps a): apparent weight m g - k_n eps a (K < 1) */
        if (eps > 0.0 && o->gap < 1e-3 * eps * a)
            lsq_add(&fit_contact, t, o->delta);
        if (t >= 0.75 * p.duration) { /* late window: persistent oscillation or still bouncing */
            if (late_bounces < 0) {
                late_bounces = rb.bounces;
                late_oscillations = rb.oscillations;
            }
            if (o->un < late_unmin)
                late_unmin = o->un;
            if (o->un > late_unmax)
                late_unmax = o->un;
        }
        /* exponential window: from the start until contact or the first bounce (the law is
         * about the film gap u; elastic ringing of the centre gap u_n after the release does
         * not open the film and does not end the window) */
        if (in_window && o->gap > contact_floor && rb.bounces == 0) {
            double dev = fabs(expm1(o->delta - ln_u0 + rate_ref * t));
            if (dev > max_dev)
                max_dev = dev;
            window_end = t;
            if (o->gap <= 0.5 * p.u0)
                lsq_add(&fit, t, o->delta);
        } else if (t > 0.0) {
            in_window = 0;
        }
        if (lub_sampler_due(&smp, t) || n == nsteps - 1) {
            row[0] = o->gap;
            row[1] = o->delta;
            row[2] = o->un;
            row[3] = vy;
            row[4] = o->fn_contact / W;
            row[5] = o->fn_lub / W;
            if (lub_h5_table_append(tab, s.step - 1, t, row)) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s",
                         lub_h5_last_error(ctx->out));
                rc = LUB_EXIT_IO;
            }
        }
        if ((n & 1023) == 0)
            lub_progress_update(ctx->progress, (double)n / (double)nsteps, s.step);
    }
    lub_progress_last_step(ctx->progress, s.step);

    const lub_pair_output *o = &s.p[0].out;
    const double rate = -lsq_slope(&fit);
    /* regime: bounced at least once (the film opened by > 2x beyond the roughness) and/or
     * still oscillating over the last quarter of the run: at least two centre-gap swings
     * (apex after a minimum, each > 1% of the static deflection m g/g_bulk) counted in that
     * window, without a bounce, and a total swing > 10% of m g/g_bulk. A monotone approach
     * (the viscous exponential) has no swing and is not an oscillation. */
    const double late_swing = (late_unmax - late_unmin) / (W / p.law.params.k_bulk);
    const int late_osc = late_bounces >= 0 && rb.bounces == late_bounces &&
                         rb.oscillations - late_oscillations >= 2 && late_swing > 0.1;
    int regime = rb.bounces > 0 ? (late_osc ? 3 : 2) : (late_osc ? 1 : 0);
    lub_summary_put_ref(ctx, "exp_rate", rate, "1/tau_c", rate_ref);
    lub_summary_put(ctx, "exp_rate_rel_error", fabs(rate / rate_ref - 1.0), NAN, "1");
    lub_summary_put(ctx, "exp_max_rel_dev", max_dev, NAN, "1");
    /* K < 1: no equilibrium, u ~ exp(-(8/9)(1 - K) t/tau_c) once u << eps a */
    lub_summary_put_ref(ctx, "contact_rate", -lsq_slope(&fit_contact), "1/tau_c",
                        (eps > 0.0 && p.K < 1.0) ? rate_ref * (1.0 - p.K) : NAN);
    lub_summary_put(ctx, "exp_window_end", window_end, NAN, "tau_c");
    lub_summary_put(ctx, "min_gap", a * exp(min_delta), NAN, "a");
    lub_summary_put(ctx, "min_log10_gap", min_delta / log(10.0), NAN, "1");
    lub_summary_put(ctx, "min_center_gap", min_un, NAN, "a");
    lub_summary_put(ctx, "final_gap", o->gap, NAN, "a");
    lub_summary_put(ctx, "final_log10_gap", o->delta / log(10.0), NAN, "1");
    /* a static equilibrium exists only for rough spheres with K > 1 (physics-reference §1a):
     * elsewhere the entry is null, not the final gap of a film still draining */
    lub_summary_put_ref(ctx, "equilibrium_gap", isnan(u_eq) ? NAN : o->gap, "a", u_eq);
    lub_summary_put(ctx, "equilibrium_gap_rel_error", fabs(o->gap / u_eq - 1.0), NAN, "1");
    lub_summary_put(ctx, "final_contact", o->contact, NAN, "1");
    lub_summary_put(ctx, "bounces", rb.bounces, NAN, "1");
    lub_summary_put(ctx, "oscillations", rb.oscillations, NAN, "1");
    lub_summary_put(ctx, "late_swing", late_swing, NAN, "m g/g_bulk");
    lub_summary_put(ctx, "regime_code", regime, NAN,
                    "0 damped, 1 oscillating, 2 bouncing, 3 mixed");
    lub_summary_put(ctx, "St", p.St, NAN, "1");
    lub_summary_put(ctx, "K", p.K, NAN, "1");
    lub_summary_put(ctx, "stiffness", p.G, NAN, "m g/a");
    lub_summary_put(ctx, "dt", dt, NAN, "tau_c");
    lub_summary_put(ctx, "dt_critical", dt_crit, NAN, "tau_c");
    /* normal-law step h = dt g a/nu_n: the backward-Euler gap update is stable for any h but
     * resolves the gap dynamics only where h |u_n/a| <~ 1 (high St, soft spheres) */
    lub_summary_put(ctx, "normal_h", dt * p.law.params.k_bulk / (1.5 * LUB_PI * eta * a), NAN, "1");

    json_t *warnings = json_array();
    lub_report_time_step(ctx, rc, p.dt, p.dt_safety, dt_crit, "dt_critical", warnings);
    /* A swinging sphere's amplitudes converge at first order in the step (St = 1, K = 0.1,
     * eps = 0.01: late_swing 0.223 / 0.119 / 0.104 / 0.102 at dt_safety 0.5 / 0.1 / 0.02 / 0.005,
     * README falling_sphere); the elastic step resolves the swing only coarsely */
    if (rc == LUB_EXIT_OK && regime != 0 && dt > FS_SWING_DT_FRACTION * dt_crit) {
        char w[420];
        snprintf(w, sizeof w,
                 "the sphere %s: its swing amplitudes (late_swing, bounce heights) and final gap "
                 "converge at first order in the step, and at dt = %.3g dt_critical they can be "
                 "twice their converged values; run again with /dt_safety %g or lower to read "
                 "them to a few per cent",
                 regime == 1 ? "oscillates" : "bounces", dt / dt_crit, FS_SWING_DT_FRACTION);
        json_array_append_new(warnings, json_string(w));
    }
    json_object_set_new(ctx->summary_extra, "warnings", warnings);

    json_t *terms = json_array();
    json_array_append_new(terms, json_string("gravity"));
    lub_law_terms_append(terms, s.law.terms);
    if (eps > 0.0)
        json_array_append_new(terms, json_string("normal_contact"));
    json_object_set_new(ctx->summary_extra, "active_terms", terms);
    json_object_set_new(ctx->summary_extra, "regime", json_string(regime_name(regime)));
    json_object_set_new(ctx->summary_extra, "steps", json_integer(s.step));
    json_object_set_new(ctx->summary_extra, "simulated_time", json_real(s.t));
    json_object_set_new(
        ctx->summary_extra, "units",
        json_pack("{s:s, s:s, s:s, s:s, s:s}", "length", "a (sphere radius)", "viscosity",
                  "eta (fluid viscosity)", "time", "tau_c = eta/(a rho g)", "force",
                  "m g (weight of the free sphere)", "note",
                  "rho g = 1, St = a rho sqrt(2 u0 g)/eta, free-fall time = St tau_c"));
    return rc;
}

const lub_scene lub_scene_falling_sphere = {
    .name = "falling_sphere",
    .title = "A sphere falling under gravity onto a fixed sphere in a viscous fluid",
    .description =
        "Two-sphere verification of the lubricated contact law (Chevremont et al., section "
        "3.1): a free sphere starts at rest at gap u0 above a fixed sphere and falls under "
        "gravity against normal lubrication and rough contact. Units: length a, viscosity "
        "eta, time tau_c = eta/(a rho g), force = weight. Inputs: St = a rho sqrt(2 u0 g)/eta, "
        "stiffness g_bulk a/(m g) or contact number K = k_n eps/((4/3) pi a^2 rho g), u0/a, "
        "law {eps (contact when u < eps a), alpha = k_n/g}. Reports the gap series, the fitted "
        "exponential rate (viscous rigid limit 8/9), the equilibrium gap eps a - m g/k_n, the "
        "minimum gap and the regime (damped, oscillating, bouncing, mixed).",
    .resolve = fs_resolve,
    .run = fs_run,
};

/* scene_two_spheres_shear.c — two neutrally buoyant spheres in simple shear with Stokes drag
 * and lubrication (physics-reference §1b; seed 000, contact-model article §3.2, eqs. 40–41).
 *
 * Units (dimensionless): length a (both radii = 1), viscosity eta = 1, time 1/gd (shear rate
 * gd = 1). Background flow w = (gd y, 0, 0), fluid spin curl(w)/2 = (0, 0, -gd/2).
 * Inputs: St = rho gd a^2/eta (-> rho = St), Ca = eta gd/E with the bulk stiffness
 * g = E a (-> g = 1/Ca), law {eps, alpha, kt_ratio = k_t/g, mu, terms}, initial offset d0/a
 * and angle theta: sphere 1 at (0,0,0), sphere 2 at (-x0, d0 sin theta, d0 cos theta), both
 * with the force- and torque-free velocities w(x) and spins (0,0,-1/2).
 *
 * Per sphere: Stokes drag F = -6 pi eta a (v - w(x)) and torque T = -8 pi eta a^3 (omega -
 * curl(w)/2), integrated exactly over a step (exponential integrator, few_body.h), so the
 * drag never limits the time step. Lubrication pair (all terms on by default) while the
 * centre gap u_n <= cutoff a (default 4a: the seed's best match to Da Cunha & Hinch).
 * Time step: dt_safety * the elastic limit from g and k_t (few_body.h); while the spheres
 * are beyond the cut-off (pure advection + drag, no stiffness) the step may grow to dt_free.
 * The run stops at `duration` or, with stop_at_separation, 1/gd after the pair has left the
 * cut-off downstream (beyond it the relative motion is affine: the offset is final).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "few_body.h"
#include "law_spec.h"
#include "run_context.h"
#include "scene.h"
#include "scene_summary.h"
#include "step_count.h"

#define LUB_PI 3.14159265358979323846

typedef struct {
    double St, Ca, d0, theta_deg, x0, cutoff, duration, dt, dt_safety, dt_free, sample_interval;
    int rotation, stop_at_separation;
    lub_law_spec law;
} ts_params;

static const lub_law_spec_opts ts_law_opts = {
    .allowed_terms = LUB_TERM_ALL,
    .default_terms = LUB_TERM_ALL,
    .tangential = 1,
    .default_eps = 0.0,
    .default_alpha = 1.0,
    .default_kt_ratio = 0.5,
    .default_mu = 0.5,
};

/* Defaults of the members the step count depends on (ts_read, ts_check_steps). */
#define TS_DEFAULT_ST 1e-3
#define TS_DEFAULT_CA 1e-6
#define TS_DEFAULT_DURATION 1e5
#define TS_DEFAULT_DT_SAFETY 0.5
#define TS_DEFAULT_DT_FREE 0.01

static int ts_check_steps(const ts_params *p, lub_error *err);

static int ts_read(json_t *spec, ts_params *p, lub_error *err)
{
    static const char *keys[] = {"scene",
                                 "St",
                                 "Ca",
                                 "d0",
                                 "theta_deg",
                                 "x0",
                                 "cutoff",
                                 "duration",
                                 "stop_at_separation",
                                 "dt",
                                 "dt_safety",
                                 "dt_free",
                                 "sample_interval",
                                 "rotation",
                                 "law",
                                 NULL};
    if (lub_spec_only_keys(spec, "", keys, err))
        return -1;
    const lub_range unit_interval = {0.0, 1.0, 1, 0};
    const lub_range angle = {0.0, 180.0, 0, 0};
    const lub_range x0r = {2.0, 1e6, 1, 0};
    /* d0 capped like x0: far beyond the cut-off the spheres never meet, and an offset near
     * DBL_MAX overflowed the step's arithmetic (d0 1e308 failed at step 179) */
    const lub_range d0r = {0.0, 1e6, 0, 0};
    if (lub_spec_number(spec, "", "St", LUB_POSITIVE, 1, TS_DEFAULT_ST, &p->St, err) ||
        lub_spec_number(spec, "", "Ca", LUB_POSITIVE, 1, TS_DEFAULT_CA, &p->Ca, err) ||
        lub_spec_number(spec, "", "d0", d0r, 1, 0.5, &p->d0, err) ||
        lub_spec_number(spec, "", "theta_deg", angle, 1, 90.0, &p->theta_deg, err) ||
        lub_spec_number(spec, "", "x0", x0r, 1, 10.0, &p->x0, err) ||
        lub_spec_number(spec, "", "cutoff", LUB_POSITIVE, 1, 4.0, &p->cutoff, err) ||
        lub_spec_number(spec, "", "duration", LUB_POSITIVE, 1, TS_DEFAULT_DURATION, &p->duration,
                        err) ||
        lub_spec_bool(spec, "", "stop_at_separation", 1, 1, &p->stop_at_separation, err) ||
        lub_spec_number(spec, "", "dt", LUB_NONNEGATIVE, 1, 0.0, &p->dt, err) ||
        lub_spec_number(spec, "", "dt_safety", unit_interval, 1, TS_DEFAULT_DT_SAFETY,
                        &p->dt_safety, err) ||
        lub_spec_number(spec, "", "dt_free", LUB_POSITIVE, 1, TS_DEFAULT_DT_FREE, &p->dt_free,
                        err) ||
        lub_spec_number(spec, "", "sample_interval", LUB_POSITIVE, 1, 0.1, &p->sample_interval,
                        err) ||
        lub_spec_bool(spec, "", "rotation", 1, 1, &p->rotation, err))
        return -1;
    json_t *law = lub_spec_object(spec, "", "law", err);
    if (!law || lub_law_spec_resolve(law, "/law", &ts_law_opts, &p->law, err) ||
        lub_law_spec_check_cutoff(&p->law, "/law", p->cutoff, err))
        return -1;
    return ts_check_steps(p, err);
}

/* The system of a spec at t = 0 and its two steps: what ts_run integrates and what ts_read
 * counts the steps of. Dimensionless set: a = 1, eta = 1, gd = 1. */
typedef struct {
    double m;                /* mass of a sphere */
    double dt_crit;          /* elastic bound (few_body.h) */
    double dt_pair, dt_away; /* the step near the pair (/dt, or /dt_safety dt_crit) and away
                               from it (at least /dt_free) */
    lub_law_spec law;        /* the spec's law with its scales set */
    lub_fb_system s;
} ts_setup;

static void ts_build(const ts_params *p, ts_setup *o)
{
    const double a = 1.0, eta = 1.0, gd = 1.0;
    const double rho = p->St * eta / (gd * a * a);
    o->m = 4.0 / 3.0 * LUB_PI * rho * a * a * a;
    const double I = 0.4 * o->m * a * a;
    o->law = p->law;
    lub_law_spec_scale(&o->law, eta, a * eta * gd / p->Ca);
    lub_fb_system *s = &o->s;
    memset(s, 0, sizeof *s);
    s->nb = 2;
    s->np = 1;
    s->law = o->law.params;
    s->env.zeta_t = 6.0 * LUB_PI * eta * a;
    s->env.zeta_r = 8.0 * LUB_PI * eta * a * a * a;
    s->env.L[0][1] = gd;
    s->env.rotation = p->rotation;
    const double th = p->theta_deg * LUB_PI / 180.0;
    const vec3 x2 = v3(-p->x0 * a, p->d0 * a * sin(th), p->d0 * a * cos(th));
    const vec3 spin = lub_fb_flow_spin(&s->env);
    s->b[0] =
        (lub_fb_body){.r = a, .inv_m = 1.0 / o->m, .inv_I = 1.0 / I, .x = v3(0, 0, 0), .w = spin};
    s->b[1] = (lub_fb_body){.r = a, .inv_m = 1.0 / o->m, .inv_I = 1.0 / I, .x = x2, .w = spin};
    s->b[0].v = lub_fb_flow_velocity(&s->env, s->b[0].x);
    s->b[1].v = lub_fb_flow_velocity(&s->env, s->b[1].x);
    s->p[0] = (lub_fb_pair){.i = 0, .j = 1, .cutoff = p->cutoff};
    o->dt_crit = lub_fb_critical_dt(s);
    o->dt_pair = p->dt > 0.0 ? p->dt : p->dt_safety * o->dt_crit;
    o->dt_away = fmax(o->dt_pair, p->dt_free);
}

/* The count the rule judges (step_count.h): every step lies between dt_pair and dt_away, so
 * the run takes at most duration/dt_pair steps (judged against the cap) and at least
 * duration/dt_away (judged against one step). */
static double ts_steps(const ts_params *p, double *dt, int *away)
{
    ts_setup o;
    ts_build(p, &o);
    const double most = lub_step_count(p->duration, o.dt_pair);
    const double fewest = lub_step_count(p->duration, o.dt_away);
    *away = lub_step_count_ok(most) && !lub_step_count_ok(fewest);
    *dt = *away ? o.dt_away : o.dt_pair;
    return *away ? fewest : most;
}

static double ts_steps_of(const ts_params *p)
{
    double dt;
    int away;
    return ts_steps(p, &dt, &away);
}

static int ts_check_steps(const ts_params *p, lub_error *err)
{
    double dt;
    int away;
    const double count = ts_steps(p, &dt, &away);
    if (lub_step_count_ok(count))
        return 0;
    lub_step_alt alt[6];
    int n = 0;
    ts_params q;
/* alt[n++]: the count with member `field` of the spec at `value`, the rest as it is */
#define TS_ALT(name, field, value)                                                                 \
    (q = *p, q.field = (value), alt[n++] = (lub_step_alt){(name), ts_steps_of(&q)})
    TS_ALT("/dt_free", dt_free, TS_DEFAULT_DT_FREE);
    if (p->dt > 0.0) {
        TS_ALT("/dt", dt, 0.0);
    } else {
        TS_ALT("/Ca", Ca, TS_DEFAULT_CA);
        TS_ALT("/St", St, TS_DEFAULT_ST);
        TS_ALT("/law/kt_ratio", law.kt_ratio, ts_law_opts.default_kt_ratio);
        TS_ALT("/dt_safety", dt_safety, TS_DEFAULT_DT_SAFETY);
    }
    TS_ALT("/duration", duration, TS_DEFAULT_DURATION);
    char origin[240];
    if (away)
        snprintf(origin, sizeof origin,
                 "the step away from the pair, the larger of /dt_free and the step near it");
    else if (p->dt > 0.0)
        snprintf(origin, sizeof origin, "the step near the pair, fixed by /dt");
    else
        snprintf(origin, sizeof origin,
                 "the step near the pair, /dt_safety %g times dt_critical, which /Ca, /St and "
                 "/law/kt_ratio set%s",
                 p->dt_safety,
                 count > 1.0 ? "; /duration bounds the run even with /stop_at_separation" : "");
    char duration[48];
    snprintf(duration, sizeof duration, "/duration %.6g", p->duration);
#undef TS_ALT
    return lub_step_count_fail(err, lub_step_count_culprit(count, alt, n), count, "", "/duration",
                               duration, dt, origin);
}

static int ts_resolve(json_t *spec, lub_error *err)
{
    ts_params p;
    return ts_read(spec, &p, err);
}

/* One row of the trajectory table: relative position, gap, centre gap, both spins. */
static void fill_row(double row[11], vec3 rel, double gap, double un, const lub_fb_system *s)
{
    row[0] = rel.x;
    row[1] = rel.y;
    row[2] = rel.z;
    row[3] = gap;
    row[4] = un;
    row[5] = s->b[0].w.x;
    row[6] = s->b[0].w.y;
    row[7] = s->b[0].w.z;
    row[8] = s->b[1].w.x;
    row[9] = s->b[1].w.y;
    row[10] = s->b[1].w.z;
}

static int ts_run(const json_t *resolved, lub_run_ctx *ctx)
{
    ts_params p;
    lub_error err;
    json_t *spec = json_deep_copy(resolved);
    int rr = ts_read(spec, &p, &err);
    json_decref(spec);
    if (rr) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s: %s", err.pointer, err.message);
        return LUB_EXIT_INTERNAL;
    }
    const double a = 1.0, eta = 1.0, gd = 1.0;
    ts_setup setup;
    ts_build(&p, &setup);
    p.law = setup.law;
    lub_fb_system s = setup.s;
    const vec3 x2 = s.b[1].x;
    const double dt_crit = setup.dt_crit;
    const double dt_pair = setup.dt_pair;
    const double dt_away = setup.dt_away;

    const char *names[] = {"relative_position", "gap", "center_gap", "spin1", "spin2"};
    const int ncomp[] = {3, 1, 1, 3, 3};
    const char *units[] = {"a", "a", "a", "gd", "gd"};
    lub_h5_table *tab = lub_h5_set_units(ctx->out, "1/gd", "a", "a gd", "gd") == 0
                            ? lub_h5_table_create(ctx->out, 5, names, ncomp, units)
                            : NULL;
    if (!tab) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }

    int rc = LUB_EXIT_OK;
    double next_sample = 0.0, t_sep = NAN;
    double min_gap_delta = INFINITY, min_un = INFINITY, max_y = x2.y;
    int was_active = 0, contacted = 0, separated = 0;
    vec3 rel = v3_sub(s.b[1].x, s.b[0].x);
    double row[11];
    /* every step is at least dt_pair long and the time counts steps (few_body.h): the run ends
     * within /duration / dt_pair steps, which ts_read keeps below LUB_MAX_STEPS; a guard */
    const int64_t step_limit = (int64_t)ceil(p.duration / dt_pair) + 16;
    while (s.t < p.duration) {
        if (ctx->stop_requested && *ctx->stop_requested) {
            rc = LUB_EXIT_INTERRUPTED;
            break;
        }
        if (s.step >= step_limit) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                     "the run took %lld steps of at least %.17g without reaching /duration "
                     "%.17g (t = %.17g)",
                     (long long)s.step, dt_pair, p.duration, s.t);
            rc = LUB_EXIT_NUMERICAL;
            break;
        }
        /* step length: elastic limit while the pair is (or may become) active */
        rel = v3_sub(s.b[1].x, s.b[0].x);
        double un_now = v3_norm(rel) - 2.0 * a;
        double dt =
            (un_now <= p.cutoff * a + 4.0 * dt_away * (fabs(rel.y) + 1.0) * gd) ? dt_pair : dt_away;
        double t_eval = s.t;
        if (lub_fb_step(&s, dt, ctx->diagnostic, sizeof ctx->diagnostic)) {
            rc = LUB_EXIT_NUMERICAL;
            break;
        }
        const lub_fb_pair *pr = &s.p[0];
        if (pr->active) {
            was_active = 1;
            if (!isfinite(pr->out.delta)) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                         "non-finite gap at step %lld, t = %.17g", (long long)s.step, t_eval);
                rc = LUB_EXIT_NUMERICAL;
                break;
            }
            if (pr->out.delta < min_gap_delta)
                min_gap_delta = pr->out.delta;
            if (pr->out.un < min_un)
                min_un = pr->out.un;
            if (pr->out.contact)
                contacted = 1;
        }
        if (rel.y > max_y)
            max_y = rel.y;
        if (t_eval >= next_sample) {
            next_sample = t_eval + p.sample_interval;
            fill_row(row, rel, pr->active ? pr->out.gap : un_now, un_now, &s);
            if (lub_h5_table_append(tab, s.step - 1, t_eval, row)) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s",
                         lub_h5_last_error(ctx->out));
                rc = LUB_EXIT_IO;
                break;
            }
        }
        if (was_active && !pr->active && rel.x > 0.0 && !separated) {
            separated = 1;
            t_sep = s.t;
        }
        if (p.stop_at_separation && separated && s.t - t_sep > 1.0 / gd)
            break;
        if ((s.step & 1023) == 0)
            lub_progress_update(ctx->progress, s.t / p.duration, s.step);
    }
    lub_progress_last_step(ctx->progress, s.step);
    rel = v3_sub(s.b[1].x, s.b[0].x);
    {
        double un_end = v3_norm(rel) - 2.0 * a;
        fill_row(row, rel, s.p[0].active ? s.p[0].out.gap : un_end, un_end, &s);
        if (rc == LUB_EXIT_OK && lub_h5_table_append(tab, s.step, s.t, row))
            rc = LUB_EXIT_IO;
    }

    const double y0 = x2.y, z0 = x2.z;
    lub_summary_put(ctx, "initial_offset_y", y0, NAN, "a");
    lub_summary_put(ctx, "initial_offset_z", z0, NAN, "a");
    lub_summary_put_ref(ctx, "final_offset_y", rel.y, "a", y0);
    lub_summary_put(ctx, "final_offset_z", rel.z, NAN, "a");
    lub_summary_put(ctx, "final_x", rel.x, NAN, "a");
    lub_summary_put(ctx, "offset_change", hypot(rel.y, rel.z) - p.d0 * a, NAN, "a");
    lub_summary_put(ctx, "offset_rel_change",
                    p.d0 > 0 ? (hypot(rel.y, rel.z) - p.d0 * a) / (p.d0 * a) : NAN, NAN, "1");
    lub_summary_put(ctx, "min_gap", was_active ? a * exp(min_gap_delta) : NAN, NAN, "a");
    lub_summary_put(ctx, "min_log10_gap", was_active ? min_gap_delta / log(10.0) : NAN, NAN, "1");
    lub_summary_put(ctx, "min_center_gap", was_active ? min_un : NAN, NAN, "a");
    lub_summary_put(ctx, "max_offset_y", max_y, NAN, "a");
    lub_summary_put(ctx, "contact", contacted, NAN, "1");
    lub_summary_put(ctx, "separated", separated, NAN, "1");
    lub_summary_put(ctx, "dt", dt_pair, NAN, "1/gd");
    lub_summary_put(ctx, "dt_critical", dt_crit, NAN, "1/gd");
    /* normal-law step h = dt g a/nu_n: the backward-Euler gap update is stable for any h but
     * resolves the gap dynamics only where h |u_n/a| <~ 1 (high St, soft spheres) */
    lub_summary_put(ctx, "normal_h", dt_pair * p.law.params.k_bulk / (1.5 * LUB_PI * eta * a), NAN,
                    "1");

    /* a run whose results are not those of an encounter: say which and what to change (the
     * pair never entered the cut-off: min_gap null; still inside it at the end: the final
     * offset is not the far-field one) */
    json_t *warnings = json_array();
    lub_report_time_step(ctx, rc, p.dt, p.dt_safety, dt_crit, "dt_critical", warnings);
    if (rc == LUB_EXIT_OK && !separated) {
        char text[320];
        text[0] = '\0';
        if (!was_active && !(y0 > 0.0))
            snprintf(text, sizeof text,
                     "the spheres start on the same streamline (d0 sin theta = 0) and never "
                     "approach: min_gap is null; raise /d0 or move /theta_deg away from 0 "
                     "and 180");
        else if (!was_active && rel.x <= 0.0)
            snprintf(text, sizeof text,
                     "the spheres had not reached each other when the run ended at /duration "
                     "%.3g (x = %.3g a): min_gap is null and the offset is the initial one; "
                     "raise /duration (the approach takes about x0/(d0 sin theta) = %.3g) or "
                     "lower /x0",
                     p.duration, rel.x, p.x0 / y0);
        else if (!was_active)
            snprintf(text, sizeof text,
                     "the spheres passed each other without coming within the cut-off (offset "
                     "%.3g a, above 2 a + cut-off = %.3g a): no lubrication interaction, "
                     "min_gap is null; lower /d0 or raise /cutoff",
                     hypot(y0, z0), 2.0 * a + p.cutoff * a);
        else if (hypot(p.x0, p.d0) < 2.0 + p.cutoff) /* started inside the cut-off */
            snprintf(text, sizeof text,
                     "the pair was still within the cut-off when the run ended at /duration "
                     "%.3g: the final offset is not the far-field one. It started within the "
                     "cut-off, where a pair can orbit on a closed trajectory of Stokes flow "
                     "for ever; raise /x0 above 2 + /cutoff, or raise /duration",
                     p.duration);
        else
            snprintf(text, sizeof text,
                     "the pair was still within the cut-off when the run ended at /duration "
                     "%.3g: the final offset is not the far-field one; raise /duration",
                     p.duration);
        json_array_append_new(warnings, json_string(text));
    }
    json_object_set_new(ctx->summary_extra, "warnings", warnings);

    json_t *terms = json_array();
    json_array_append_new(terms, json_string("stokes_drag"));
    json_array_append_new(terms, json_string("stokes_drag_torque"));
    if (p.rotation)
        json_array_append_new(terms, json_string("rotation"));
    lub_law_terms_append(terms, s.law.terms);
    if (p.law.params.eps > 0.0)
        json_array_append_new(terms, json_string("normal_contact"));
    json_object_set_new(ctx->summary_extra, "active_terms", terms);
    json_object_set_new(ctx->summary_extra, "steps", json_integer(s.step));
    json_object_set_new(ctx->summary_extra, "simulated_time", json_real(s.t));
    json_object_set_new(
        ctx->summary_extra, "units",
        json_pack("{s:s, s:s, s:s, s:s}", "length", "a (sphere radius)", "viscosity",
                  "eta (fluid viscosity)", "time", "1/gd (inverse shear rate)", "note",
                  "St = rho gd a^2/eta, Ca = eta gd/E with bulk stiffness g = E a"));
    return rc;
}

const lub_scene lub_scene_two_spheres_shear = {
    .name = "two_spheres_shear",
    .title = "Two neutrally buoyant spheres passing each other in simple shear",
    .description =
        "Two-sphere verification of the lubricated contact law (Chevremont et al., section "
        "3.2): sphere 1 at the origin, sphere 2 at (-x0, d0 sin theta, d0 cos theta) a, both "
        "in the shear flow w = (gd y, 0, 0) with Stokes drag and drag torque (integrated "
        "exactly) and all lubrication terms while u_n < cutoff a (default 4a). Units: length "
        "a, viscosity eta, time 1/gd. Inputs: St = rho gd a^2/eta, Ca = eta gd/E (g = E a), "
        "law {eps, alpha, kt_ratio, mu, terms}. Reports the relative trajectory, the minimum "
        "gap and the final streamline offset (reversible for smooth rigid spheres).",
    .resolve = ts_resolve,
    .run = ts_run,
};

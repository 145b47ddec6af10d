/* scene_continuum_rheometer.c — "continuum_rheometer": the 0-D texture-tensor rheometer of
 * Ozenda's thesis (models M3, chapter 3, and M4, chapter 4) under an arbitrary piecewise
 * protocol of imposed shear rate, imposed shear stress and pauses.
 *
 * Spec (schema/continuum_rheometer.schema.json):
 *   parameters (default {"set": "m4_laws", "psi": 0.8}):
 *               {"set": "m4_laws", "psi", "phi_m" = 0.535, "eta0" = 1.02}   laws (4.9), Table 4.1
 *             | {"set": "m4_table", "phi"}           Table 4.2 row (phi in 0.30 .. 0.50)
 *             | {"set": "m3_laws", "phi", "eta0" = 1.03}  laws (3.10), (3.16), Table 3.3
 *             | {"set": "m3_table", "phi"}           Table 3.2 row
 *             | {"set": "m4", a, delta1, delta2, beta1, beta2, beta3, eta, eta_e}   explicit
 *             | {"set": "m3", alpha, beta, eta, eta_e}                                explicit
 *   initial_state: "rest" | "steady_positive" | "steady_negative" (pre-sheared), default rest
 *   protocol: [{"mode": "rate", "rate" (1/s, != 0), "strain" | "duration" (s)},
 *              {"mode": "stress", "stress" (Pa), "strain" | "duration"},
 *              {"mode": "pause", "duration"},
 *              {"mode": "oscillation", "rate_amplitude" (1/s), "frequency" (Hz), "duration"}]
 *             (1..1000 segments; oscillation = LAOS gd = A sin(2 pi f t) from the segment start;
 *             default: start-up at 1/s to strain 10, then reversal at -1/s for strain 10)
 *   samples_per_segment: 2..100000, default 200
 * SI units (Pa, Pa.s, s, 1/s). Exact strain-space solution per segment (continuum_protocol.h).
 * Outputs: /observables/<series> (strain, shear_rate, shear_stress, N1, N2, particle_pressure,
 * apparent_viscosity, depletion_angle, gamma_e_xx, gamma_e_yy, gamma_e_xy, fabric_gap, b_e_min,
 * segment); summary: steady closed-form values, final values, extrema of eta_app.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "continuum_protocol.h"
#include "continuum_texture_laws.h"
#include "json_text.h"
#include "run_context.h"
#include "scene.h"

#define RHEO_MAX_SEGMENTS 1000
#define PI_ 3.14159265358979323846

static const double TABLE_PHIS[5] = {0.30, 0.40, 0.44, 0.47, 0.50};

static int table_phi(json_t *obj, const char *ptr, double *phi, lub_error *err)
{
    char p[256];
    lub_pointer_join(p, sizeof p, ptr, "phi");
    if (lub_spec_number(obj, ptr, "phi", LUB_UNBOUNDED, 0, 0.0, phi, err))
        return -1;
    for (int i = 0; i < 5; ++i)
        if (*phi == TABLE_PHIS[i])
            return 0;
    char got[40];
    return lub_fail(err, p,
                    "must be one of the tabulated fractions 0.3, 0.4, 0.44, 0.47, 0.5 "
                    "(got %s)",
                    lub_real_text(*phi, got));
}

/* Reads the "parameters" object into model parameters (also used by run on the resolved spec). */
static int read_params(json_t *spec, lub_texture_params *tp, const char **set_out, lub_error *err)
{
    static const char *sets[] = {"m4_laws", "m4_table", "m3_laws", "m3_table", "m4", "m3", NULL};
    const char *P = "/parameters";
    json_t *o = json_object_get(spec, "parameters");
    if (!o) { /* default: the chapter-4 laws at psi = 0.8 */
        json_object_set_new(spec, "parameters",
                            json_pack("{s:s, s:f}", "set", "m4_laws", "psi", 0.8));
        o = json_object_get(spec, "parameters");
    }
    if (!json_is_object(o))
        return lub_fail(err, P, "must be an object");
    const char *set;
    if (lub_spec_enum(o, P, "set", sets, NULL, &set, err))
        return -1;
    *set_out = set;
    const char *why = NULL;
    if (strcmp(set, "m4_laws") == 0) {
        static const char *k[] = {"set", "psi", "phi_m", "eta0", NULL};
        double psi, phim, eta0;
        if (lub_spec_only_keys(o, P, k, err) ||
            lub_spec_number(o, P, "psi", (lub_range){0.0, 1.0, 1, 1}, 0, 0, &psi, err) ||
            lub_spec_number(o, P, "phi_m", (lub_range){0.0, 1.0, 1, 1}, 1, 0.535, &phim, err) ||
            lub_spec_number(o, P, "eta0", LUB_POSITIVE, 1, 1.02, &eta0, err))
            return -1;
        lub_m4_laws L = lub_m4_laws_thesis();
        if (lub_m4_from_laws(&L, psi, phim, eta0, tp, &why))
            return lub_fail(err, "/parameters/psi", "%s", why);
    } else if (strcmp(set, "m3_laws") == 0) {
        static const char *k[] = {"set", "phi", "eta0", NULL};
        double phi, eta0;
        if (lub_spec_only_keys(o, P, k, err) ||
            lub_spec_number(o, P, "phi", (lub_range){0.0, 0.571, 1, 1}, 0, 0, &phi, err) ||
            lub_spec_number(o, P, "eta0", LUB_POSITIVE, 1, 1.03, &eta0, err))
            return -1;
        lub_m3_laws L = lub_m3_laws_thesis();
        if (lub_m3_from_laws(&L, phi, eta0, tp, &why))
            return lub_fail(err, "/parameters/phi", "%s", why);
    } else if (strcmp(set, "m4_table") == 0 || strcmp(set, "m3_table") == 0) {
        static const char *k[] = {"set", "phi", NULL};
        double phi;
        if (lub_spec_only_keys(o, P, k, err) || table_phi(o, P, &phi, err))
            return -1;
        int rc = set[1] == '4' ? lub_m4_table42(phi, tp, NULL, &why)
                               : lub_m3_table32(phi, tp, NULL, &why);
        if (rc)
            return lub_fail(err, "/parameters/phi", "%s", why);
    } else if (strcmp(set, "m4") == 0) {
        static const char *k[] = {"set",   "a",     "delta1", "delta2", "beta1",
                                  "beta2", "beta3", "eta",    "eta_e",  NULL};
        if (lub_spec_only_keys(o, P, k, err) ||
            lub_spec_number(o, P, "a", (lub_range){0.0, 1.0, 1, 0}, 0, 0, &tp->a, err) ||
            lub_spec_number(o, P, "delta1", LUB_POSITIVE, 0, 0, &tp->delta1, err) ||
            lub_spec_number(o, P, "delta2", LUB_UNBOUNDED, 0, 0, &tp->delta2, err) ||
            lub_spec_number(o, P, "beta1", LUB_UNBOUNDED, 0, 0, &tp->beta1, err) ||
            lub_spec_number(o, P, "beta2", LUB_UNBOUNDED, 0, 0, &tp->beta2, err) ||
            lub_spec_number(o, P, "beta3", LUB_UNBOUNDED, 0, 0, &tp->beta3, err) ||
            lub_spec_number(o, P, "eta", LUB_POSITIVE, 0, 0, &tp->eta, err) ||
            lub_spec_number(o, P, "eta_e", LUB_NONNEGATIVE, 0, 0, &tp->eta_e, err))
            return -1;
    } else { /* m3 */
        static const char *k[] = {"set", "alpha", "beta", "eta", "eta_e", NULL};
        double al, be, et, ee;
        if (lub_spec_only_keys(o, P, k, err) ||
            lub_spec_number(o, P, "alpha", LUB_POSITIVE, 0, 0, &al, err) ||
            lub_spec_number(o, P, "beta", LUB_UNBOUNDED, 0, 0, &be, err) ||
            lub_spec_number(o, P, "eta", LUB_POSITIVE, 0, 0, &et, err) ||
            lub_spec_number(o, P, "eta_e", LUB_NONNEGATIVE, 0, 0, &ee, err))
            return -1;
        *tp = lub_texture_m3(al, be, ee, et);
    }
    const char *bad = lub_texture_check(tp);
    if (bad)
        return lub_fail(err, P, "%s", bad);
    return 0;
}

static int read_protocol(json_t *spec, lub_segment *segs, int *nseg, lub_error *err)
{
    static const char *modes[] = {"rate", "stress", "pause", "oscillation", NULL};
    json_t *a = json_object_get(spec, "protocol");
    if (!a) { /* default: start-up to strain 10, then reversal for strain 10, at |gd| = 1/s */
        json_object_set_new(spec, "protocol",
                            json_pack("[{s:s, s:f, s:f}, {s:s, s:f, s:f}]", "mode", "rate", "rate",
                                      1.0, "strain", 10.0, "mode", "rate", "rate", -1.0, "strain",
                                      10.0));
        a = json_object_get(spec, "protocol");
    }
    if (!json_is_array(a) || json_array_size(a) < 1 || json_array_size(a) > RHEO_MAX_SEGMENTS)
        return lub_fail(err, "/protocol", "must be an array of 1 to %d segments",
                        RHEO_MAX_SEGMENTS);
    *nseg = (int)json_array_size(a);
    for (int k = 0; k < *nseg; ++k) {
        char P[64], p2[128];
        snprintf(P, sizeof P, "/protocol/%d", k);
        json_t *o = json_array_get(a, (size_t)k);
        if (!json_is_object(o))
            return lub_fail(err, P, "must be an object {\"mode\": ...}");
        const char *mode;
        if (lub_spec_enum(o, P, "mode", modes, NULL, &mode, err))
            return -1;
        lub_segment *s = &segs[k];
        memset(s, 0, sizeof *s);
        if (strcmp(mode, "pause") == 0) {
            static const char *kk[] = {"mode", "duration", NULL};
            s->mode = LUB_SEG_PAUSE;
            if (lub_spec_only_keys(o, P, kk, err) ||
                lub_spec_number(o, P, "duration", LUB_POSITIVE, 0, 0, &s->duration, err))
                return -1;
            continue;
        }
        if (strcmp(mode, "oscillation") == 0) {
            static const char *kk[] = {"mode", "rate_amplitude", "frequency", "duration", NULL};
            s->mode = LUB_SEG_OSCILLATION;
            if (lub_spec_only_keys(o, P, kk, err) ||
                lub_spec_number(o, P, "rate_amplitude", LUB_POSITIVE, 0, 0, &s->value, err) ||
                lub_spec_number(o, P, "frequency", LUB_POSITIVE, 0, 0, &s->frequency, err) ||
                lub_spec_number(o, P, "duration", LUB_POSITIVE, 0, 0, &s->duration, err))
                return -1;
            if (!(2.0 * s->frequency * s->duration <= 1e7))
                return lub_fail(err, P, "at most 1e7 half periods (2 frequency x duration)");
            /* the strain of a half period 2A/omega and the total strain ~ (2/pi) A duration
             * (until 2026-12-07 an overflow here exited 3 with "/protocol/k: non-finite ... at
             * strain -nan") */
            if (!isfinite(s->value / (3.14159265358979323846 * s->frequency)) ||
                !isfinite(s->value * s->duration))
                return lub_fail(err, lub_pointer_join(p2, sizeof p2, P, "rate_amplitude"),
                                "rate_amplitude / frequency (the strain 2A/omega of a half period) "
                                "and rate_amplitude x duration must stay finite doubles");
            continue;
        }
        int rate = strcmp(mode, "rate") == 0;
        static const char *kr[] = {"mode", "rate", "strain", "duration", NULL};
        static const char *ks[] = {"mode", "stress", "strain", "duration", NULL};
        s->mode = rate ? LUB_SEG_RATE : LUB_SEG_STRESS;
        if (lub_spec_only_keys(o, P, rate ? kr : ks, err) ||
            lub_spec_number(o, P, rate ? "rate" : "stress", LUB_UNBOUNDED, 0, 0, &s->value, err))
            return -1;
        json_t *js = json_object_get(o, "strain"), *jd = json_object_get(o, "duration");
        if ((js != NULL) == (jd != NULL))
            return lub_fail(err, P, "give exactly one of \"strain\" or \"duration\"");
        if (js ? lub_spec_number(o, P, "strain", LUB_POSITIVE, 0, 0, &s->strain, err)
               : lub_spec_number(o, P, "duration", LUB_POSITIVE, 0, 0, &s->duration, err))
            return -1;
        if (rate && s->value == 0.0)
            return lub_fail(err, lub_pointer_join(p2, sizeof p2, P, "rate"),
                            "must be nonzero (use a \"pause\" segment for gd = 0)");
        /* the strain of a duration segment, |rate| duration or the time map's |stress|
         * duration/eta_app, is formed from this product */
        if (!isfinite(fabs(s->value) * s->duration))
            return lub_fail(err, lub_pointer_join(p2, sizeof p2, P, "duration"),
                            "%s x duration overflows a double", rate ? "rate" : "stress");
        if (!rate && s->value == 0.0 && js)
            return lub_fail(err, lub_pointer_join(p2, sizeof p2, P, "stress"),
                            "a zero imposed stress never accumulates strain: end the segment "
                            "by \"duration\"");
    }
    return 0;
}

static int rheo_resolve(json_t *spec, lub_error *err)
{
    static const char *keys[] = {"scene",    "parameters",          "initial_state",
                                 "protocol", "samples_per_segment", NULL};
    static const char *inits[] = {"rest", "steady_positive", "steady_negative", NULL};
    lub_segment tmp[RHEO_MAX_SEGMENTS]; /* 32 kB of scratch on the stack (thread-safe) */
    lub_texture_params tp;
    const char *set, *init;
    long long ns;
    int nseg;
    if (lub_spec_only_keys(spec, "", keys, err) || read_params(spec, &tp, &set, err) ||
        lub_spec_enum(spec, "", "initial_state", inits, "rest", &init, err) ||
        read_protocol(spec, tmp, &nseg, err) ||
        lub_spec_integer(spec, "", "samples_per_segment", 2, 100000, 1, 200, &ns, err))
        return -1;
    return 0;
}

typedef struct {
    lub_run_ctx *ctx;
    lub_h5_table *tab;
    int nseg, io_error;
    int64_t step;
    double eta_min, strain_min, eta_max, strain_max;
    lub_rheo_sample last;
} rheo_sink_state;

static int rheo_sink(void *user, const lub_rheo_sample *s)
{
    rheo_sink_state *st = user;
    double row[14] = {s->strain,      s->gd,
                      s->sigma_xy,    s->n1,
                      s->n2,          s->pp,
                      s->eta_app,     s->micro.theta_e,
                      s->g.xx,        s->g.yy,
                      s->g.xy,        s->micro.fabric_gap,
                      s->micro.b_min, (double)s->segment};
    if (lub_h5_table_append(st->tab, st->step++, s->time, row)) {
        st->io_error = 1;
        return 1;
    }
    if (s->gd != 0.0) {
        if (s->eta_app < st->eta_min) {
            st->eta_min = s->eta_app;
            st->strain_min = s->strain;
        }
        if (s->eta_app > st->eta_max) {
            st->eta_max = s->eta_app;
            st->strain_max = s->strain;
        }
    }
    st->last = *s;
    lub_progress_update(st->ctx->progress, (double)(s->segment + 1) / (double)(st->nseg + 1),
                        st->step);
    return (st->ctx->stop_requested && *st->ctx->stop_requested) ? 1 : 0;
}

static int rheo_run(const json_t *resolved, lub_run_ctx *ctx)
{
    lub_segment segs[RHEO_MAX_SEGMENTS];
    lub_error err;
    json_t *spec = json_deep_copy(resolved);
    lub_texture_params tp;
    const char *set, *init;
    long long ns;
    int nseg;
    if (!spec || read_params(spec, &tp, &set, &err) ||
        lub_spec_enum(spec, "", "initial_state", NULL, "rest", &init, &err) ||
        read_protocol(spec, segs, &nseg, &err) ||
        lub_spec_integer(spec, "", "samples_per_segment", 2, 100000, 1, 200, &ns, &err)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "resolved spec rejected: %s: %s",
                 err.pointer, err.message);
        json_decref(spec);
        return LUB_EXIT_INTERNAL;
    }
    lub_texture_state g0 = {0, 0, 0};
    int s0 = 1;
    if (strcmp(init, "steady_positive") == 0)
        g0 = lub_texture_steady_state(&tp, +1);
    else if (strcmp(init, "steady_negative") == 0) {
        g0 = lub_texture_steady_state(&tp, -1);
        s0 = -1;
    }
    json_t *model =
        json_pack("{s:s, s:f, s:f, s:f, s:f, s:f, s:f, s:f, s:f}", "set", set, "a", tp.a, "delta1",
                  tp.delta1, "delta2", tp.delta2, "beta1", tp.beta1, "beta2", tp.beta2, "beta3",
                  tp.beta3, "eta", tp.eta, "eta_e", tp.eta_e);
    const int m3_laws = strcmp(set, "m3_laws") == 0; /* set points into spec */
    json_decref(spec);

    static const char *names[14] = {"strain",
                                    "shear_rate",
                                    "shear_stress",
                                    "N1",
                                    "N2",
                                    "particle_pressure",
                                    "apparent_viscosity",
                                    "depletion_angle",
                                    "gamma_e_xx",
                                    "gamma_e_yy",
                                    "gamma_e_xy",
                                    "fabric_gap",
                                    "b_e_min",
                                    "segment"};
    static const char *units[14] = {"1",   "1/s", "Pa", "Pa", "Pa", "Pa", "Pa.s",
                                    "rad", "1",   "1",  "1",  "1",  "1",  "1"};
    static const int ncomp[14] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
    rheo_sink_state st = {.ctx = ctx,
                          .nseg = nseg,
                          .eta_min = INFINITY,
                          .eta_max = -INFINITY,
                          .strain_min = NAN,
                          .strain_max = NAN};
    st.tab = lub_h5_set_units(ctx->out, "s", NULL, NULL, NULL) == 0
                 ? lub_h5_table_create(ctx->out, 14, names, ncomp, units)
                 : NULL;
    if (!st.tab) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        json_decref(model);
        return LUB_EXIT_IO;
    }
    lub_rheo_error rerr;
    memset(&rerr, 0, sizeof rerr);
    int rc = lub_rheo_run(&tp, g0, s0, segs, nseg, (int)ns, rheo_sink, &st, &rerr);
    lub_progress_last_step(ctx->progress, st.step);
    json_object_set_new(ctx->summary_extra, "model_parameters", model);
    json_object_set_new(
        ctx->summary_extra, "active_terms",
        json_pack("[s, s]",
                  tp.a == 1.0 ? "texture_upper_convected_M3" : "texture_gordon_schowalter_M4",
                  "exact_strain_solution"));
    json_object_set_new(ctx->summary_extra, "units",
                        json_pack("{s:s, s:s, s:s, s:s}", "stress", "Pa", "viscosity", "Pa.s",
                                  "time", "s", "angle", "rad (summary: deg where named _deg)"));
    json_object_set_new(ctx->summary_extra, "steps", json_integer(st.step));
    json_object_set_new(ctx->summary_extra, "simulated_time", json_real(st.last.time));
    if (st.io_error) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }
    if (rc < 0) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "/protocol/%d: %s", rerr.segment,
                 rerr.message);
        return LUB_EXIT_NUMERICAL;
    }
    lub_texture_stress ss = lub_texture_steady_stress(&tp);
    if (m3_laws) {
        /* the M3 laws outside the range of their fit (since 2026-12-07) */
        double phi =
            json_number_value(json_object_get(json_object_get(resolved, "parameters"), "phi"));
        if (phi < LUB_M3_LAWS_PHI_FIT_MIN || phi > LUB_M3_LAWS_PHI_FIT_MAX) {
            char w[400], v[40];
            snprintf(w, sizeof w,
                     "/parameters/phi: %s is outside 0.30 ... 0.50, the range on which the "
                     "thesis fitted the M3 laws (3.10), (3.16) (Table 3.2, Fig. 3.11): the "
                     "parameters are extrapolated; towards phi -> 0 the stresses diverge like "
                     "1/phi^2 (beta -> beta_bar while alpha -> 0)",
                     lub_real_text(phi, v));
            lub_summary_warn(ctx, w);
        }
    }
    if (!isfinite(ss.eta_app) || !isfinite(ss.n1) || !isfinite(ss.n2) || !isfinite(ss.pp)) {
        /* beyond the doubles (they are computed without intermediate overflow) */
        lub_summary_warn(ctx,
                         "/parameters/eta_e: the closed-form steady values (eta_app_steady, "
                         "N1/N2/pp_steady_per_rate) exceed the largest double and are reported "
                         "null: they scale with eta_e, times the beta terms over Delta^2 "
                         "(Delta = 1 - a^2 + delta1^2); lower /parameters/eta_e or the betas");
    }
    lub_summary_put(ctx, "eta_app_steady", ss.eta_app, NAN, "Pa.s");
    lub_summary_put(ctx, "N1_steady_per_rate", ss.n1, NAN, "Pa.s");
    lub_summary_put(ctx, "N2_steady_per_rate", ss.n2, NAN, "Pa.s");
    lub_summary_put(ctx, "pp_steady_per_rate", ss.pp, NAN, "Pa.s");
    lub_summary_put(ctx, "theta_e_steady_deg", 0.5 * atan(tp.delta1) * 180.0 / PI_, NAN, "deg");
    lub_summary_put(ctx, "eta_app_min", st.eta_min, NAN, "Pa.s");
    lub_summary_put(ctx, "strain_at_eta_app_min", st.strain_min, NAN, "1");
    lub_summary_put(ctx, "eta_app_max", st.eta_max, NAN, "Pa.s");
    lub_summary_put(ctx, "strain_at_eta_app_max", st.strain_max, NAN, "1");
    lub_summary_put(ctx, "strain_total", st.last.strain, NAN, "1");
    lub_summary_put(ctx, "time_total", st.last.time, NAN, "s");
    lub_summary_put(ctx, "eta_app_final", st.last.eta_app, NAN, "Pa.s");
    lub_summary_put(ctx, "sigma_xy_final", st.last.sigma_xy, NAN, "Pa");
    lub_summary_put(ctx, "N1_final", st.last.n1, NAN, "Pa");
    lub_summary_put(ctx, "N2_final", st.last.n2, NAN, "Pa");
    lub_summary_put(ctx, "particle_pressure_final", st.last.pp, NAN, "Pa");
    lub_summary_put(ctx, "theta_e_final_deg", st.last.micro.theta_e * 180.0 / PI_, NAN, "deg");
    return rc == 1 ? LUB_EXIT_INTERRUPTED : LUB_EXIT_OK;
}

const lub_scene lub_scene_continuum_rheometer = {
    .name = "continuum_rheometer",
    .title = "Texture-tensor rheometer (Ozenda M3/M4): start-up, reversal, pause, imposed rate or "
             "stress",
    .description =
        "0-D simple shear of the texture-tensor models of Ozenda's thesis (M3: chapter 3, "
        "upper-convected; M4: chapter 4, Gordon-Schowalter with all Hand stress terms), with the "
        "errata of the note applied (sign of (4.4c), (3.14), depletion angle). Parameters from "
        "the thesis laws (3.16)/(4.9), the per-phi Tables 3.2/4.2, or explicit. The protocol is "
        "a list of segments at imposed shear rate, imposed shear stress, pause or sinusoidal "
        "rate (LAOS), each ending after a strain or a duration. Exact strain-space solution per "
        "segment; imposed stress "
        "through the exact time map t = int eta_app dgamma/|sigma|. SI units. Outputs vs time "
        "and strain: shear rate, shear stress, N1, N2, particle pressure, apparent viscosity, "
        "depletion angle, gamma_e, fabric gap, min eigenvalue of b_e.",
    .resolve = rheo_resolve,
    .run = rheo_run,
};

/* scene_sbm_resuspension.c — "sbm_resuspension": steady viscous-resuspension profile from the
 * suspension balance model (the SBM predictor for the DEM "resuspension" scene).
 *
 * eta_ii(phi(y)) = (1/Sh) int_y^inf phi, Sh = eta0 gd/(drho g a), y in units of a
 * (physics-reference §4; seed 000 eqs (3)-(6)); solved exactly (continuum_sbm_resuspension.h).
 * Spec (schema/sbm_resuspension.schema.json):
 *   law: {"kind": "dem_seed", "mu_m" = 0.5, "phi_rcp" = 0.64}        (default kind)
 *      | {"kind": "boyer" | "zarraga" | "morris_boulay"}              (presets, seed 000 L1450)
 *      | {"kind": "power_law", "lambda", "n" (> 1), "phi_m"}         (user eta = lambda s^n)
 *      | {"kind": "ozenda_m4", "phi_m" = 0.58}                       (-N2/(eta0 gd) of M4)
 *   direction: "gradient" (eta_22, default) | "vorticity" (eta_33)
 *   shields (> 0, default 0.1), inventory (int phi dy / a, > 0, default 20), phi0 = 0.55 (settled
 * fraction, for h0 and the Acrivos number), points = 401. Outputs: /profiles/y, phi, Phi (= int_y
 * phi), eta_law (eta_ii(phi(y))), eta_from_profile
 * ((1/Sh) int_y phi by the trapezoidal rule on the output grid: the DEM seed's estimator);
 * /profiles/y_uniform, phi_uniform (linear interpolation of an 8x finer exact grid).
 * Summary: height, phi_bottom, expansion h/h0, Acrivos number, closed form for power laws.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "continuum_sbm_resuspension.h"
#include "json_text.h"
#include "run_context.h"
#include "scene.h"

typedef struct {
    lub_normal_law law;
    const char *kind;
    double shields, inventory, phi0;
    long long points;
} rs_params;

static const lub_range OPEN01 = {0.0, 1.0, 1, 1};
/* smallest power-law exponent: DBL_MIN^(n-1) <= 1e-3 (see rs_read) */
#define RS_N_MIN 1.01
/* the solver's height against the power law's closed form (they agree to 1e-9 in test_sbm) */
#define RS_CLOSED_FORM_TOL 1e-6

static int rs_read(json_t *spec, rs_params *p, lub_error *err)
{
    static const char *keys[] = {"scene",     "law",  "direction", "shields",
                                 "inventory", "phi0", "points",    NULL};
    static const char *kinds[] = {"dem_seed",  "boyer",     "zarraga", "morris_boulay",
                                  "power_law", "ozenda_m4", NULL};
    static const char *dirs[] = {"gradient", "vorticity", NULL};
    const char *dir;
    if (lub_spec_only_keys(spec, "", keys, err))
        return -1;
    json_t *law = lub_spec_object(spec, "", "law", err);
    if (!law || lub_spec_enum(law, "/law", "kind", kinds, "dem_seed", &p->kind, err) ||
        lub_spec_enum(spec, "", "direction", dirs, "gradient", &dir, err))
        return -1;
    int direction = strcmp(dir, "gradient") == 0 ? 2 : 3;
    memset(&p->law, 0, sizeof p->law);
    p->law.direction = direction;
    const char *k = p->kind;
    if (strcmp(k, "dem_seed") == 0) {
        static const char *lk[] = {"kind", "mu_m", "phi_rcp", NULL};
        double mu;
        p->law.kind = LUB_NLAW_DEM_SEED;
        if (lub_spec_only_keys(law, "/law", lk, err) ||
            lub_spec_number(law, "/law", "mu_m", LUB_NONNEGATIVE, 1, 0.5, &mu, err) ||
            lub_spec_number(law, "/law", "phi_rcp", OPEN01, 1, 0.64, &p->law.phi_rcp, err))
            return -1;
        p->law.phi_m = lub_dem_phi_m(mu);
    } else if (strcmp(k, "power_law") == 0) {
        static const char *lk[] = {"kind", "lambda", "n", "phi_m", NULL};
        p->law.kind = LUB_NLAW_POWER;
        if (lub_spec_only_keys(law, "/law", lk, err) ||
            lub_spec_number(law, "/law", "lambda", LUB_POSITIVE, 0, 0, &p->law.lambda, err) ||
            lub_spec_number(law, "/law", "n", (lub_range){1.0, 100.0, 1, 0}, 0, 0, &p->law.n,
                            err) ||
            lub_spec_number(law, "/law", "phi_m", OPEN01, 0, 0, &p->law.phi_m, err))
            return -1;
        char got[40];
        if (p->law.n < RS_N_MIN)
            return lub_fail(err, "/law/n",
                            "must be in [1.01, 100] (got %s): the height of the dilute tail "
                            "grows as s^(n-1)/(n-1) as s = phi/(phi_m - phi) -> 0, and below "
                            "n = 1.01 more than 0.1%% of it lies where phi is below the smallest "
                            "normal double (2.2e-308^(n-1) > 1e-3), which the profile cannot "
                            "represent (n -> 1 gives an unbounded height)",
                            lub_real_text(p->law.n, got));
    } else if (strcmp(k, "ozenda_m4") == 0) {
        static const char *lk[] = {"kind", "phi_m", NULL};
        p->law.kind = LUB_NLAW_OZENDA_M4;
        p->law.m4 = lub_m4_laws_thesis();
        if (lub_spec_only_keys(law, "/law", lk, err) ||
            lub_spec_number(law, "/law", "phi_m", OPEN01, 1, 0.58, &p->law.phi_m, err))
            return -1;
        if (direction == 3)
            return lub_fail(err, "/direction",
                            "the ozenda_m4 closure has eta_33 = 0 (tau_zz = 0): no resuspension "
                            "along the vorticity direction; use \"gradient\"");
    } else {
        static const char *lk[] = {"kind", NULL};
        if (lub_spec_only_keys(law, "/law", lk, err))
            return -1;
        lub_normal_law_preset(k, direction, &p->law);
    }
    if (lub_spec_number(spec, "", "shields", (lub_range){0.0, 1e12, 1, 0}, 1, 0.1, &p->shields,
                        err) ||
        lub_spec_number(spec, "", "inventory", (lub_range){0.0, 1e12, 1, 0}, 1, 20.0, &p->inventory,
                        err) ||
        lub_spec_number(spec, "", "phi0", OPEN01, 1, 0.55, &p->phi0, err) ||
        lub_spec_integer(spec, "", "points", 2, 1000000, 1, 401, &p->points, err))
        return -1;
    /* the normal viscosity at the bottom (until 2026-12-07 its overflow exited 3 blaming /law) */
    if (!isfinite(p->inventory / p->shields))
        return lub_fail(err, "/shields",
                        "inventory / shields (the normal viscosity at the bottom) overflows a "
                        "double: raise /shields or lower /inventory");
    return 0;
}

static int rs_resolve(json_t *spec, lub_error *err)
{
    rs_params p;
    return rs_read(spec, &p, err);
}

/* The bound of the quadratures (continuum_sbm_resuspension.h): 2^20 panels (about a second
 * of the DEM-seed law) plus 64 per interval of the two profiles, where a law whose values stay
 * normal doubles takes 3 to 4 per interval and about 200 for the height. */
static long long rs_panel_bound(int n, int nf) { return (1LL << 20) + 64LL * (n + nf); }

/* After the quadratures gave up (work->status): exit 5 for a stop request (nothing is written:
 * the profile is computed whole), else exit 3 with what failed and which member to change. */
static int rs_work_failed(lub_run_ctx *ctx, const lub_resusp_work *work, const rs_params *p)
{
    json_object_set_new(ctx->summary_extra, "steps", json_integer(0));
    json_object_set_new(ctx->summary_extra, "simulated_time", json_real(0.0));
    lub_progress_last_step(ctx->progress, 0);
    if (work->status == LUB_RESUSP_STOPPED) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "stopped by a signal while the profile was computed: no results (the profile "
                 "is computed whole)");
        return LUB_EXIT_INTERRUPTED;
    }
    const char *underflow = work->underflow ? ", where the law's values underflow (below the "
                                              "smallest normal double)"
                                            : "";
    if (p->law.kind == LUB_NLAW_POWER && p->law.n < 1.05)
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "/law/n: the quadrature of the profile gave up after %lld panels (its bound) "
                 "without converging%s: a power law with n = %g needs the substitution exponent "
                 "ceil(1/(n - 1)) in s = s_b v^m, and v^(m-1) underflows; raise /law/n",
                 work->panels, underflow, p->law.n);
    else
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "/inventory: the quadrature of the profile gave up after %lld panels (its bound) "
                 "without converging%s: the normal viscosity at the floor, /inventory over "
                 "/shields = %g, is too small for it; raise /inventory or lower /shields",
                 work->panels, underflow, p->inventory / p->shields);
    return LUB_EXIT_NUMERICAL;
}

static int rs_run(const json_t *resolved, lub_run_ctx *ctx)
{
    rs_params p;
    lub_error err;
    json_t *spec = json_deep_copy(resolved);
    int bad = !spec || rs_read(spec, &p, &err);
    if (bad) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "resolved spec rejected: %s: %s",
                 err.pointer, err.message);
        json_decref(spec);
        return LUB_EXIT_INTERNAL;
    }
    char kind[32];
    snprintf(kind, sizeof kind, "%s", p.kind); /* p.kind points into spec */
    json_decref(spec);
    const int n = (int)p.points, nf = 8 * (n - 1) + 1;
    lub_resusp r;
    lub_resusp_work work = {.max_panels = rs_panel_bound(n, nf), .stop = ctx->stop_requested};
    const char *why = NULL;
    if (lub_resusp_solve_bounded(&p.law, p.shields, p.inventory, &work, &r, &why)) {
        if (work.status)
            return rs_work_failed(ctx, &work, &p);
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "/law: %s", why);
        return LUB_EXIT_NUMERICAL;
    }
    double *y = malloc(sizeof(double) * (size_t)n * 5);
    double *fy = malloc(sizeof(double) * (size_t)nf * 2);
    double *uy = malloc(sizeof(double) * (size_t)n * 2);
    if (!y || !fy || !uy) {
        free(y);
        free(fy);
        free(uy);
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory");
        return LUB_EXIT_INTERNAL;
    }
    /* sub-arrays only once the blocks exist (arithmetic on a null pointer is undefined) */
    double *phi = y + n, *Phi = y + 2 * n, *eta_law = y + 3 * n, *eta_prof = y + 4 * n;
    double *fphi = fy + nf, *uphi = uy + n;
    lub_resusp_profile(&p.law, &r, n, y, phi);
    if (!work.status)
        lub_resusp_profile(&p.law, &r, nf, fy, fphi);
    if (work.status) {
        free(y);
        free(fy);
        free(uy);
        return rs_work_failed(ctx, &work, &p);
    }
    double acc = 0.0;
    eta_prof[n - 1] = 0.0;
    for (int k = n - 1; k >= 0; --k) {
        if (k < n - 1)
            acc += 0.5 * (phi[k] + phi[k + 1]) * (y[k + 1] - y[k]);
        eta_prof[k] = acc / p.shields;
        double s = phi[k] / (p.law.phi_m - phi[k]);
        eta_law[k] = lub_normal_law_eta_s(&p.law, s);
        Phi[k] = p.shields * eta_law[k];
    }
    for (int i = 0, j = 0; i < n; ++i) {
        double yi = r.height * i / (n - 1);
        while (j < nf - 2 && fy[j + 1] < yi)
            ++j;
        double w = fy[j + 1] > fy[j] ? (yi - fy[j]) / (fy[j + 1] - fy[j]) : 0.0;
        w = fmin(1.0, fmax(0.0, w));
        uy[i] = yi;
        uphi[i] = (1.0 - w) * fphi[j] + w * fphi[j + 1];
    }
    double mass = 0.0;
    for (int k = 1; k < n; ++k)
        mass += 0.5 * (phi[k] + phi[k - 1]) * (y[k] - y[k - 1]);
    double eta_prof0 = eta_prof[0];
    double h0 = p.inventory / p.phi0, hc = NAN;
    if (p.law.kind == LUB_NLAW_POWER) {
        double nn = p.law.n, lam = p.law.lambda,
               s0 = pow(p.inventory / (p.shields * lam), 1.0 / nn);
        hc = nn * p.shields * lam / p.law.phi_m * (pow(s0, nn - 1) / (nn - 1) + pow(s0, nn) / nn);
    }
    /* never a result that disagrees with the power law's closed form, or a null mass check */
    if (!isfinite(mass) || !isfinite(eta_prof0) ||
        (p.law.kind == LUB_NLAW_POWER && !(fabs(r.height / hc - 1.0) <= RS_CLOSED_FORM_TOL))) {
        free(y);
        free(fy);
        free(uy);
        json_object_set_new(ctx->summary_extra, "steps", json_integer(0));
        json_object_set_new(ctx->summary_extra, "simulated_time", json_real(0.0));
        lub_progress_last_step(ctx->progress, 0);
        /* a power law near n = 1 strains the quadrature (raise n); otherwise the profile's
         * scale has left the doubles (lambda, inventory/shields far from 1) */
        const int power = p.law.kind == LUB_NLAW_POWER, near_one = power && p.law.n < 1.05;
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "%s: the profile failed its checks (height %.10g, closed form %.10g, relative "
                 "tolerance %g; trapezoid mass %.10g for the inventory %.10g)%s",
                 near_one ? "/law/n" : (power ? "/law/lambda" : "/inventory"), r.height, hc,
                 RS_CLOSED_FORM_TOL, mass, p.inventory,
                 near_one ? ": raise /law/n"
                          : (power ? ": the height or its closed form left the range of a double; "
                                     "bring /law/lambda and /inventory over /shields nearer 1"
                                   : ": change /inventory or /shields"));
        return LUB_EXIT_NUMERICAL;
    }
    const char *names[7] = {"y",         "phi",        "Phi", "eta_law", "eta_from_profile",
                            "y_uniform", "phi_uniform"};
    const double *data[7] = {y, phi, Phi, eta_law, eta_prof, uy, uphi};
    const char *units[7] = {"a", "1", "a", "1", "1", "a", "1"};
    int64_t dims[1] = {n};
    int io = 0;
    for (int q = 0; q < 7 && !io; ++q)
        io = lub_h5_write_array(ctx->out, names[q], 1, dims, data[q], units[q]);
    free(y);
    free(fy);
    free(uy);
    if (io) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }
    lub_summary_put(ctx, "height", r.height, NAN, "a");
    lub_summary_put(ctx, "phi_bottom", r.phi_bottom, NAN, "1");
    lub_summary_put(ctx, "phi_m", p.law.phi_m, NAN, "1");
    lub_summary_put(ctx, "height_over_packed", r.height * p.law.phi_m / p.inventory, NAN, "1");
    lub_summary_put(ctx, "h0", h0, NAN, "a");
    lub_summary_put(ctx, "expansion", r.height / h0, NAN, "1");
    lub_summary_put(ctx, "acrivos", 4.5 * p.shields / h0, NAN, "1");
    lub_summary_put(ctx, "mass_trapezoid_rel_error", mass / p.inventory - 1.0, NAN, "1");
    lub_summary_put(ctx, "eta_bottom_from_profile_rel_error",
                    eta_prof0 / (p.inventory / p.shields) - 1.0, NAN, "1");
    if (p.law.kind == LUB_NLAW_POWER) {
        lub_summary_put(ctx, "height_closed_form", hc, NAN, "a");
        lub_summary_put(ctx, "lambda", p.law.lambda, NAN, "1");
        lub_summary_put(ctx, "n", p.law.n, NAN, "1");
    }
    json_object_set_new(ctx->summary_extra, "active_terms",
                        json_pack("[s, s]", "sbm_zero_flux_balance", kind));
    json_object_set_new(ctx->summary_extra, "units",
                        json_pack("{s:s, s:s}", "length", "a (particle radius)", "shields",
                                  "Sh = eta0 gd/(drho g a)"));
    json_object_set_new(ctx->summary_extra, "steps", json_integer(n));
    json_object_set_new(ctx->summary_extra, "simulated_time", json_real(0.0));
    lub_progress_last_step(ctx->progress, n);
    return LUB_EXIT_OK;
}

const lub_scene lub_scene_sbm_resuspension = {
    .name = "sbm_resuspension",
    .title = "Steady viscous resuspension profile from the suspension balance model",
    .description =
        "Zero-flux SBM balance eta_ii(phi(y)) = (1/Sh) int_y^inf phi dy' (y in units of the "
        "particle radius a, Sh = eta0 gd/(drho g a)), solved exactly for the floor fraction, the "
        "profile phi(y) and the resuspended height, given the inventory int phi dy / a. Normal "
        "viscosity along the gradient (eta_22) or vorticity (eta_33): DEM-seed laws, Boyer, "
        "Zarraga, Morris-Boulay presets, a user power law lambda (psi/(1-psi))^n, or -N2/(eta0 gd) "
        "of Ozenda's M4 model.",
    .resolve = rs_resolve,
    .run = rs_run,
};

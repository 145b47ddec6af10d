/* scene_sbm_channel.c — "sbm_channel": steady shear-induced migration in a pressure-driven pipe
 * or plane channel with the congestion cap psi <= psi* of Ozenda's chapter 5 (central plug with
 * contact pressure p_c). Steady reduction of (5.19), continuum_sbm_channel.h.
 *
 * Spec (schema/sbm_channel.schema.json):
 *   geometry: "pipe" (default) | "channel"
 *   closure: {"kind": "m4", "phi_m" = 0.58}                                (default kind)
 *          | {"kind": "morris_miller", "K_s" = 0.1, "K_n" = 0.75, "lambda_grad" = 0.8,
 *             "lambda_vort" = 0.5, "phi_m" = 0.68}
 *          | {"kind": "dem_seed", "mu_m" = 0.5, "phi_rcp" = 0.64}
 *   psi_star = 0.95 (cap), psi_mean = 0.5 (< psi_star), inventory: "area" | "flux",
 *   cells = 1000.
 * Outputs: /profiles/x (r/R or y/H), psi, phi, u (units of the mean velocity), p_c (eta0 U/R),
 * eta_rel (eta_app/eta0). Summary: plug edge, wall/centre psi, pressure gradient (eta0 U/R^2) and
 * its ratio to the Newtonian one, area and flux-weighted means, p_c at the axis.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "continuum_sbm_channel.h"
#include "json_text.h"
#include "run_context.h"
#include "scene.h"

typedef struct {
    lub_closure cl;
    lub_channel_setup setup;
    const char *kind, *geom;
} ch_params;

static const lub_range OPEN01 = {0.0, 1.0, 1, 1};

static int ch_read(json_t *spec, ch_params *p, lub_error *err)
{
    static const char *keys[] = {"scene",    "geometry",  "closure", "psi_star",
                                 "psi_mean", "inventory", "cells",   NULL};
    static const char *geoms[] = {"pipe", "channel", NULL};
    static const char *kinds[] = {"m4", "morris_miller", "dem_seed", NULL};
    static const char *invs[] = {"area", "flux", NULL};
    const char *inv;
    long long cells;
    memset(p, 0, sizeof *p);
    if (lub_spec_only_keys(spec, "", keys, err) ||
        lub_spec_enum(spec, "", "geometry", geoms, "pipe", &p->geom, err))
        return -1;
    json_t *c = lub_spec_object(spec, "", "closure", err);
    if (!c || lub_spec_enum(c, "/closure", "kind", kinds, "m4", &p->kind, err))
        return -1;
    if (strcmp(p->kind, "m4") == 0) {
        static const char *k[] = {"kind", "phi_m", NULL};
        p->cl.kind = LUB_CLOSURE_M4;
        p->cl.m4 = lub_m4_laws_thesis();
        if (lub_spec_only_keys(c, "/closure", k, err) ||
            lub_spec_number(c, "/closure", "phi_m", OPEN01, 1, 0.58, &p->cl.m4_phi_m, err))
            return -1;
    } else if (strcmp(p->kind, "morris_miller") == 0) {
        static const char *k[] = {"kind",        "K_s",   "K_n", "lambda_grad",
                                  "lambda_vort", "phi_m", NULL};
        lub_mm_params *m = &p->cl.mm;
        p->cl.kind = LUB_CLOSURE_MM;
        if (lub_spec_only_keys(c, "/closure", k, err) ||
            lub_spec_number(c, "/closure", "K_s", LUB_NONNEGATIVE, 1, 0.1, &m->K_s, err) ||
            lub_spec_number(c, "/closure", "K_n", LUB_POSITIVE, 1, 0.75, &m->K_n, err) ||
            lub_spec_number(c, "/closure", "lambda_grad", LUB_POSITIVE, 1, 0.8, &m->lambda_grad,
                            err) ||
            lub_spec_number(c, "/closure", "lambda_vort", LUB_NONNEGATIVE, 1, 0.5, &m->lambda_vort,
                            err) ||
            lub_spec_number(c, "/closure", "phi_m", OPEN01, 1, 0.68, &m->phi_m, err))
            return -1;
        if (!(m->lambda_vort < 2.0 * m->lambda_grad))
            return lub_fail(err, "/closure/lambda_vort",
                            "must be < 2 lambda_grad (otherwise no central plug can form: "
                            "A_r ~ r^(lambda_vort/lambda_grad - 2))");
    } else {
        static const char *k[] = {"kind", "mu_m", "phi_rcp", NULL};
        double mu;
        p->cl.kind = LUB_CLOSURE_DEM;
        if (lub_spec_only_keys(c, "/closure", k, err) ||
            lub_spec_number(c, "/closure", "mu_m", LUB_NONNEGATIVE, 1, 0.5, &mu, err) ||
            lub_spec_number(c, "/closure", "phi_rcp", OPEN01, 1, 0.64, &p->cl.dem_phi_rcp, err))
            return -1;
        p->cl.dem_phi_m = lub_dem_phi_m(mu);
    }
    lub_channel_setup *S = &p->setup;
    if (lub_spec_number(spec, "", "psi_star", OPEN01, 1, 0.95, &S->psi_star, err) ||
        lub_spec_number(spec, "", "psi_mean", OPEN01, 1, 0.5, &S->psi_mean, err) ||
        lub_spec_enum(spec, "", "inventory", invs, "area", &inv, err) ||
        lub_spec_integer(spec, "", "cells", 4, 1000000, 1, 1000, &cells, err))
        return -1;
    char star[40], mean[40];
    if (!(S->psi_mean < S->psi_star))
        return lub_fail(err, "/psi_mean", "must be < psi_star = %s (got %s)",
                        lub_real_text(S->psi_star, star), lub_real_text(S->psi_mean, mean));
    S->geom = strcmp(p->geom, "pipe") == 0 ? LUB_GEOM_PIPE : LUB_GEOM_CHANNEL;
    S->flux_weighted = strcmp(inv, "flux") == 0;
    S->n = (int)cells;
    return 0;
}

static int ch_resolve(json_t *spec, lub_error *err)
{
    ch_params p;
    return ch_read(spec, &p, err);
}

static int ch_run(const json_t *resolved, lub_run_ctx *ctx)
{
    ch_params p;
    lub_error err;
    json_t *spec = json_deep_copy(resolved);
    if (!spec || ch_read(spec, &p, &err)) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "resolved spec rejected: %s: %s",
                 err.pointer, err.message);
        json_decref(spec);
        return LUB_EXIT_INTERNAL;
    }
    char kind[32], geom[16];
    snprintf(kind, sizeof kind, "%s", p.kind);
    snprintf(geom, sizeof geom, "%s", p.geom);
    json_decref(spec);
    const int n = p.setup.n;
    double *buf = malloc(sizeof(double) * (size_t)n * 6);
    if (!buf) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory");
        return LUB_EXIT_INTERNAL;
    }
    double *x = buf, *psi = buf + n, *u = buf + 2 * n, *pc = buf + 3 * n, *er = buf + 4 * n,
           *phi = buf + 5 * n;
    lub_channel_result R;
    const char *why = NULL;
    p.setup.stop = ctx->stop_requested;
    const int solved = lub_channel_solve(&p.cl, &p.setup, x, psi, u, pc, er, &R, &why);
    if (solved == -2) { /* a stop request: the profile is solved whole or not at all */
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "stopped by a signal while the profile was solved: no results (the profile is "
                 "solved whole)");
        free(buf);
        json_object_set_new(ctx->summary_extra, "steps", json_integer(0));
        json_object_set_new(ctx->summary_extra, "simulated_time", json_real(0.0));
        lub_progress_last_step(ctx->progress, 0);
        return LUB_EXIT_INTERRUPTED;
    }
    if (solved == -3) { /* the closest profile misses the inventory: no results */
        const double got = p.setup.flux_weighted ? R.psi_flux : R.psi_area;
        /* above the request: the smallest mean the wall constant's bracket reaches (a closure
         * whose A_r vanishes steeply, like the DEM seed's psi^9, at a small psi_mean); below
         * it: in a pipe where lambda_33 = A_th/A_r of the DEM closure exceeds 2, |A_r| decreases
         * towards the axis and the mean jumps past psi_mean as the wall constant varies */
        const int too_high = got > p.setup.psi_mean;
        const int dem_pipe =
            !too_high && p.cl.kind == LUB_CLOSURE_DEM && p.setup.geom == LUB_GEOM_PIPE;
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                 "%s: %s: the closest profile has the %s mean psi %.10g against psi_mean = %.10g "
                 "(tolerance %g)%s",
                 dem_pipe ? "/closure/phi_rcp" : "/psi_mean", why,
                 p.setup.flux_weighted ? "flux-weighted" : "area", got, p.setup.psi_mean,
                 LUB_CHANNEL_INVENTORY_TOL,
                 too_high   ? ": no profile of this closure has a mean that small; raise /psi_mean"
                 : dem_pipe ? " (in a pipe, where lambda_33 = A_th/A_r of the DEM closure exceeds "
                              "2, |A_r| decreases towards the axis and the mean jumps past "
                              "psi_mean as the wall constant varies): raise /closure/phi_rcp or "
                              "lower /psi_mean"
                            : ": lower /psi_mean");
        free(buf);
        json_object_set_new(ctx->summary_extra, "steps", json_integer(0));
        json_object_set_new(ctx->summary_extra, "simulated_time", json_real(0.0));
        lub_progress_last_step(ctx->progress, 0);
        return LUB_EXIT_NUMERICAL;
    }
    if (solved) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "/closure: %s", why);
        free(buf);
        return LUB_EXIT_NUMERICAL;
    }
    double phim = lub_closure_phi_m(&p.cl);
    for (int i = 0; i < n; ++i)
        phi[i] = psi[i] * phim;
    const char *names[6] = {"x", "psi", "u", "p_c", "eta_rel", "phi"};
    const char *units[6] = {"R", "1", "U (mean velocity)", "eta0 U/R", "1", "1"};
    int64_t dims[1] = {n};
    int io = 0;
    for (int q = 0; q < 6 && !io; ++q)
        io = lub_h5_write_array(ctx->out, names[q], 1, dims, buf + (size_t)q * n, units[q]);
    free(buf);
    if (io) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
        return LUB_EXIT_IO;
    }
    lub_summary_put(ctx, "plug_edge", R.x_plug, NAN, "R");
    lub_summary_put(ctx, "psi_wall", R.psi_wall, NAN, "1");
    lub_summary_put(ctx, "psi_centre", R.psi_centre, NAN, "1");
    lub_summary_put(ctx, "psi_area_mean", R.psi_area, NAN, "1");
    lub_summary_put(ctx, "psi_flux_mean", R.psi_flux, NAN, "1");
    lub_summary_put(ctx, "pressure_gradient", R.G, NAN, "eta0 U/R^2");
    lub_summary_put(ctx, "pressure_gradient_over_newtonian", R.G / R.G_newtonian, NAN, "1");
    lub_summary_put(ctx, "p_c_centre", R.pc_centre, NAN, "eta0 U/R");
    lub_summary_put(ctx, "wall_constant", R.q, NAN, "1");
    lub_summary_put(ctx, "phi_m", phim, NAN, "1");
    json_object_set_new(ctx->summary_extra, "active_terms",
                        json_pack("[s, s, s]", "sbm_steady_migration", kind, geom));
    json_object_set_new(ctx->summary_extra, "units",
                        json_pack("{s:s, s:s, s:s}", "length",
                                  "R (pipe radius or channel half-width)", "velocity",
                                  "U (mean velocity)", "pressure", "eta0 U/R"));
    json_object_set_new(ctx->summary_extra, "steps", json_integer(n));
    json_object_set_new(ctx->summary_extra, "simulated_time", json_real(0.0));
    lub_progress_last_step(ctx->progress, n);
    return LUB_EXIT_OK;
}

const lub_scene lub_scene_sbm_channel = {
    .name = "sbm_channel",
    .title = "Steady shear-induced migration in a pipe or channel with a congested plug",
    .description =
        "Steady reduction of Ozenda's chapter-5 pipe problem (5.19): radial particle balance "
        "d(r^2 A_r)/dr = r A_th (pipe) or A_r y = const (channel) with A_i = tau_ii/(eta_app "
        "|gd|), a central plug at the cap psi* carrying a contact pressure p_c, and the "
        "inventory (area or flux-weighted mean psi) fixing the one free constant. Closures: "
        "Ozenda M4 (N2 only), Miller-Morris SBM, DEM-seed laws. Dimensionless (R, mean "
        "velocity U, eta0).",
    .resolve = ch_resolve,
    .run = ch_run,
};

/* scene_continuum_steady_curves.c — "continuum_steady_curves": steady simple-shear rheology
 * against psi = phi/phi_m for the texture models of Ozenda's thesis (M4 laws (4.9) + Table 4.1,
 * M3 laws (3.10)/(3.16) + Table 3.3), the Miller–Morris SBM closure and the DEM-seed laws, side
 * by side; plus the per-phi thesis fits (Tables 3.2 and 4.2) as points.
 *
 * Spec (schema/continuum_steady_curves.schema.json): psi_min (0.05), psi_max (0.95),
 * points (19), report_psi (0.8), m4_phi_m (0.58, Einstein term only), m3_eta0 (1.03 Pa.s),
 * dem_mu_m (0.5), dem_phi_rcp (0.64), mm {K_s 0.1, K_n 0.75, lambda_grad 0.8, lambda_vort 0.5,
 * phi_m 0.68}. Outputs: /profiles/<model>_<quantity> over /profiles/psi (dimensionless:
 * eta_rel = sigma_xy/(eta0 gd), alpha1 = N1/sigma_xy, alpha2 = N2/sigma_xy, pp_rel =
 * p_p/sigma_xy, eta_n2 = -N2/(eta0 gd), theta_e in rad); /profiles/m3_table and m4_table rows
 * [phi, eta_app (Pa.s), N1/|gd|, N2/|gd|, p_p/|gd| (Pa.s), theta_e (rad)]; summary at report_psi.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "continuum_steady_curves.h"
#include "continuum_texture_laws.h"
#include "json_text.h"
#include "run_context.h"
#include "scene.h"

#define PI_ 3.14159265358979323846

typedef struct {
    double psi_min, psi_max, report_psi, m4_phi_m, m3_eta0, dem_mu_m, dem_phi_rcp;
    long long points;
    lub_mm_params mm;
} sc_params;

static const lub_range OPEN01 = {0.0, 1.0, 1, 1};
#define SC_PSI_LOW 1e-34     /* smallest psi_min and report_psi (sc_read) */
#define SC_PHI_RCP_LOW 1e-40 /* smallest dem_phi_rcp (sc_read) */

static int sc_read(json_t *spec, sc_params *p, lub_error *err)
{
    static const char *keys[] = {"scene",       "psi_min",  "psi_max", "points",
                                 "report_psi",  "m4_phi_m", "m3_eta0", "dem_mu_m",
                                 "dem_phi_rcp", "mm",       NULL};
    static const char *mk[] = {"K_s", "K_n", "lambda_grad", "lambda_vort", "phi_m", NULL};
    if (lub_spec_only_keys(spec, "", keys, err) ||
        lub_spec_number(spec, "", "psi_min", OPEN01, 1, 0.05, &p->psi_min, err) ||
        lub_spec_number(spec, "", "psi_max", OPEN01, 1, 0.95, &p->psi_max, err) ||
        lub_spec_integer(spec, "", "points", 2, 1000000, 1, 19, &p->points, err) ||
        lub_spec_number(spec, "", "report_psi", OPEN01, 1, 0.8, &p->report_psi, err) ||
        lub_spec_number(spec, "", "m4_phi_m", OPEN01, 1, 0.58, &p->m4_phi_m, err) ||
        /* >= 1e-100: the laws' eta0 x (small factors near psi -> 1) must stay normal doubles
         * (until 2026-12-07 > 0: 1e-320 exited 3 naming /psi_min) */
        lub_spec_number(spec, "", "m3_eta0", (lub_range){1e-100, INFINITY, 0, 0}, 1, 1.03,
                        &p->m3_eta0, err) ||
        lub_spec_number(spec, "", "dem_mu_m", LUB_NONNEGATIVE, 1, 0.5, &p->dem_mu_m, err) ||
        lub_spec_number(spec, "", "dem_phi_rcp", OPEN01, 1, 0.64, &p->dem_phi_rcp, err))
        return -1;
    json_t *mm = lub_spec_object(spec, "", "mm", err);
    if (!mm || lub_spec_only_keys(mm, "/mm", mk, err) ||
        lub_spec_number(mm, "/mm", "K_s", LUB_NONNEGATIVE, 1, 0.1, &p->mm.K_s, err) ||
        lub_spec_number(mm, "/mm", "K_n", LUB_NONNEGATIVE, 1, 0.75, &p->mm.K_n, err) ||
        lub_spec_number(mm, "/mm", "lambda_grad", LUB_NONNEGATIVE, 1, 0.8, &p->mm.lambda_grad,
                        err) ||
        lub_spec_number(mm, "/mm", "lambda_vort", LUB_NONNEGATIVE, 1, 0.5, &p->mm.lambda_vort,
                        err) ||
        lub_spec_number(mm, "/mm", "phi_m", OPEN01, 1, 0.68, &p->mm.phi_m, err))
        return -1;
    char hi[40], lo[40];
    /* the DEM seed's eta_22 ~ psi^9 leaves the normal doubles below psi = DBL_MIN^(1/9) = 6e-35,
     * and mu = eta_r/eta_22 overflows */
    if (p->psi_min < SC_PSI_LOW)
        return lub_fail(err, "/psi_min",
                        "must be >= 1e-34 (got %s): the DEM seed's eta_22 ~ psi^9 is below the "
                        "smallest normal double under psi = 6e-35, and mu = eta_r/eta_22 "
                        "overflows",
                        lub_real_text(p->psi_min, lo));
    if (p->report_psi < SC_PSI_LOW)
        return lub_fail(err, "/report_psi",
                        "must be >= 1e-34 like /psi_min (got %s): below it the DEM seed's eta_22 ~ "
                        "psi^9 underflows, and the M3 laws overflow further down",
                        lub_real_text(p->report_psi, lo));
    /* lambda_33 = u^7.5/(1e-3 + u^6) with u = phi/phi_rcp <= 1/phi_rcp: u^7.5 overflows a double
     * (1.8e308) for u > 1.26e41 */
    if (p->dem_phi_rcp < SC_PHI_RCP_LOW)
        return lub_fail(err, "/dem_phi_rcp",
                        "must be >= 1e-40 (got %s): lambda_33 = u^7.5/(1e-3 + u^6) with u = "
                        "phi/dem_phi_rcp overflows a double (u^7.5 > 1.8e308) for u > 1.26e41",
                        lub_real_text(p->dem_phi_rcp, lo));
    if (!(p->psi_max > p->psi_min))
        return lub_fail(err, "/psi_max", "must be > psi_min (got %s <= %s)",
                        lub_real_text(p->psi_max, hi), lub_real_text(p->psi_min, lo));
    return 0;
}

static int sc_resolve(json_t *spec, lub_error *err)
{
    sc_params p;
    return sc_read(spec, &p, err);
}

enum { NQ = 22 };

/* The M3 columns outside the phi range of the laws' fit (LUB_M3_LAWS_PHI_FIT_MIN/MAX) are
 * extrapolated: a warning naming the member that takes them there (since 2026-12-07) */
static void sc_warn_m3_range(lub_run_ctx *ctx, const sc_params *p, double phi_m)
{
    const double lo = LUB_M3_LAWS_PHI_FIT_MIN / phi_m, hi = LUB_M3_LAWS_PHI_FIT_MAX / phi_m;
    const char *member = p->psi_min < lo ? "/psi_min" : (p->psi_max > hi ? "/psi_max" : NULL);
    char w[2][480];
    int n = 0;
    if (member)
        snprintf(w[n++], sizeof w[0],
                 "%s: the M3 columns (m3_*) outside psi = %.3f ... %.3f (phi = 0.30 ... 0.50, "
                 "the range on which the thesis fitted the M3 laws (3.10), (3.16): Table 3.2, "
                 "Fig. 3.11) are extrapolated; towards psi -> 0 m3_eta_rel diverges like 1/psi^2 "
                 "(beta -> beta_bar while alpha -> 0) and is not monotone in psi",
                 member, lo, hi);
    if (p->report_psi < lo || p->report_psi > hi)
        snprintf(w[n++], sizeof w[0],
                 "/report_psi: the M3 headline numbers (m3_*) at psi = %.6g are extrapolated "
                 "outside psi = %.3f ... %.3f, the range of the M3 laws' fit (phi = 0.30 ... 0.50)",
                 p->report_psi, lo, hi);
    for (int i = 0; i < n; ++i)
        lub_summary_warn(ctx, w[i]);
}

static int sc_run(const json_t *resolved, lub_run_ctx *ctx)
{
    sc_params p;
    lub_error err;
    json_t *spec = json_deep_copy(resolved);
    int bad = !spec || sc_read(spec, &p, &err);
    json_decref(spec);
    if (bad) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "resolved spec rejected: %s: %s",
                 err.pointer, err.message);
        return LUB_EXIT_INTERNAL;
    }
    const int n = (int)p.points;
    static const char *qn[NQ] = {
        "psi",          "m4_eta_rel", "m4_alpha1",  "m4_alpha2", "m4_pp_rel",  "m4_theta_e",
        "m4_eta_n2",    "m3_eta_rel", "m3_alpha1",  "m3_pp_rel", "m3_theta_e", "mm_eta_rel",
        "mm_alpha1",    "mm_alpha2",  "mm_pp_rel",  "dem_phi",   "dem_eta_r",  "dem_eta22",
        "dem_lambda33", "dem_alpha2", "dem_eta_n2", "dem_mu"};
    static const char *qu[NQ] = {"1", "1", "1", "1", "1", "rad", "1", "1", "1", "1", "rad",
                                 "1", "1", "1", "1", "1", "1",   "1", "1", "1", "1", "1"};
    double *buf = malloc(sizeof(double) * (size_t)n * NQ);
    if (!buf) {
        snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "out of memory");
        return LUB_EXIT_INTERNAL;
    }
    lub_m4_laws L4 = lub_m4_laws_thesis();
    lub_m3_laws L3 = lub_m3_laws_thesis();
    double dem_phim = lub_dem_phi_m(p.dem_mu_m);
    for (int i = 0; i < n; ++i) {
        if (ctx->stop_requested && *ctx->stop_requested) { /* the curves are written whole */
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                     "stopped by a signal after %d of the %d points: no results (the curves are "
                     "written whole)",
                     i, n);
            free(buf);
            json_object_set_new(ctx->summary_extra, "steps", json_integer(i));
            json_object_set_new(ctx->summary_extra, "simulated_time", json_real(0.0));
            lub_progress_last_step(ctx->progress, i);
            return LUB_EXIT_INTERRUPTED;
        }
        if ((i & 1023) == 0)
            lub_progress_update(ctx->progress, (double)i / (double)n, i);
        double psi = p.psi_min + (p.psi_max - p.psi_min) * i / (n - 1);
        lub_steady_row a, b, c;
        lub_steady_dem_row d;
        const char *why;
        if (lub_steady_m4(&L4, psi, p.m4_phi_m, &a, &why) ||
            lub_steady_m3(&L3, psi, p.m3_eta0, &b, &why) || lub_steady_mm(&p.mm, psi, &c, &why) ||
            lub_steady_dem(psi, dem_phim, p.dem_phi_rcp, &d, &why)) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "psi = %.17g: %s", psi, why);
            free(buf);
            return LUB_EXIT_NUMERICAL;
        }
        double v[NQ] = {psi,        a.eta_rel, a.alpha1, a.alpha2, a.pp_rel,  a.theta_e,
                        a.eta_n2,   b.eta_rel, b.alpha1, b.pp_rel, b.theta_e, c.eta_rel,
                        c.alpha1,   c.alpha2,  c.pp_rel, d.phi,    d.eta_r,   d.eta22,
                        d.lambda33, d.alpha2,  d.eta_n2, d.mu};
        for (int q = 0; q < NQ; ++q) {
            if (!isfinite(v[q])) {
                snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                         "%s: %s not finite at psi = %.17g",
                         strncmp(qn[q], "dem_", 4) == 0 && strstr(qn[q], "lambda33")
                             ? "/dem_phi_rcp"
                             : (psi < 0.5 ? "/psi_min" : "/psi_max"),
                         qn[q], psi);
                free(buf);
                return LUB_EXIT_NUMERICAL;
            }
            buf[(size_t)q * n + i] = v[q];
        }
    }
    int64_t dims[2] = {n, 6};
    for (int q = 0; q < NQ; ++q)
        if (lub_h5_write_array(ctx->out, qn[q], 1, dims, buf + (size_t)q * n, qu[q])) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
            free(buf);
            return LUB_EXIT_IO;
        }
    free(buf);
    /* thesis per-phi fits */
    double tab[5 * 6];
    for (int m = 0; m < 2; ++m) {
        for (int i = 0; i < 5; ++i) {
            lub_texture_params tp;
            const char *why;
            double phi = lub_texture_table_phi(i);
            if (m == 0)
                lub_m3_table32(phi, &tp, NULL, &why);
            else
                lub_m4_table42(phi, &tp, NULL, &why);
            lub_texture_stress s = lub_texture_steady_stress(&tp);
            double row[6] = {phi, s.eta_app, s.n1, s.n2, s.pp, 0.5 * atan(tp.delta1)};
            memcpy(tab + 6 * i, row, sizeof row);
        }
        dims[0] = 5;
        if (lub_h5_write_array(ctx->out, m == 0 ? "m3_table" : "m4_table", 2, dims, tab,
                               "[phi, Pa.s, Pa.s, Pa.s, Pa.s, rad]")) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic, "%s", lub_h5_last_error(ctx->out));
            return LUB_EXIT_IO;
        }
    }
    /* headline numbers at report_psi */
    lub_steady_row a, b, c;
    lub_steady_dem_row d;
    const char *why;
    double rp = p.report_psi;
    lub_steady_m4(&L4, rp, p.m4_phi_m, &a, &why);
    lub_steady_m3(&L3, rp, p.m3_eta0, &b, &why);
    lub_steady_mm(&p.mm, rp, &c, &why);
    lub_steady_dem(rp, dem_phim, p.dem_phi_rcp, &d, &why);
    const double head[18] = {a.eta_rel, a.alpha1, a.alpha2, a.pp_rel,   a.eta_n2,  a.theta_e,
                             b.eta_rel, b.alpha1, b.pp_rel, b.theta_e,  c.eta_rel, c.alpha1,
                             c.alpha2,  d.eta_r,  d.eta22,  d.lambda33, d.alpha2,  d.eta_n2};
    for (int q = 0; q < 18; ++q)
        if (!isfinite(head[q])) {
            snprintf(ctx->diagnostic, sizeof ctx->diagnostic,
                     "/report_psi: a headline number is not finite at report_psi = %.17g; move "
                     "/report_psi into the range of the laws",
                     rp);
            return LUB_EXIT_NUMERICAL;
        }
    sc_warn_m3_range(ctx, &p, L3.phi_m);
    lub_summary_put(ctx, "m4_eta_rel", a.eta_rel, NAN, "1");
    lub_summary_put(ctx, "m4_alpha1", a.alpha1, NAN, "1");
    lub_summary_put(ctx, "m4_alpha2", a.alpha2, NAN, "1");
    lub_summary_put(ctx, "m4_pp_rel", a.pp_rel, NAN, "1");
    lub_summary_put(ctx, "m4_eta_n2", a.eta_n2, NAN, "1");
    lub_summary_put(ctx, "m4_theta_e_deg", a.theta_e * 180 / PI_, NAN, "deg");
    lub_summary_put(ctx, "m3_eta_rel", b.eta_rel, NAN, "1");
    lub_summary_put(ctx, "m3_alpha1", b.alpha1, NAN, "1");
    lub_summary_put(ctx, "m3_pp_rel", b.pp_rel, NAN, "1");
    lub_summary_put(ctx, "m3_theta_e_deg", b.theta_e * 180 / PI_, NAN, "deg");
    lub_summary_put(ctx, "mm_eta_rel", c.eta_rel, NAN, "1");
    lub_summary_put(ctx, "mm_alpha1", c.alpha1, NAN, "1");
    lub_summary_put(ctx, "mm_alpha2", c.alpha2, NAN, "1");
    lub_summary_put(ctx, "dem_phi_m", dem_phim, NAN, "1");
    lub_summary_put(ctx, "dem_eta_r", d.eta_r, NAN, "1");
    lub_summary_put(ctx, "dem_eta22", d.eta22, NAN, "1");
    lub_summary_put(ctx, "dem_lambda33", d.lambda33, NAN, "1");
    lub_summary_put(ctx, "dem_alpha2", d.alpha2, NAN, "1");
    lub_summary_put(ctx, "dem_eta_n2", d.eta_n2, NAN, "1");
    double e1, a2, pp;
    lub_steady_m4_limits(&L4, &e1, &a2, &pp);
    lub_summary_put(ctx, "m4_eta1_bar_limit", e1, NAN, "1");
    lub_summary_put(ctx, "m4_alpha2_limit", a2, NAN, "1");
    lub_summary_put(ctx, "m4_pp_rel_limit", pp, NAN, "1");
    lub_summary_put(ctx, "m4_c2_small_psi", lub_steady_m4_c2(&L4), NAN, "1");
    json_object_set_new(ctx->summary_extra, "active_terms",
                        json_pack("[s, s, s, s]", "texture_M4_laws_4.9", "texture_M3_laws_3.16",
                                  "sbm_miller_morris", "dem_seed_laws"));
    json_object_set_new(ctx->summary_extra, "units",
                        json_pack("{s:s, s:s}", "reduced",
                                  "eta_rel = sigma_xy/(eta0 gd); "
                                  "alpha_i = N_i/sigma_xy; pp_rel = p_p/sigma_xy",
                                  "tables", "Pa.s per unit |gd| (thesis eta0)"));
    json_object_set_new(ctx->summary_extra, "steps", json_integer(n));
    json_object_set_new(ctx->summary_extra, "simulated_time", json_real(0.0));
    lub_progress_last_step(ctx->progress, n);
    return LUB_EXIT_OK;
}

const lub_scene lub_scene_continuum_steady_curves = {
    .name = "continuum_steady_curves",
    .title =
        "Steady rheology vs psi = phi/phi_m: Ozenda M4/M3 laws, Miller-Morris SBM, DEM-seed laws",
    .description =
        "Closed-form steady simple-shear predictions against the reduced fraction psi: apparent "
        "viscosity, N1/sigma, N2/sigma, particle pressure and depletion angle of Ozenda's "
        "texture models (chapter 4: (4.7) with laws (4.9), Table 4.1; chapter 3: (3.8) with "
        "(3.10)/(3.16), Table 3.3), of the Miller-Morris SBM closure, and of the DEM-seed laws "
        "(eta_r, eta_22, lambda_33), side by side; plus the per-phi fits of Tables 3.2 and 4.2. "
        "Dimensionless (reduced by eta0 gd or sigma_xy).",
    .resolve = sc_resolve,
    .run = sc_run,
};

/* test_sbm.c — SBM steady solvers: resuspension (continuum-check.py case I, closed forms for
 * every power law, DEM-seed and M4 laws, domain errors, the bound on the quadratures' work and
 * the stop request) and pipe/channel migration (case H). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "continuum_sbm_channel.h"
#include "continuum_sbm_resuspension.h"

/* closed form for eta = lambda s^n: h = (n Sh lambda/phi_m)(s0^{n-1}/(n-1) + s0^n/n) */
static double h_power(double lam, double n, double phim, double sh, double inv)
{
    double s0 = pow(inv / (sh * lam), 1.0 / n);
    return n * sh * lam / phim * (pow(s0, n - 1) / (n - 1) + pow(s0, n) / n);
}

static double mass(const lub_normal_law *L, const lub_resusp *r, int n)
{
    static double y[20001], phi[20001];
    lub_resusp_profile(L, r, n, y, phi);
    double m = 0.0;
    for (int k = 1; k < n; ++k)
        m += 0.5 * (phi[k] + phi[k - 1]) * (y[k] - y[k - 1]);
    return m;
}

static void resuspension(void)
{
    lub_normal_law L;
    lub_resusp r;
    const char *why = NULL;
    /* continuum-check.py case I: "Sh = 0.01" there multiplies Phi, i.e. it is 1/Sh of the
     * physics-reference definition Sh = eta0 gd/(drho g a); the same case is Sh = 100 here. */
    lub_normal_law_preset("boyer", 3, &L);
    check_true("I.solve", lub_resusp_solve(&L, 100.0, 20.0, &r, &why) == 0);
    check_near("I.height_analytic_formula", lub_resusp_height_n2(0.6, 0.585, 100.0, 20.0), 152.619,
               5e-4);
    check_near("I.height_numeric", r.height, 152.619, 5e-4);
    check_near("I.height_numeric_minus_closed_form",
               r.height - lub_resusp_height_n2(0.6, 0.585, 100.0, 20.0), 0.0, 1e-9 * r.height);
    check_near("I.bottom_phi", r.phi_bottom, 0.2141, 5e-5);
    check_near("I.mass_conservation", mass(&L, &r, 20001), 20.0, 1e-4);
    printf("I.script_euler_height_(not_a_target)=152.613\n");
    /* the same inventory at the physics-reference Sh = 0.01 (weak shear): a nearly packed bed */
    lub_resusp_solve(&L, 0.01, 20.0, &r, &why);
    check_near("I.physref_Sh0.01_height", r.height, h_power(0.6, 2, 0.585, 0.01, 20.0), 1e-9);
    printf("I.physref_Sh0.01_height=%.4f phi_bottom=%.4f\n", r.height, r.phi_bottom);
    /* user power law == preset */
    lub_normal_law P = {
        .kind = LUB_NLAW_POWER, .direction = 3, .phi_m = 0.585, .lambda = 0.6, .n = 2};
    lub_resusp rp;
    lub_resusp_solve(&P, 100.0, 20.0, &rp, &why);
    check_near("I.power_law_equals_boyer_preset", rp.height, 152.619, 5e-4);
    /* every other exponent against its closed form */
    const double ns[4] = {1.2, 1.5, 2.5, 3.0};
    char name[96];
    for (int i = 0; i < 4; ++i) {
        P.n = ns[i];
        P.lambda = 1.36;
        P.phi_m = 0.62;
        check_true("power.solve", lub_resusp_solve(&P, 0.5, 30.0, &rp, &why) == 0);
        snprintf(name, sizeof name, "power.n%.1f.height_vs_closed_form", ns[i]);
        double hr = h_power(1.36, ns[i], 0.62, 0.5, 30.0);
        check_near(name, rp.height, hr, 1e-9 * hr);
    }
    /* Zarraga preset, gradient */
    lub_normal_law_preset("zarraga", 2, &L);
    lub_resusp_solve(&L, 0.5, 30.0, &r, &why);
    check_near("zarraga.grad.height", r.height, h_power(1.36, 3, 0.62, 0.5, 30.0), 1e-9 * r.height);
    /* DEM-seed laws (mu_m = 0.5): gradient and vorticity, mass, slope dy/dPhi = -1/phi */
    lub_normal_law D = {
        .kind = LUB_NLAW_DEM_SEED, .direction = 2, .phi_m = lub_dem_phi_m(0.5), .phi_rcp = 0.64};
    for (int dir = 2; dir <= 3; ++dir) {
        D.direction = dir;
        check_true("dem.solve", lub_resusp_solve(&D, 0.05, 20.0, &r, &why) == 0);
        snprintf(name, sizeof name, "dem.dir%d.Sh0.05.inv20.height", dir);
        printf("%s=%.6f\n", name, r.height);
        snprintf(name, sizeof name, "dem.dir%d.Sh0.05.inv20.phi_bottom", dir);
        printf("%s=%.6f\n", name, r.phi_bottom);
        snprintf(name, sizeof name, "dem.dir%d.mass", dir);
        check_near(name, mass(&D, &r, 20001), 20.0, 2e-3);
        double s1 = 0.4 * r.s_bottom, s2 = 0.41 * r.s_bottom, sm = 0.405 * r.s_bottom;
        double slope = (lub_resusp_y_of_s(&D, &r, s2) - lub_resusp_y_of_s(&D, &r, s1)) /
                       (0.05 * (lub_normal_law_eta_s(&D, s2) - lub_normal_law_eta_s(&D, s1)));
        double phim = D.phi_m * sm / (1 + sm);
        snprintf(name, sizeof name, "dem.dir%d.dy_dPhi_times_phi", dir);
        check_near(name, slope * phim, -1.0, 1e-4);
        double yh = 0.5 * r.height, ph = lub_resusp_phi_at(&D, &r, yh);
        snprintf(name, sizeof name, "dem.dir%d.phi_at_half_height_roundtrip", dir);
        double sh = ph / (D.phi_m - ph);
        check_near(name, lub_resusp_y_of_s(&D, &r, sh), yh, 1e-8 * r.height);
    }
    /* Ozenda M4 closure: gradient works, vorticity is an error (eta_33 = 0) */
    lub_normal_law M = {
        .kind = LUB_NLAW_OZENDA_M4, .direction = 2, .phi_m = 0.58, .m4 = lub_m4_laws_thesis()};
    check_true("m4.grad.solve", lub_resusp_solve(&M, 0.05, 20.0, &r, &why) == 0);
    printf("m4.grad.Sh0.05.inv20.height=%.6f phi_bottom=%.6f\n", r.height, r.phi_bottom);
    M.direction = 3;
    check_true("m4.vort.error", lub_resusp_solve(&M, 0.05, 20.0, &r, &why) == -1);
    printf("m4.vort.error_message=%s\n", why);
    /* domain errors and singular limits */
    /* n near 1: the closed form (until 2026-12-06 n = 1.02, 1.03 failed: s^2 underflowed) */
    for (double nn = 1.01; nn < 1.045; nn += 0.01) {
        lub_normal_law Q = {
            .kind = LUB_NLAW_POWER, .direction = 2, .phi_m = 0.5, .lambda = 1.0, .n = nn};
        char nm[64];
        double s0 = pow(20.0 / 0.1, 1.0 / nn);
        double hc = nn * 0.1 / 0.5 * (pow(s0, nn - 1) / (nn - 1) + pow(s0, nn) / nn);
        snprintf(nm, sizeof nm, "power.n%.2f.height_over_closed_form", nn);
        check_true(nm, lub_resusp_solve(&Q, 0.1, 20.0, &rp, &why) == 0);
        check_near(nm, rp.height / hc, 1.0, 1e-9);
    }
    P.n = 1.0 + 1e-10; /* ceil(1/(n-1)) overflowed an int */
    check_true("power.n1+1e-10_error", lub_resusp_solve(&P, 0.5, 30.0, &rp, &why) == -1);
    P.n = 1.0;
    check_true("power.n1_error", lub_resusp_solve(&P, 0.5, 30.0, &rp, &why) == -1);
    P.n = 2.0;
    check_true("inventory0_error", lub_resusp_solve(&P, 0.5, 0.0, &rp, &why) == -1);
    check_true("shields0_error", lub_resusp_solve(&P, 0.0, 1.0, &rp, &why) == -1);
    D.direction = 2;
    check_true("dem.dense_bed.solve", lub_resusp_solve(&D, 1e-4, 1e4, &r, &why) == 0);
    check_true("dem.dense_bed.finite", isfinite(r.height) && r.phi_bottom < D.phi_m);
    check_near("dem.dense_bed.height_over_packed", r.height / (1e4 / D.phi_m), 1.0, 5e-3);
    check_true("dem.dilute.solve", lub_resusp_solve(&D, 1e4, 1e-3, &r, &why) == 0 &&
                                       isfinite(r.height) && r.height > 0);
}

/* contact pressure in the plug (seed 003 ch. 5): pipe dp_c/dr = G (A_r* - A_th* / 2), channel
 * dp_c/dy = G A_r* (< 0), p_c = 0 at the plug edge and beyond. Until 2026-12-07 untested: dp_c/dr
 * with A_th* instead of A_th* / 2 and an extra factor edge on p_c at the axis passed. */
static void check_pc(const char *tag, const lub_closure *c, const lub_channel_setup *S,
                     const double *x, const double *pc, const lub_channel_result *R)
{
    char name[128];
    double ar, ath, e, wpc = 0.0;
    lub_closure_eval(c, S->psi_star, &ar, &ath, &e);
    const double slope = S->geom == LUB_GEOM_PIPE ? R->G * (ar - 0.5 * ath) : R->G * ar;
    snprintf(name, sizeof name, "%s.pc_centre", tag);
    check_near(name, R->pc_centre, -slope * R->x_plug, 1e-12 * fabs(slope));
    snprintf(name, sizeof name, "%s.pc_centre_positive", tag);
    check_true(name, R->pc_centre > 0.0 && R->x_plug > 0.0);
    for (int i = 0; i < S->n; ++i)
        wpc = fmax(wpc, fabs(pc[i] - (x[i] < R->x_plug ? slope * (x[i] - R->x_plug) : 0.0)));
    snprintf(name, sizeof name, "%s.pc_profile_linear", tag);
    check_near(name, wpc, 0.0, 1e-12 * R->pc_centre);
    printf("%s.A_r_star=%.6g A_th_star=%.6g\n", tag, ar, ath);
}

static void pipe_H(void)
{
    static double x[400], psi[400], u[400], pc[400], er[400];
    lub_closure c = {.kind = LUB_CLOSURE_M4, .m4 = lub_m4_laws_thesis(), .m4_phi_m = 0.58};
    lub_channel_setup S = {.geom = LUB_GEOM_PIPE, .psi_star = 0.95, .flux_weighted = 0, .n = 400};
    const double ref[2][6] = {{0.5, 0.05300, 0.309, 0.338, 0.539, 0.574},
                              {0.6, 0.09309, 0.410, 0.407, 0.709, 0.674}};
    char name[96];
    for (int k = 0; k < 2; ++k) {
        lub_channel_result R;
        const char *why;
        S.psi_mean = ref[k][0];
        check_true("H.solve", lub_channel_solve(&c, &S, x, psi, u, pc, er, &R, &why) == 0);
        snprintf(name, sizeof name, "H.bulk%.2f.C", ref[k][0]);
        check_near(name, R.q, ref[k][1], 5e-6);
        snprintf(name, sizeof name, "H.bulk%.2f.plug_radius", ref[k][0]);
        check_near(name, R.x_plug, ref[k][2], 5e-4);
        /* the script reports its last and middle midpoints r = 0.99875 and 0.50125 */
        snprintf(name, sizeof name, "H.bulk%.2f.psi_r0.99875", ref[k][0]);
        check_near(name, psi[399], ref[k][3], 5e-4);
        snprintf(name, sizeof name, "H.bulk%.2f.psi_r0.50125", ref[k][0]);
        check_near(name, psi[200], ref[k][4], 5e-4);
        snprintf(name, sizeof name, "H.bulk%.2f.flux_weighted_psi", ref[k][0]);
        check_near(name, R.psi_flux, ref[k][5], 5e-4);
        snprintf(name, sizeof name, "H.bulk%.2f.area_mean", ref[k][0]);
        check_near(name, R.psi_area, ref[k][0], 1e-10);
        printf("H.bulk%.2f.psi_wall_exact=%.6f G_over_newtonian=%.4f pc_centre=%.5f\n", ref[k][0],
               R.psi_wall, R.G / R.G_newtonian, R.pc_centre);
        /* alpha2(psi(r)) r^2 = -C outside the plug */
        double worst = 0;
        for (int i = 0; i < 400; ++i)
            if (x[i] > R.x_plug) {
                double ar, ath, e;
                lub_closure_eval(&c, psi[i], &ar, &ath, &e);
                worst = fmax(worst, fabs(ar * x[i] * x[i] + R.q));
            }
        snprintf(name, sizeof name, "H.bulk%.2f.alpha2_r2_const", ref[k][0]);
        check_near(name, worst, 0.0, 1e-9);
        snprintf(name, sizeof name, "H.bulk%.2f", ref[k][0]);
        check_pc(name, &c, &S, x, pc, &R);
    }
}

static void other_closures(void)
{
    static double x[800], psi[800], u[800], pc[800], er[800];
    lub_channel_result R;
    const char *why;
    char name[96];
    /* Miller-Morris: |A_r| r^{2 - lambda_vort/lambda_grad} = const */
    lub_closure mm = {.kind = LUB_CLOSURE_MM, .mm = lub_mm_default()};
    lub_channel_setup S = {.geom = LUB_GEOM_PIPE, .psi_star = 0.95, .psi_mean = 0.5, .n = 800};
    check_true("MM.pipe.solve", lub_channel_solve(&mm, &S, x, psi, u, pc, er, &R, &why) == 0);
    double k = 0.5 / 0.8, worst = 0;
    for (int i = 0; i < 800; ++i)
        if (x[i] > R.x_plug) {
            double ar, ath, e;
            lub_closure_eval(&mm, psi[i], &ar, &ath, &e);
            worst = fmax(worst, fabs(-ar * pow(x[i], 2 - k) - R.q));
        }
    check_near("MM.pipe.Ar_r^(2-k)_const", worst, 0.0, 1e-9);
    printf("MM.pipe.psi_mean0.5.plug=%.4f psi_wall=%.4f\n", R.x_plug, R.psi_wall);
    check_pc("MM.pipe", &mm, &S, x, pc, &R); /* A_th* != 0 (M4's is 0) */
    /* DEM closure: variable lambda_33, RK4; check with the exact ODE residual d ln|Q|/d ln r */
    lub_closure dem = {
        .kind = LUB_CLOSURE_DEM, .dem_phi_m = lub_dem_phi_m(0.5), .dem_phi_rcp = 0.64};
    check_true("DEM.pipe.solve", lub_channel_solve(&dem, &S, x, psi, u, pc, er, &R, &why) == 0);
    check_near("DEM.pipe.area_mean", R.psi_area, 0.5, 1e-10);
    check_pc("DEM.pipe", &dem, &S, x, pc, &R);
    double res = 0;
    for (int i = 600; i < 798; ++i) {
        double a1, t1, e1, a2, t2, e2, a0, t0, e0;
        lub_closure_eval(&dem, psi[i], &a1, &t1, &e1);
        lub_closure_eval(&dem, psi[i + 2], &a2, &t2, &e2);
        lub_closure_eval(&dem, psi[i + 1], &a0, &t0, &e0);
        double d =
            (log(-a2 * x[i + 2] * x[i + 2]) - log(-a1 * x[i] * x[i])) / (log(x[i + 2]) - log(x[i]));
        res = fmax(res, fabs(d - t0 / a0));
    }
    check_near("DEM.pipe.ode_residual", res, 0.0, 1e-3);
    /* the figures of this run (until 2026-12-07 printed after the refused run below: 0 / 0.95) */
    printf("DEM.pipe.psi_mean0.5.plug=%.4f psi_wall=%.4f\n", R.x_plug, R.psi_wall);
    /* lambda_33 > 2 (phi_rcp = 0.01): no wall constant meets the inventory (until 2026-12-06
     * returned 0 with an area mean of 0.164) */
    lub_closure dem_bad = dem;
    dem_bad.dem_phi_rcp = 0.01;
    check_true("DEM.pipe.rcp0.01.inventory_not_met",
               lub_channel_solve(&dem_bad, &S, x, psi, u, pc, er, &R, &why) == -3);
    /* plane channel with M4: alpha2(psi(y)) y = const */
    lub_closure m4 = {.kind = LUB_CLOSURE_M4, .m4 = lub_m4_laws_thesis(), .m4_phi_m = 0.58};
    S.geom = LUB_GEOM_CHANNEL;
    check_true("M4.channel.solve", lub_channel_solve(&m4, &S, x, psi, u, pc, er, &R, &why) == 0);
    worst = 0;
    for (int i = 0; i < 800; ++i)
        if (x[i] > R.x_plug) {
            double ar, ath, e;
            lub_closure_eval(&m4, psi[i], &ar, &ath, &e);
            worst = fmax(worst, fabs(-ar * x[i] - R.q));
        }
    check_near("M4.channel.alpha2_y_const", worst, 0.0, 1e-9);
    check_near("M4.channel.G_newtonian", R.G_newtonian, 3.0, 0);
    check_pc("M4.channel", &m4, &S, x, pc, &R);
    printf("M4.channel.psi_mean0.5.plug=%.4f psi_wall=%.4f\n", R.x_plug, R.psi_wall);
    /* flux-weighted inventory */
    S.flux_weighted = 1;
    check_true("M4.channel.flux.solve",
               lub_channel_solve(&m4, &S, x, psi, u, pc, er, &R, &why) == 0);
    check_near("M4.channel.flux_mean", R.psi_flux, 0.5, 1e-10);
    /* Newtonian check of the velocity normalisation: dilute limit -> G ~ G_newtonian */
    S.geom = LUB_GEOM_PIPE;
    S.flux_weighted = 0;
    S.psi_mean = 1e-6;
    check_true("M4.pipe.dilute.solve",
               lub_channel_solve(&m4, &S, x, psi, u, pc, er, &R, &why) == 0);
    check_near("M4.pipe.dilute.G", R.G, 8.0, 1e-3);
    snprintf(name, sizeof name, "M4.pipe.dilute.u_axis");
    check_near(name, u[0], 2.0, 1e-3);
    /* errors */
    S.psi_mean = 0.96;
    check_true("error.psi_mean_ge_psi_star",
               lub_channel_solve(&m4, &S, x, psi, u, pc, er, &R, &why) == -1);
    S.psi_mean = 0.5;
    S.psi_star = 1.0;
    check_true("error.psi_star_1", lub_channel_solve(&m4, &S, x, psi, u, pc, er, &R, &why) == -1);
}

/* The bound on the quadratures' work and the stop request (continuum_sbm_resuspension.h,
 * continuum_sbm_channel.h): a well-behaved law gives the same profile bit for bit with a bound;
 * the DEM-seed law at inventory/Sh = 1e-259 underflows in the fine profile of the scene (3201
 * points), which took 58 s and 7.6e7 panels, and gives up at the bound instead. */
static void work_bound(void)
{
    static double y[3201], phi[3201], y0[401], phi0[401];
    lub_normal_law D = {.kind = LUB_NLAW_DEM_SEED, .direction = 2, .phi_rcp = 0.64};
    D.phi_m = lub_dem_phi_m(0.5);
    lub_resusp r, rb;
    lub_resusp_work w = {.max_panels = 1 << 20};
    const char *why = NULL;
    check_true("bound.dem.solve", lub_resusp_solve(&D, 0.05, 20.0, &r, &why) == 0 &&
                                      lub_resusp_solve_bounded(&D, 0.05, 20.0, &w, &rb, &why) == 0);
    lub_resusp_profile(&D, &r, 401, y0, phi0);
    lub_resusp_profile(&D, &rb, 401, y, phi);
    check_true("bound.dem.same_profile_bit_for_bit",
               w.status == LUB_RESUSP_OK && rb.height == r.height &&
                   memcmp(y, y0, sizeof y0) == 0 && memcmp(phi, phi0, sizeof phi0) == 0);
    printf("bound.dem.panels=%lld\n", w.panels);
    check_true("bound.dem.panels_few", w.panels > 0 && w.panels < 5000);
    lub_resusp_work u = {.max_panels = 1 << 20};
    check_true("bound.underflow.solve",
               lub_resusp_solve_bounded(&D, 0.1, 1e-260, &u, &rb, &why) == 0);
    lub_resusp_profile(&D, &rb, 3201, y, phi);
    printf("bound.underflow.panels=%lld status=%d underflow=%d\n", u.panels, u.status, u.underflow);
    check_true("bound.underflow.gives_up",
               u.status == LUB_RESUSP_BUDGET && u.panels == (1 << 20) + 1 && u.underflow);
    volatile sig_atomic_t stop = 1;
    lub_resusp_work st = {.max_panels = 1 << 20, .stop = &stop};
    check_true("bound.stop.solve", lub_resusp_solve_bounded(&D, 0.05, 20.0, &st, &rb, &why) == -1 &&
                                       st.status == LUB_RESUSP_STOPPED && st.panels == 0);
    static double x[400], psi[400], u_[400], pc[400], er[400];
    lub_closure c = {.kind = LUB_CLOSURE_M4, .m4 = lub_m4_laws_thesis(), .m4_phi_m = 0.58};
    lub_channel_setup S = {
        .geom = LUB_GEOM_PIPE, .psi_star = 0.95, .psi_mean = 0.5, .n = 400, .stop = &stop};
    lub_channel_result R;
    check_true("bound.channel.stop", lub_channel_solve(&c, &S, x, psi, u_, pc, er, &R, &why) == -2);
}

int main(void)
{
    work_bound();
    resuspension();
    pipe_H();
    other_closures();
    return check_report();
}

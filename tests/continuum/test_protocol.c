/* test_protocol.c — piecewise protocols of the texture rheometer: pauses, reversals, imposed
 * stress (time map against a direct time integration), rate independence, stress near zero,
 * sign changes, and the eta_app <= 0 error. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "check.h"
#include "continuum_protocol.h"
#include "continuum_texture_laws.h"

#define MAXS 20000
static lub_rheo_sample buf[MAXS];
static int nbuf;

static int store(void *user, const lub_rheo_sample *s)
{
    (void)user;
    if (nbuf < MAXS)
        buf[nbuf++] = *s;
    return 0;
}

static int stop_after_10(void *user, const lub_rheo_sample *s)
{
    (void)s;
    int *n = user;
    return ++*n >= 10;
}

static int run(const lub_texture_params *p, lub_texture_state g0, int s0, const lub_segment *seg,
               int n, int samples, lub_rheo_error *err)
{
    nbuf = 0;
    return lub_rheo_run(p, g0, s0, seg, n, samples, store, NULL, err);
}

static void pauses_and_reversal(void)
{
    lub_texture_params p = lub_texture_m3(sqrt(3.0), 5.0, 10.0, 10.0);
    lub_segment seg[5] = {{LUB_SEG_RATE, 2.0, 10.0, 0, 0},
                          {LUB_SEG_PAUSE, 0, 0, 3.0, 0},
                          {LUB_SEG_RATE, 2.0, 1.0, 0, 0},
                          {LUB_SEG_RATE, -0.5, 0, 4.0, 0},
                          {LUB_SEG_STRESS, 0.0, 0, 2.0, 0}};
    lub_rheo_error err;
    int samples = 101;
    check_true("pause.run", run(&p, (lub_texture_state){0, 0, 0}, 1, seg, 5, samples, &err) == 0);
    check_true("pause.count", nbuf == 5 * samples);
    const lub_rheo_sample *end1 = &buf[samples - 1], *pz = &buf[samples],
                          *pz_end = &buf[2 * samples - 1];
    const lub_rheo_sample *re = &buf[2 * samples], *rv = &buf[3 * samples], *fz = &buf[4 * samples];
    check_near("pause.sigma_zero", fabs(pz->sigma_xy) + fabs(pz_end->n1) + fabs(pz_end->pp), 0.0,
               0.0);
    check_near("pause.state_frozen",
               fabs(pz_end->g.xy - end1->g.xy) + fabs(pz_end->g.xx - end1->g.xx), 0.0, 0.0);
    check_near("pause.time_advances", pz_end->time - end1->time, 3.0, 1e-12);
    check_near("pause.strain_constant", pz_end->strain, 10.0, 1e-12);
    check_near("pause.restart_same_direction_jumps_back", re->sigma_xy, end1->sigma_xy, 1e-12);
    check_near("pause.theta_e_conserved", pz_end->micro.theta_e, end1->micro.theta_e, 0.0);
    /* reversal at -0.5/s: eta_app(0+) = eta - eta_e (1 - beta/alpha^2) = 16.6667 (steady reached)
     */
    check_near("reversal.eta_0plus", rv->eta_app, 16.6667, 5e-5);
    check_near("reversal.sigma_sign", rv->sigma_xy < 0 ? 1.0 : 0.0, 1.0, 0);
    check_near("reversal.strain_end", buf[4 * samples - 1].strain, 11.0 + 2.0, 1e-12);
    check_near("reversal.time_end", buf[4 * samples - 1].time, 5.0 + 3.0 + 0.5 + 4.0, 1e-12);
    check_near("zero_stress.frozen_strain", buf[5 * samples - 1].strain, fz->strain, 0.0);
    check_near("zero_stress.gd", buf[5 * samples - 1].gd, 0.0, 0.0);
    int ns = 0;
    check_true("sink_stop", lub_rheo_run(&p, (lub_texture_state){0, 0, 0}, 1, seg, 5, samples,
                                         stop_after_10, &ns, &err) == 1 &&
                                ns == 10);
}

/* direct time integration (RK4 in t) of (4.4) with gd = sigma/eta_app(state) */
static double time_to_strain_direct(const lub_texture_params *p, lub_texture_state g, double sigma,
                                    double gamma_end, double dt)
{
    double t = 0, gam = 0;
    int s = sigma > 0 ? 1 : -1;
    while (gam < gamma_end) {
        lub_texture_state k[4], y = g;
        double kg[4];
        for (int st = 0; st < 4; ++st) {
            double c = st == 0 ? 0 : (st == 3 ? 1.0 : 0.5);
            if (st > 0) {
                y.xx = g.xx + c * dt * k[st - 1].xx;
                y.yy = g.yy + c * dt * k[st - 1].yy;
                y.xy = g.xy + c * dt * k[st - 1].xy;
            }
            double gd = sigma / lub_texture_stress_of(p, s, y).eta_app;
            lub_texture_state r = lub_texture_rhs(p, s, y);
            k[st] = (lub_texture_state){r.xx * fabs(gd), r.yy * fabs(gd), r.xy * fabs(gd)};
            kg[st] = fabs(gd);
        }
        double dg = dt / 6 * (kg[0] + 2 * kg[1] + 2 * kg[2] + kg[3]);
        if (gam + dg > gamma_end) { /* last partial step: linear interpolation in time */
            t += dt * (gamma_end - gam) / dg;
            break;
        }
        g.xx += dt / 6 * (k[0].xx + 2 * k[1].xx + 2 * k[2].xx + k[3].xx);
        g.yy += dt / 6 * (k[0].yy + 2 * k[1].yy + 2 * k[2].yy + k[3].yy);
        g.xy += dt / 6 * (k[0].xy + 2 * k[1].xy + 2 * k[2].xy + k[3].xy);
        gam += dg;
        t += dt;
    }
    return t;
}

static void imposed_stress(void)
{
    lub_texture_params p;
    const char *why;
    lub_m4_table42(0.40, &p, NULL, &why);
    lub_texture_state g0 = lub_texture_steady_state(&p, -1);
    double sigma = 3.0;
    lub_segment seg[1] = {{LUB_SEG_STRESS, sigma, 8.0, 0, 0}};
    lub_rheo_error err;
    check_true("stress.run", run(&p, g0, -1, seg, 1, 801, &err) == 0);
    double worst = 0;
    for (int i = 0; i < nbuf; ++i) {
        lub_texture_state g = lub_texture_advance(&p, +1, g0, buf[i].strain);
        worst = fmax(worst, fabs(buf[i].eta_app - lub_texture_stress_of(&p, +1, g).eta_app));
        worst = fmax(worst, fabs(buf[i].sigma_xy - sigma));
    }
    check_near("stress.curve_equals_rate_curve_in_strain", worst, 0.0, 1e-12);
    double t_direct = time_to_strain_direct(&p, g0, sigma, 8.0, 1e-4);
    check_near("stress.time_map_vs_direct_rk4_rel", buf[nbuf - 1].time / t_direct - 1.0, 0.0, 1e-6);
    printf("stress.phi0.40.sigma3.time_to_strain8=%.9f direct=%.9f\n", buf[nbuf - 1].time,
           t_direct);
    /* duration-ended segment: round trip */
    double dg, t, bad;
    check_true("stress.strain_for_time",
               lub_rheo_strain_for_time(&p, +1, g0, sigma, 7.5, &dg, &bad) == 0);
    lub_rheo_time_for_strain(&p, +1, g0, sigma, dg, &t, &bad);
    check_near("stress.roundtrip_time", t, 7.5, 1e-10);
    /* long duration: decayed transient handled by the linear map */
    lub_rheo_strain_for_time(&p, +1, g0, sigma, 1e6, &dg, &bad);
    double ss = lub_texture_steady_stress(&p).eta_app;
    lub_rheo_time_for_strain(&p, +1, g0, sigma, 20.0, &t, &bad);
    check_near("stress.long_duration_rate", (dg - 20.0) / (1e6 - t), sigma / ss, 1e-9 * sigma / ss);
    /* stress near zero: tiny strain, finite, no NaN */
    lub_segment tiny[2] = {{LUB_SEG_STRESS, 1e-12, 0, 10.0, 0},
                           {LUB_SEG_STRESS, -1e-300, 0, 10.0, 0}};
    check_true("stress.near_zero.run", run(&p, g0, -1, tiny, 2, 11, &err) == 0);
    int fin = 1;
    for (int i = 0; i < nbuf; ++i)
        fin &= isfinite(buf[i].eta_app) && isfinite(buf[i].strain) && isfinite(buf[i].time);
    check_true("stress.near_zero.finite", fin);
    double e0 = lub_texture_stress_of(&p, +1, g0).eta_app; /* eta_app just after reversal */
    check_near("stress.near_zero.strain", buf[10].strain, 1e-11 / e0, 1e-6 * 1e-11 / e0);
    check_near("stress.near_zero.time", buf[nbuf - 1].time, 20.0, 1e-9);
    /* a strain-ended segment at a denormal stress would take an infinite time: clean error */
    lub_segment denorm[1] = {{LUB_SEG_STRESS, 1e-320, 1.0, 0, 0}};
    memset(&err, 0, sizeof err);
    check_true("stress.denormal.error", run(&p, g0, -1, denorm, 1, 11, &err) == -1);
    printf("stress.denormal.message=%s\n", err.message);
}

static void rate_independence_and_signs(void)
{
    lub_texture_params p;
    const char *why;
    lub_m4_table42(0.30, &p, NULL, &why);
    lub_segment a[1] = {{LUB_SEG_RATE, 1e-3, 5.0, 0, 0}}, b[1] = {{LUB_SEG_RATE, 1e3, 5.0, 0, 0}};
    lub_rheo_error err;
    static double ea[101];
    run(&p, (lub_texture_state){0, 0, 0}, 1, a, 1, 101, &err);
    for (int i = 0; i < 101; ++i)
        ea[i] = buf[i].eta_app;
    run(&p, (lub_texture_state){0, 0, 0}, 1, b, 1, 101, &err);
    double worst = 0, wn1 = 0;
    for (int i = 0; i < 101; ++i) {
        worst = fmax(worst, fabs(ea[i] - buf[i].eta_app));
        wn1 = fmax(wn1, fabs(buf[i].n1 / 1e3 - lub_texture_stress_of(&p, 1, buf[i].g).n1));
    }
    check_near("rate_independence.eta_app", worst, 0.0, 1e-13);
    check_near("rate_independence.N1_scales_with_gd", wn1, 0.0, 1e-9);
    /* 200 alternating sign changes with tiny strains: SPD kept, finite */
    static lub_segment alt[200];
    for (int k = 0; k < 200; ++k)
        alt[k] =
            (lub_segment){LUB_SEG_RATE, (k % 2 ? -1.0 : 1.0) * (1 + k), 1e-3 * (1 + k % 7), 0, 0};
    check_true("signs.run", run(&p, (lub_texture_state){0, 0, 0}, 1, alt, 200, 3, &err) == 0);
    int ok = 1;
    for (int i = 0; i < nbuf; ++i)
        ok &= isfinite(buf[i].sigma_xy) && buf[i].micro.b_min > 0;
    check_true("signs.finite_spd", ok);
}

/* LAOS at imposed rate: exact half-period splitting against RK4 in time of (4.4) with
 * gd = A sin(omega t) (|gd| is non-smooth at the sign changes: RK4 steps align with them) */
static void oscillation(void)
{
    lub_texture_params p;
    const char *why;
    lub_m4_table42(0.44, &p, NULL, &why);
    const double A = 2.0, f = 0.5, dur = 2.3 / f, om = 2 * 3.14159265358979323846 * f;
    lub_segment seg[1] = {{LUB_SEG_OSCILLATION, A, 0, dur, f}};
    lub_rheo_error err;
    check_true("laos.run", run(&p, (lub_texture_state){0, 0, 0}, 1, seg, 1, 2301, &err) == 0);
    lub_texture_state g = {0, 0, 0};
    const int N = 230000;
    double h = dur / N;
    for (int i = 0; i < N; ++i) {
        double t0 = i * h;
        lub_texture_state k[4], y;
        const double c[4] = {0, 0.5, 0.5, 1};
        for (int st = 0; st < 4; ++st) {
            y = g;
            if (st > 0) {
                y.xx += c[st] * h * k[st - 1].xx;
                y.yy += c[st] * h * k[st - 1].yy;
                y.xy += c[st] * h * k[st - 1].xy;
            }
            double gd = A * sin(om * (t0 + c[st] * h));
            /* sign from the half period of the step (steps never straddle a sign change) */
            int s = sin(om * (t0 + 0.5 * h)) >= 0 ? 1 : -1;
            lub_texture_state r = lub_texture_rhs(&p, s, y);
            k[st] = (lub_texture_state){r.xx * fabs(gd), r.yy * fabs(gd), r.xy * fabs(gd)};
        }
        g.xx += h / 6 * (k[0].xx + 2 * k[1].xx + 2 * k[2].xx + k[3].xx);
        g.yy += h / 6 * (k[0].yy + 2 * k[1].yy + 2 * k[2].yy + k[3].yy);
        g.xy += h / 6 * (k[0].xy + 2 * k[1].xy + 2 * k[2].xy + k[3].xy);
    }
    const lub_rheo_sample *e = &buf[nbuf - 1];
    double d = fabs(e->g.xx - g.xx) + fabs(e->g.yy - g.yy) + fabs(e->g.xy - g.xy);
    check_near("laos.final_state_vs_rk4_in_time", d, 0.0, 1e-9);
    /* strain: 4 half periods of 2A/omega + (A/omega)(1 - cos(0.6 pi)) */
    check_near("laos.total_strain", e->strain,
               A / om * (8.0 + 1.0 - cos(0.6 * 3.14159265358979323846)), 1e-12);
    check_near("laos.final_time", e->time, dur, 1e-12);
    int ok = 1;
    for (int i = 0; i < nbuf; ++i)
        ok &= isfinite(buf[i].sigma_xy) && buf[i].micro.b_min > 0 &&
              (buf[i].gd == 0 || (buf[i].sigma_xy > 0) == (buf[i].gd > 0));
    check_true("laos.finite_spd_and_stress_follows_rate_sign", ok);
    printf("laos.phi0.44.A2.f0.5.sigma_final=%.6f\n", e->sigma_xy);
}

static void negative_viscosity(void)
{
    /* delta2 very negative: eta_app < 0 at steady state -> imposed stress must fail cleanly */
    lub_texture_params p = {.a = 0.6,
                            .delta1 = 1.0,
                            .delta2 = -50.0,
                            .beta1 = 0,
                            .beta2 = 0,
                            .beta3 = 0,
                            .eta = 0.1,
                            .eta_e = 1.0};
    lub_segment seg[1] = {{LUB_SEG_STRESS, 1.0, 5.0, 0, 0}};
    lub_rheo_error err;
    memset(&err, 0, sizeof err);
    check_true("eta_negative.error",
               run(&p, (lub_texture_state){0, 0, 0}, 1, seg, 1, 51, &err) == -1);
    printf("eta_negative.message=%s\n", err.message);
    check_true("eta_negative.strain_reported", err.strain > 0 && err.strain < 5.0);
}

/* int_0^G eta_app(gamma) dgamma / sigma by composite 3-point Gauss-Legendre on panels of
 * 0.02/max(1, delta1) strain, the state from lub_texture_advance at every node (a reference
 * independent of the time map's panels, doubling and steady tail) */
static double time_ref(const lub_texture_params *p, int s, lub_texture_state g0, double sigma,
                       double G)
{
    const double x3 = sqrt(0.6);
    long n = (long)ceil(G / (0.02 / fmax(1.0, p->delta1)));
    double h = G / n, acc = 0.0;
    for (long i = 0; i < n; ++i) {
        double c = (i + 0.5) * h, e[3];
        const double at[3] = {c - 0.5 * h * x3, c, c + 0.5 * h * x3};
        for (int k = 0; k < 3; ++k)
            e[k] = lub_texture_stress_of(p, s, lub_texture_advance(p, s, g0, at[k])).eta_app;
        acc += 0.5 * h * (5.0 * e[0] + 8.0 * e[1] + 5.0 * e[2]) / 9.0;
    }
    return acc / sigma;
}

/* the time map's panel length (a GL node may sit that far past the first eta_app <= 0) */
static double sub_panel_strain(const lub_texture_params *p)
{
    return 0.1 / fmax(p->delta1, sqrt((1.0 - p->a) * (1.0 + p->a)));
}

static void time_map_bounded(void)
{
    /* M3, alpha = 1e-6, beta = 0: eta_app = 2 - e^{-alpha gamma} from rest, so the time to strain
     * G at sigma = 1 is 2 G + expm1(-alpha G)/alpha. Until 2026-12-07 the time map took panels
     * of 0.1 strain until alpha gamma > 40 (1e8 panels here: 25 s, SIGTERM unheard) */
    lub_texture_params m3 = lub_texture_m3(1e-6, 0.0, 1.0, 1.0);
    lub_segment seg[1] = {{LUB_SEG_STRESS, 1.0, 1e7, 0, 0}};
    lub_rheo_error err;
    clock_t c0 = clock();
    check_true("bounded.m3_alpha1e-6.run",
               run(&m3, (lub_texture_state){0, 0, 0}, 1, seg, 1, 2, &err) == 0);
    double took = (double)(clock() - c0) / CLOCKS_PER_SEC;
    printf("bounded.m3_alpha1e-6.strain1e7.cpu_s=%.3f\n", took);
    check_true("bounded.m3_alpha1e-6.strain1e7.under_1s", took < 1.0);
    double want = 2e7 + expm1(-10.0) / 1e-6;
    check_near("bounded.m3_alpha1e-6.strain1e7.time_rel", buf[1].time / want - 1.0, 0.0, 1e-13);
    /* M4 with a slowly damped oscillation (sqrt(1 - a^2) = 8660 delta1): the transient is
     * integrated by panel doubling; against panel-by-panel quadrature */
    lub_texture_params p = {.a = 0.5,
                            .delta1 = 1e-4,
                            .delta2 = -0.5,
                            .beta1 = 1.0,
                            .beta2 = 0.5,
                            .beta3 = 0.2,
                            .eta = 1.0,
                            .eta_e = 1.0};
    lub_texture_state g0 = lub_texture_steady_state(&p, -1);
    double t, dg, bad;
    c0 = clock();
    check_true("bounded.m4_doubling.time",
               lub_rheo_time_for_strain(&p, +1, g0, 2.0, 1e4, &t, &bad) == 0);
    took = (double)(clock() - c0) / CLOCKS_PER_SEC;
    double ref = time_ref(&p, +1, g0, 2.0, 1e4);
    check_near("bounded.m4_doubling.time_vs_panels_rel", t / ref - 1.0, 0.0, 1e-12);
    printf("bounded.m4_doubling.time=%.15g ref=%.15g cpu_s=%.4f\n", t, ref, took);
    check_true("bounded.m4_doubling.strain_for_time",
               lub_rheo_strain_for_time(&p, +1, g0, 2.0, t, &dg, &bad) == 0);
    check_near("bounded.m4_doubling.roundtrip_strain", dg, 1e4, 1e-9);
    /* a strain of 1e12, far past the transient (alpha gamma = 1e8): steady tail */
    check_true("bounded.m4_doubling.huge",
               lub_rheo_time_for_strain(&p, +1, g0, 2.0, 1e12, &t, &bad) == 0);
    double ss = lub_texture_steady_stress(&p).eta_app;
    check_near("bounded.m4_doubling.huge_rate", t * 2.0 / (1e12 * ss), 1.0, 1e-6);
    /* eta_app <= 0 found in the doubling regime (delta2 = -50: eta_ss < 0) */
    p.delta2 = -50.0;
    int rc = lub_rheo_time_for_strain(&p, +1, (lub_texture_state){0, 0, 0}, 1.0, 1e4, &t, &bad);
    check_true("bounded.m4_doubling.eta_negative_error", rc == -1);
    double scan = 0.0; /* first eta_app <= 0 on a grid of 1e-3 */
    while (lub_texture_stress_of(&p, +1,
                                 lub_texture_advance(&p, +1, (lub_texture_state){0, 0, 0}, scan))
               .eta_app > 0.0)
        scan += 1e-3;
    check_near("bounded.m4_doubling.eta_negative_at", bad, scan, sub_panel_strain(&p));
}

/* a long segment with 2 samples: the panel size matters (samples 0.01 strain apart never
 * exercised it; panels 80 times coarser passed the 1e-6 check above) */
static void time_map_long_segment(void)
{
    lub_texture_params p;
    const char *why;
    lub_m4_table42(0.40, &p, NULL, &why);
    lub_texture_state g0 = lub_texture_steady_state(&p, -1);
    lub_segment seg[1] = {{LUB_SEG_STRESS, 3.0, 8.0, 0, 0}};
    lub_rheo_error err;
    check_true("long_segment.run", run(&p, g0, -1, seg, 1, 2, &err) == 0);
    double ref = time_ref(&p, +1, g0, 3.0, 8.0);
    check_near("long_segment.time_vs_panels_rel", buf[1].time / ref - 1.0, 0.0, 1e-10);
    printf("long_segment.phi0.40.time=%.15g ref=%.15g\n", buf[1].time, ref);
}

/* signs at a negative rate: sigma_xy = gd eta_app < 0 while N1, N2 and p_p scale with |gd|
 * (steady closed forms (4.7) times |gd|), and a pause after steady shear at gd < 0 reports
 * eta_app for the negative direction (s0 = -1). Mutants S.pp = gd * st.pp and S.n2 = gd * st.n2
 * passed every test until 2026-12-07. */
static void negative_rate_signs(void)
{
    lub_texture_params p;
    const char *why;
    lub_m4_table42(0.40, &p, NULL, &why);
    lub_texture_stress ss = lub_texture_steady_stress(&p);
    lub_texture_state gm = lub_texture_steady_state(&p, -1);
    const double gd = -2.5;
    lub_segment seg[2] = {{LUB_SEG_RATE, gd, 1.0, 0, 0}, {LUB_SEG_PAUSE, 0, 0, 1.0, 0}};
    lub_rheo_error err;
    check_true("negative_rate.run", run(&p, gm, -1, seg, 2, 3, &err) == 0);
    const lub_rheo_sample *m = &buf[1], *pz = &buf[4];
    check_near("negative_rate.sigma_xy", m->sigma_xy, gd * ss.eta_app,
               1e-12 * fabs(gd * ss.eta_app));
    check_near("negative_rate.N1", m->n1, fabs(gd) * ss.n1, 1e-12 * fabs(gd * ss.n1));
    check_near("negative_rate.N2", m->n2, fabs(gd) * ss.n2, 1e-12 * fabs(gd * ss.n2));
    check_near("negative_rate.pp", m->pp, fabs(gd) * ss.pp, 1e-12 * fabs(gd * ss.pp));
    check_true("negative_rate.N2_pp_nonzero(test_has_power)",
               fabs(ss.n2) > 0.1 && fabs(ss.pp) > 0.1);
    check_near("negative_rate.pause_eta_app_negative_direction", pz->eta_app, ss.eta_app,
               1e-12 * ss.eta_app);
    /* from the steady state at gd < 0 with nothing before the pause: s0 = -1 is reported */
    lub_segment pause[1] = {{LUB_SEG_PAUSE, 0, 0, 1.0, 0}};
    check_true("negative_rate.pause_only.run", run(&p, gm, -1, pause, 1, 2, &err) == 0);
    check_near("negative_rate.pause_only.eta_app", buf[0].eta_app, ss.eta_app, 1e-12 * ss.eta_app);
    check_true("negative_rate.pause_only.differs_from_plus",
               fabs(lub_texture_stress_of(&p, +1, gm).eta_app - ss.eta_app) > 1.0);
}

int main(void)
{
    pauses_and_reversal();
    imposed_stress();
    rate_independence_and_signs();
    oscillation();
    negative_viscosity();
    time_map_bounded();
    time_map_long_segment();
    negative_rate_signs();
    return check_report();
}

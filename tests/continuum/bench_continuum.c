/* bench_continuum.c — cost of the continuum kernels (label "bench"; name=value lines). Fails
 * only if a result is not finite or a kernel returns an error. */
#include <math.h>
#include <stdio.h>
#include <time.h>

#include "continuum_protocol.h"
#include "continuum_sbm_channel.h"
#include "continuum_sbm_resuspension.h"
#include "continuum_texture_laws.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static double sink_acc;
static int sink(void *u, const lub_rheo_sample *s)
{
    (void)u;
    sink_acc += s->eta_app;
    return 0;
}

int main(void)
{
    int bad = 0;
    lub_texture_params p;
    const char *why;
    lub_m4_table42(0.44, &p, NULL, &why);
    lub_texture_state g0 = lub_texture_steady_state(&p, -1), g;
    double acc = 0, t0 = now();
    const int N = 2000000;
    for (int i = 0; i < N; ++i) {
        g = lub_texture_advance(&p, +1, g0, 1e-6 * i);
        acc += lub_texture_stress_of(&p, +1, g).eta_app;
    }
    double t1 = now();
    printf("bench.texture_advance_plus_stress_ns=%.1f\n", 1e9 * (t1 - t0) / N);
    bad |= !isfinite(acc);
    lub_segment seg[2] = {{LUB_SEG_RATE, 1.0, 8.0, 0, 0}, {LUB_SEG_STRESS, -3.0, 8.0, 0, 0}};
    lub_rheo_error err;
    t0 = now();
    for (int r = 0; r < 20; ++r)
        bad |= lub_rheo_run(&p, g0, -1, seg, 2, 1000, sink, NULL, &err) != 0;
    t1 = now();
    printf("bench.rheometer_rate_plus_stress_2x1000_samples_ms=%.3f\n", 1e3 * (t1 - t0) / 20);
    lub_normal_law D = {
        .kind = LUB_NLAW_DEM_SEED, .direction = 3, .phi_m = lub_dem_phi_m(0.5), .phi_rcp = 0.64};
    lub_resusp rr = {0};
    static double y[401], phi[401];
    t0 = now();
    for (int r = 0; r < 20; ++r) {
        bad |= lub_resusp_solve(&D, 0.05, 20.0, &rr, &why) != 0;
        lub_resusp_profile(&D, &rr, 401, y, phi);
    }
    t1 = now();
    printf("bench.resuspension_dem_401_points_ms=%.3f\n", 1e3 * (t1 - t0) / 20);
    bad |= !isfinite(rr.height);
    static double x[1000], ps[1000], u[1000], pc[1000], er[1000];
    lub_closure c = {.kind = LUB_CLOSURE_DEM, .dem_phi_m = lub_dem_phi_m(0.5), .dem_phi_rcp = 0.64};
    lub_channel_setup S = {.geom = LUB_GEOM_PIPE, .psi_star = 0.95, .psi_mean = 0.5, .n = 1000};
    lub_channel_result R;
    t0 = now();
    bad |= lub_channel_solve(&c, &S, x, ps, u, pc, er, &R, &why) != 0;
    t1 = now();
    printf("bench.pipe_dem_1000_cells_ms=%.3f\n", 1e3 * (t1 - t0));
    lub_closure m4 = {.kind = LUB_CLOSURE_M4, .m4 = lub_m4_laws_thesis(), .m4_phi_m = 0.58};
    t0 = now();
    bad |= lub_channel_solve(&m4, &S, x, ps, u, pc, er, &R, &why) != 0;
    t1 = now();
    printf("bench.pipe_m4_1000_cells_ms=%.3f\n", 1e3 * (t1 - t0));
    printf("bench.failures=%d\n", bad);
    return bad;
}

/* two_sphere_dt_sweep.c (label bench) — time-step sweep of the two-sphere scenes. For each
 * dt_safety (fraction of the elastic stability limit) prints one name=value line per run:
 *   falling_sphere: viscous rigid limit (St 0.01, stiffness 1e4, eps 0, 6 tau_c): error of the
 *     fitted rate against 8/9 and max |u/(u0 e^{-8t/9}) - 1|; rough (eps 0.01, K 100): error
 *     of the final gap against u_eq = eps a - m g/k_n;
 *   two_spheres_shear: smooth rigid, d0 = 0.5, St 1e-3, Ca 1e-6: reversibility error
 *     |y_end/d0 - 1| (analytic: 0) and the minimum gap (compared with the finest step by
 *     the plotting script);
 * plus the wall time of each run. Plot/table: two_sphere_dt_sweep.py. */
#include <stdio.h>

#include "scene_harness.h"

int main(void)
{
    const double sf[] = {1.0, 0.5, 0.25, 0.125, 0.0625};
    const int n = (int)(sizeof sf / sizeof sf[0]);
    char spec[512];
    int bad = 0;
    for (int i = 0; i < n; ++i) {
        scene_outcome a, b;
        snprintf(spec, sizeof spec,
                 "{\"scene\":\"falling_sphere\",\"St\":0.01,\"stiffness\":1e4,\"duration\":6,"
                 "\"samples\":2,\"dt_safety\":%g}",
                 sf[i]);
        scene_run_text(spec, NULL, &a);
        snprintf(spec, sizeof spec,
                 "{\"scene\":\"falling_sphere\",\"St\":0.01,\"K\":100,\"duration\":8,"
                 "\"samples\":2,\"dt_safety\":%g,\"law\":{\"eps\":0.01}}",
                 sf[i]);
        scene_run_text(spec, NULL, &b);
        printf("bench=falling_sphere dt_safety=%g dt=%.6g rate_rel_error=%.6g "
               "exp_max_rel_dev=%.6g eq_gap_rel_error=%.6g wall_s=%.4f rc=%d\n",
               sf[i], scene_value(&a, "dt"), scene_value(&a, "exp_rate_rel_error"),
               scene_value(&a, "exp_max_rel_dev"), scene_value(&b, "equilibrium_gap_rel_error"),
               a.wall_s + b.wall_s, a.rc | b.rc);
        bad |= a.rc | b.rc;
        scene_outcome_free(&a);
        scene_outcome_free(&b);
        fflush(stdout);
    }
    for (int i = 0; i < n; ++i) {
        scene_outcome a;
        snprintf(spec, sizeof spec,
                 "{\"scene\":\"two_spheres_shear\",\"St\":1e-3,\"Ca\":1e-6,\"d0\":0.5,"
                 "\"dt_safety\":%g}",
                 sf[i]);
        scene_run_text(spec, NULL, &a);
        printf("bench=two_spheres_shear dt_safety=%g dt=%.6g offset_rel_error=%.6g "
               "min_gap=%.10g wall_s=%.4f rc=%d\n",
               sf[i], scene_value(&a, "dt"), scene_value(&a, "offset_rel_change"),
               scene_value(&a, "min_gap"), a.wall_s, a.rc);
        bad |= a.rc;
        scene_outcome_free(&a);
        fflush(stdout);
    }
    return bad != 0;
}

/* test_two_spheres_physics.c (label physics) — minimum gap of smooth rigid spheres versus
 * the initial offset d0 and the lubrication cut-off (seed fig. 9). Prints the table as
 * name=value lines and checks the qualitative trends: the minimum gap saturates as d0 -> 0
 * and grows with the cut-off. */
#include <math.h>
#include <stdio.h>

#include "scene_harness.h"

int main(void)
{
    int fails = 0;
    const double cut[] = {2.0, 4.0, 7.0};
    const double d0[] = {0.3, 0.1, 0.03, 0.01};
    double g[3][4];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) {
            char spec[256];
            snprintf(spec, sizeof spec,
                     "{\"scene\":\"two_spheres_shear\",\"St\":1e-3,\"Ca\":1e-6,\"d0\":%g,"
                     "\"cutoff\":%g}",
                     d0[j], cut[i]);
            scene_outcome o;
            scene_run_text(spec, NULL, &o);
            g[i][j] = scene_value(&o, "min_gap");
            printf("cutoff=%g d0=%g min_gap=%.6g final_offset_y=%.6g wall_s=%.3f rc=%d\n", cut[i],
                   d0[j], g[i][j], scene_value(&o, "final_offset_y"), o.wall_s, o.rc);
            fails += o.rc != 0;
            scene_outcome_free(&o);
        }
    for (int i = 0; i < 3; ++i)
        fails += scene_check(fabs(g[i][3] / g[i][2] - 1) < 0.05,
                             "saturation: |g(d0=0.01)/g(d0=0.03) - 1|", fabs(g[i][3] / g[i][2] - 1),
                             0.05);
    for (int j = 0; j < 4; ++j)
        fails += scene_check(g[0][j] < g[1][j] && g[1][j] < g[2][j],
                             "min gap grows with the cut-off (g4/g2)", g[1][j] / g[0][j], 1.0);
    printf("%d failure(s)\n", fails);
    return fails != 0;
}

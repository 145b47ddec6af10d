/* hand_stress_case.c — helper of shear.hand_stress (test_hand_stress.py): one
 * lub_shear_step of a configuration read from stdin, sampling the full stress; prints the five
 * stress parts (divided by the volume, row-major F_i l_j) and the pair counts.
 *
 * stdin, whitespace-separated numbers:
 *   h00 h01 h02 h10 h11 h12 h20 h21 h22     cell matrix (columns = cell vectors)
 *   gd                                      velocity gradient L = gd e_x e_y
 *   eta k_bulk alpha k_t eps mu             law (all terms on)
 *   rho cutoff skin dt threads
 *   n, then n lines: r x y z vx' vy' vz' wx wy wz
 *     (position; velocity fluctuation v - L x; absolute spin)
 * stdout: "rc R", "counts ACTIVE CONTACTS CRUSHED SLIDING", then "NC|SC|NL|SL|KIN" lines of
 * 9 numbers each (%.17g). Exit 0, or 1 on bad input or a failed init/step. */
#include <stdio.h>
#include <stdlib.h>

#include "shear_system.h"

static int read_doubles(double *out, int n)
{
    for (int k = 0; k < n; ++k)
        if (scanf("%lf", &out[k]) != 1)
            return -1;
    return 0;
}

int main(void)
{
    double h[9], gd, lawv[6], run[5];
    int n;
    if (read_doubles(h, 9) || read_doubles(&gd, 1) || read_doubles(lawv, 6) ||
        read_doubles(run, 5) || scanf("%d", &n) != 1 || n < 2 || n > 64) {
        fprintf(stderr, "hand_stress_case: bad input\n");
        return 1;
    }
    double r[64];
    vec3 x[64], vp[64], w[64];
    for (int i = 0; i < n; ++i) {
        double row[10];
        if (read_doubles(row, 10)) {
            fprintf(stderr, "hand_stress_case: bad particle %d\n", i);
            return 1;
        }
        r[i] = row[0];
        x[i] = v3(row[1], row[2], row[3]);
        vp[i] = v3(row[4], row[5], row[6]);
        w[i] = v3(row[7], row[8], row[9]);
    }
    lub_cell cell;
    lub_cell_init_box(&cell, 1.0, 1.0, 1.0);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            cell.h[a][b] = h[3 * a + b];
    if (lub_cell_refresh(&cell)) {
        fprintf(stderr, "hand_stress_case: degenerate cell\n");
        return 1;
    }
    cell.L[0][1] = gd;
    const lub_law_params law = {.eta = lawv[0],
                                .k_bulk = lawv[1],
                                .alpha = lawv[2],
                                .k_t = lawv[3],
                                .eps = lawv[4],
                                .mu = lawv[5],
                                .terms = LUB_TERM_ALL};
    lub_shear_system s;
    int rc =
        lub_shear_init(&s, n, r, x, &cell, &law, run[0], run[1], run[2], run[3], (int)run[4], 0, 0);
    if (rc) {
        fprintf(stderr, "hand_stress_case: init %d\n", rc);
        return 1;
    }
    /* the prescribed fluctuations on top of the affine flow, and the spins */
    for (int i = 0; i < n; ++i) {
        s.v[i] = v3_add(lub_cell_mean_velocity(&s.cell, s.x[i]), vp[i]);
        s.w[i] = w[i];
    }
    lub_shear_sample smp;
    rc = lub_shear_step(&s, LUB_SAMPLE_STRESS, &smp);
    printf("rc %d\ncounts %zu %zu %zu %zu\n", rc, smp.n_active, smp.n_contacts, smp.n_crushed,
           smp.n_sliding);
    const char *name[LUB_SP_N] = {"NC", "SC", "NL", "SL", "KIN"};
    for (int p = 0; p < LUB_SP_N; ++p) {
        printf("%s", name[p]);
        for (int k = 0; k < 9; ++k)
            printf(" %.17g", smp.stress.part[p][k]);
        printf("\n");
    }
    lub_shear_free(&s);
    return rc ? 1 : 0;
}

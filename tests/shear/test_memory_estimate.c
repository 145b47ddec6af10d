/* test_memory_estimate.c — the lower bound of a shear system's memory (lub_shear_min_bytes),
 * which the run driver and the service compare with the memory a run may use before anything
 * is allocated (memory_budget.h). For packings across solid fraction, cut-off, skin,
 * polydispersity and threads, after the first steps:
 *  - the listed pairs are 0.9-8 times lub_shear_listed_pairs_estimate (1.0-1.1 measured at
 *    cut-off 2 a, more at small cut-offs where contacts dominate);
 *  - lub_shear_min_bytes <= lub_shear_memory_bytes (a bound that is not one would refuse runs
 *    that fit), and >= 0.3 of it (a bound far below would let through runs that cannot fit;
 *    0.64-0.83 at cut-off 2 a, 0.36 at 0.1 a, where contacts are most of the list), after the
 *    first neighbour-list rebuild and again after the strain that makes a second one certain
 *    (lub_shear_rebuild_strain), with the store's second buffer counted. */
#include <math.h>
#include <stdlib.h>

#include "packing.h"
#include "shear_fixture.h"
#include "shear_system.h"
#include "shear_test.h"

typedef struct {
    int n;
    double phi, cutoff, skin, radius_std;
    int threads;
    double dt_factor; /* time step over dt_elastic; many partners need less */
} estimate_case;

int main(void)
{
    const estimate_case cases[] = {
        {3000, 0.05, 2.0, 0.5, 0.05, 1, 0.3}, {3000, 0.35, 2.0, 0.5, 0.05, 1, 0.3},
        {3000, 0.50, 2.0, 0.5, 0.05, 2, 0.3}, {3000, 0.60, 2.0, 0.5, 0.20, 1, 0.3},
        {3000, 0.05, 2.0, 0.5, 0.20, 1, 0.3}, {3000, 0.55, 0.1, 0.05, 0.05, 1, 0.3},
        {3000, 0.50, 0.5, 2.0, 0.0, 1, 0.3},  {3000, 0.50, 4.0, 0.5, 0.05, 2, 0.1},
    };
    const lub_law_params law = shear_fixture_law(1e4);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        const estimate_case *c = &cases[k];
        double *r = malloc((size_t)c->n * sizeof *r);
        vec3 *x = malloc((size_t)c->n * sizeof *x);
        lub_cell cell;
        lub_packing_params pp = {.n = c->n,
                                 .phi = c->phi,
                                 .radius_std = c->radius_std,
                                 .seed = 7,
                                 .margin = 0.01,
                                 .max_sweeps = 2000000};
        lub_shear_system s;
        int rc = r && x ? lub_packing_generate(&pp, r, x, &cell, NULL) : -1;
        if (rc == 0) {
            cell.L[0][1] = 1.0;
            rc = lub_shear_init(&s, c->n, r, x, &cell, &law, 0.01, c->cutoff, c->skin, 1.0,
                                c->threads, 0, 0);
        }
        free(r);
        free(x);
        ST_CHECK(rc == 0, "case %zu: system not built (%d)", k, rc);
        if (rc)
            continue;
        s.dt = c->dt_factor * lub_shear_elastic_dt(&s);
        /* after the first rebuild (step 0), then once the strain of a certain second rebuild
         * is passed */
        const double second = lub_shear_rebuild_strain(c->cutoff, c->skin);
        for (int rebuilt = 0; rebuilt <= 1 && rc == 0; ++rebuilt) {
            for (int step = 0; rc == 0 && (rebuilt ? s.time <= second : step < 3); ++step)
                rc = lub_shear_step(&s, 0, NULL); /* L_xy = 1: time is strain */
            ST_CHECK(rc == 0, "case %zu: step failed (%d)", k, rc);
            ST_CHECK(s.rebuilds >= 1 + rebuilt, "case %zu: %ld rebuild(s) at strain %.4f", k,
                     s.rebuilds, s.time);
            const double listed = (double)s.pairs.n / c->n;
            const double expected =
                lub_shear_listed_pairs_estimate(c->phi, c->radius_std, c->cutoff, c->skin);
            const double held = (double)lub_shear_memory_bytes(&s);
            const double bound = lub_shear_min_bytes(c->n, c->phi, c->radius_std, c->cutoff,
                                                     c->skin, c->threads, rebuilt);
            printf("case %zu: n=%d phi=%.2f cut-off=%.2f skin=%.2f std=%.2f threads=%d, strain "
                   "%.4f, %ld rebuild(s): listed pairs %.2f per particle (estimate %.2f, ratio "
                   "%.3f); bound %.0f of %.0f B per particle (%.2f)\n",
                   k, c->n, c->phi, c->cutoff, c->skin, c->radius_std, c->threads, s.time,
                   s.rebuilds, listed, expected, listed / expected, bound / c->n, held / c->n,
                   bound / held);
            ST_CHECK(listed >= 0.9 * expected && listed <= 8.0 * expected,
                     "case %zu: listed %.3f against the estimate %.3f", k, listed, expected);
            ST_CHECK(bound <= held && bound >= 0.3 * held, "case %zu: bound %.0f against held %.0f",
                     k, bound, held);
        }
        lub_shear_free(&s);
    }
    /* pure and monotone: more particles, a denser packing or a longer list need more */
    const double b0 = lub_shear_min_bytes(1e6, 0.5, 0.05, 2.0, 0.5, 1, 0);
    ST_CHECK(lub_shear_min_bytes(2e6, 0.5, 0.05, 2.0, 0.5, 1, 0) == 2.0 * b0, "linear in n");
    ST_CHECK(lub_shear_min_bytes(1e6, 0.55, 0.05, 2.0, 0.5, 1, 0) > b0, "phi");
    ST_CHECK(lub_shear_min_bytes(1e6, 0.5, 0.05, 3.0, 0.5, 1, 0) > b0, "cut-off");
    ST_CHECK(lub_shear_min_bytes(1e6, 0.5, 0.05, 2.0, 0.5, 2, 0) > b0, "threads");
    ST_CHECK(lub_shear_min_bytes(1e6, 0.5, 0.05, 2.0, 0.5, 1, 1) > b0, "second buffer");
    ST_CHECK(lub_shear_listed_pairs_estimate(0.5, 0.0, 0.0, 0.0) == 0.0, "no shell, no pairs");
    ST_DONE();
}

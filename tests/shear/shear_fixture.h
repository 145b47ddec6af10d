/* shear_fixture.h — a sheared random packing for the tests/shear system tests (test_system.c,
 * test_delaunay.c): the full law at a given bulk stiffness, and a system built from a
 * lub_packing_generate packing (radius std 5 %, L_xy = 1, skin 0.5 a, dt = 0.3 of the elastic
 * time step). Static helpers: each test program gets its own copy. */
#ifndef LUBDEM_SHEAR_FIXTURE_H
#define LUBDEM_SHEAR_FIXTURE_H

#include <stdlib.h>

#include "packing.h"
#include "shear_system.h"

/* Every term on, bulk stiffness g, k_t = g/2, eps 0.02, mu 0.5. */
static inline lub_law_params shear_fixture_law(double g)
{
    lub_law_params p = {.eta = 1.0,
                        .k_bulk = g,
                        .alpha = 1.0,
                        .k_t = 0.5 * g,
                        .eps = 0.02,
                        .mu = 0.5,
                        .terms = LUB_TERM_ALL};
    return p;
}

/* n spheres at solid fraction phi (packing seed `seed`), density from St, sheared at L_xy = 1,
 * microstructure accumulators of pdf_theta x pdf_phi bins (0, 0: off). Returns 0 or the
 * packing / init error. */
static inline int shear_fixture_make_pdf(lub_shear_system *s, int n, double phi,
                                         const lub_law_params *law, double cutoff, int threads,
                                         unsigned seed, double st, int pdf_theta, int pdf_phi)
{
    double *r = malloc(n * sizeof *r);
    vec3 *x = malloc(n * sizeof *x);
    lub_cell c;
    lub_packing_params pp = {.n = n,
                             .phi = phi,
                             .radius_std = 0.05,
                             .seed = seed,
                             .margin = 0.01,
                             .max_sweeps = 2000000};
    int rc = r && x ? lub_packing_generate(&pp, r, x, &c, NULL) : -1;
    if (rc == 0) {
        c.L[0][1] = 1.0;
        rc = lub_shear_init(s, n, r, x, &c, law, st, cutoff, 0.5, 1.0, threads, pdf_theta, pdf_phi);
        if (rc == 0)
            s->dt = 0.3 * lub_shear_elastic_dt(s);
    }
    free(r);
    free(x);
    return rc;
}

/* The same without microstructure accumulators. */
static inline int shear_fixture_make(lub_shear_system *s, int n, double phi,
                                     const lub_law_params *law, double cutoff, int threads,
                                     unsigned seed, double st)
{
    return shear_fixture_make_pdf(s, n, phi, law, cutoff, threads, seed, st, 0, 0);
}

#endif

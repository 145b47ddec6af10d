/* pair_accum.c — allocation and zeroing of per-particle pair sums (see pair_accum.h). */
#include "pair_accum.h"

#include <stdlib.h>
#include <string.h>

int lub_pair_accum_init(lub_pair_accum *a, int n)
{
    memset(a, 0, sizeof *a);
    const size_t m = n > 0 ? (size_t)n : 1;
    a->f = calloc(m, sizeof *a->f);
    a->t = calloc(m, sizeof *a->t);
    a->n_active = calloc(m, sizeof *a->n_active);
    a->n_near = calloc(m, sizeof *a->n_near);
    if (!a->f || !a->t || !a->n_active || !a->n_near) {
        lub_pair_accum_free(a);
        return -1;
    }
    a->n = n;
    return 0;
}

void lub_pair_accum_free(lub_pair_accum *a)
{
    free(a->f);
    free(a->t);
    free(a->n_active);
    free(a->n_near);
    memset(a, 0, sizeof *a);
}

void lub_pair_accum_zero(lub_pair_accum *a, int p0, int p1)
{
    if (p1 <= p0)
        return;
    const size_t m = (size_t)(p1 - p0);
    memset(a->f + p0, 0, m * sizeof *a->f);
    memset(a->t + p0, 0, m * sizeof *a->t);
    memset(a->n_active + p0, 0, m * sizeof *a->n_active);
    memset(a->n_near + p0, 0, m * sizeof *a->n_near);
}

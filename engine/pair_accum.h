/* pair_accum.h — per-particle sums of pair forces, torques and interaction counts.
 *
 * The pair loops add every evaluated pair's force and torques straight into one accumulator
 * (body 1 gets +f1 and t1, body 2 gets -f1 and t2), instead of storing per-pair outputs and
 * gathering them afterwards: half the memory traffic per pair. Each thread owns one
 * accumulator (no races); the particle pass sums them in thread order. The sums of one
 * accumulator follow the pair order, so a run is reproducible for a given number of threads;
 * different thread counts agree to round-off.
 *
 * Units: those of the contact law (forces, torques). Ownership: the arrays are owned here
 * (lub_pair_accum_init / lub_pair_accum_free); nothing is allocated by zero or add.
 */
#ifndef LUBDEM_PAIR_ACCUM_H
#define LUBDEM_PAIR_ACCUM_H

#include "vec3.h"

typedef struct {
    int n;         /* number of bodies */
    vec3 *f, *t;   /* [n] force and torque sums */
    int *n_active; /* [n] pairs inside the cut-off evaluated this step */
    int *n_near;   /* [n] of which with u < a (roll/twist torques on) */
} lub_pair_accum;

/* Allocates zeroed sums for n >= 0 bodies. Returns 0, or -1 (no memory; *a is then empty and
 * may be freed). */
int lub_pair_accum_init(lub_pair_accum *a, int n);

void lub_pair_accum_free(lub_pair_accum *a);

/* Zeroes the sums of bodies p0 <= p < p1. */
void lub_pair_accum_zero(lub_pair_accum *a, int p0, int p1);

/* Adds one evaluated pair (i, j): force f1 and torque t1 on body i, -f1 and t2 on body j. */
static inline void lub_pair_accum_add(lub_pair_accum *a, int i, int j, vec3 f1, vec3 t1, vec3 t2,
                                      int near)
{
    a->f[i] = v3_add(a->f[i], f1);
    a->t[i] = v3_add(a->t[i], t1);
    a->f[j] = v3_sub(a->f[j], f1);
    a->t[j] = v3_add(a->t[j], t2);
    a->n_active[i]++;
    a->n_active[j]++;
    a->n_near[i] += near;
    a->n_near[j] += near;
}

/* Body p's sums over the accumulators all[0..team-1], added in that order (the thread order
 * that makes a run reproducible for a given thread count). */
static inline void lub_pair_accum_sum(const lub_pair_accum *all, int team, int p, vec3 *f, vec3 *t,
                                      int *n_active, int *n_near)
{
    vec3 F = all[0].f[p], T = all[0].t[p];
    int na = all[0].n_active[p], nn = all[0].n_near[p];
    for (int q = 1; q < team; ++q) {
        F = v3_add(F, all[q].f[p]);
        T = v3_add(T, all[q].t[p]);
        na += all[q].n_active[p];
        nn += all[q].n_near[p];
    }
    *f = F;
    *t = T;
    *n_active = na;
    *n_near = nn;
}

#endif

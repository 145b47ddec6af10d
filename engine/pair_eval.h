/* pair_eval.h — one step of the contact law for a stored pair of a periodic many-particle
 * system, and the per-particle gather of the pair results. Shared by the tri-periodic shear
 * system and the resuspension system so that the pair life cycle (notes §5), the image
 * velocity (notes §1.5) and the torque inertia share (contact_law.h) are written once.
 *
 * Pure with respect to everything but the pair store entries it is given (pair k's state,
 * active/near flags and f1/t1/t2), so pairs can be evaluated in parallel. No allocation.
 */
#ifndef LUBDEM_PAIR_EVAL_H
#define LUBDEM_PAIR_EVAL_H

#include "contact_batch.h"
#include "contact_law.h"
#include "pair_store.h"
#include "periodic_cell.h"

/* Per-particle state the pair kernel reads (structure of arrays, borrowed). */
typedef struct {
    const vec3 *x, *v, *w; /* positions (unwrapped), absolute velocities, spins */
    const double *r;       /* radii */
    const double *inv_i;   /* 1/I (0 for fixed bodies) */
    const int *share;      /* number of pairs among which a body's inertia is shared by the
                              stable roll/twist torque integration (values < 1 count as 1) */
} lub_pair_bodies;

/* 1/I of body p times its inertia share N_p (>= 1): the inverse inertia the law is given. */
static inline double lub_pair_inv_inertia(const lub_pair_bodies *b, int p)
{
    return b->inv_i[p] * (b->share[p] > 1 ? b->share[p] : 1);
}

enum { LUB_PAIR_OUT = -1, LUB_PAIR_OK = 0, LUB_PAIR_NONFINITE = 1 };

/* Evaluates pair k: beyond cutoff*a it leaves the cut-off (state dropped, zero outputs) and
 * LUB_PAIR_OUT is returned; otherwise it enters (fresh state if new), the law is stepped with
 * the image velocity L H c and the inertia share, and f1/t1/t2/near are stored. Returns
 * LUB_PAIR_NONFINITE (outputs not stored) if the law fails or a force/torque is not finite.
 * *o, *branch and *un receive the law output, x2 + Hc - x1 and the centre gap. */
static inline int lub_pair_eval(lub_pairs *ps, size_t k, const lub_cell *cell,
                                const lub_pair_bodies *b, const lub_law_params *law, double cutoff,
                                double dt, lub_pair_output *o, vec3 *branch, double *un)
{
    const int i = ps->i[k], j = ps->j[k];
    const vec3 shift = lub_cell_shift(cell, &ps->c[3 * k]);
    const vec3 d = v3_sub(v3_add(b->x[j], shift), b->x[i]);
    const double ri = b->r[i], rj = b->r[j];
    *branch = d;
    *un = v3_norm(d) - ri - rj;
    const double a = 0.5 * (ri + rj);
    if (*un > cutoff * a) {
        lub_pairs_leave(ps, k);
        return LUB_PAIR_OUT;
    }
    lub_pairs_enter(ps, k);
    const lub_pair_input in = {
        .branch = d,
        .v1 = b->v[i],
        .v2 = v3_add(b->v[j], lub_mat_vec(cell->L, shift)),
        .w1 = b->w[i],
        .w2 = b->w[j],
        .r1 = ri,
        .r2 = rj,
        .inv_inertia1 = lub_pair_inv_inertia(b, i),
        .inv_inertia2 = lub_pair_inv_inertia(b, j),
        .dt = dt,
    };
    if (lub_pair_step(law, &in, &ps->state[k], o) != 0 || !v3_isfinite(o->force1) ||
        !v3_isfinite(o->torque1) || !v3_isfinite(o->torque2))
        return LUB_PAIR_NONFINITE;
    ps->near[k] = o->delta < 0.0;
    ps->f1[k] = o->force1;
    ps->t1[k] = o->torque1;
    ps->t2[k] = o->torque2;
    return LUB_PAIR_OK;
}

/* Sums over the pairs of a range evaluated by lub_pair_eval_range. */
typedef struct {
    double syy;    /* sum of f1.y d.y (contact-law part of sigma_yy times the volume) */
    long contacts; /* pairs in contact (u < eps a) */
    long crushed;  /* pairs with u_n < -alpha eps a (asperities fully crushed) */
} lub_pair_range_sums;

/* Evaluates the pairs k0 <= k < k1 for a step that needs only forces and torques (no stress
 * sample): the cut-off life cycle and the image velocity per pair as in lub_pair_eval, the law
 * for the active pairs in batches of LUB_BATCH through lub_pair_step_batch (contact_batch.h),
 * and the lanes it declines through lub_pair_eval. Same stored outputs as calling
 * lub_pair_eval for every pair, to round-off. Pairs of two bodies both >= n_mobile (fixed
 * floor spheres) never interact: inactive, zero outputs. batches[2] is scratch space owned by
 * the caller (pairs are split by their last near flag so that most vector groups are
 * uniform). *sums (zeroed by the caller) receives the range's sums.
 * Returns -1, or the index of the first pair whose law failed (LUB_PAIR_NONFINITE; later pairs
 * of the range are still evaluated), with its centre gap in *fail_un. No allocation. */
long lub_pair_eval_range(lub_pairs *ps, long k0, long k1, const lub_cell *cell,
                         const lub_pair_bodies *b, const lub_law_params *law, double cutoff,
                         double dt, int n_mobile, lub_pair_batch batches[2],
                         lub_pair_range_sums *sums, double *fail_un);

/* Sums over particle p's pairs: force and torque on p, and the numbers of its active pairs
 * and of its pairs with u < a (roll/twist torques on). */
static inline void lub_pair_gather(const lub_pairs *ps, int p, vec3 *force, vec3 *torque,
                                   int *n_active, int *n_near)
{
    vec3 F = v3(0, 0, 0), T = v3(0, 0, 0);
    int na = 0, nn = 0;
    for (size_t k = ps->first1[p]; k < ps->first1[p + 1]; ++k) {
        F = v3_add(F, ps->f1[k]);
        T = v3_add(T, ps->t1[k]);
        na += ps->active[k];
        nn += ps->near[k];
    }
    for (size_t q = ps->first2[p]; q < ps->first2[p + 1]; ++q) {
        const size_t k = ps->by2[q];
        F = v3_sub(F, ps->f1[k]);
        T = v3_add(T, ps->t2[k]);
        na += ps->active[k];
        nn += ps->near[k];
    }
    *force = F;
    *torque = T;
    *n_active = na;
    *n_near = nn;
}

#endif

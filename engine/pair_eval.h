/* pair_eval.h — one step of the contact law for a stored pair of a periodic many-particle
 * system, and the per-particle gather of the pair results. Shared by the tri-periodic shear
 * system and the resuspension system so that the pair life cycle (notes §5), the image
 * velocity (notes §1.5) and the torque inertia share (contact_law.h) are written once.
 *
 * Pure with respect to everything but the pair store entries it is given (pair k's state and
 * active/near flags) and the caller's accumulator (pair_accum.h), so pairs can be evaluated in
 * parallel, one accumulator per thread. No allocation.
 */
#ifndef LUBDEM_PAIR_EVAL_H
#define LUBDEM_PAIR_EVAL_H

#include "contact_batch.h"
#include "contact_law.h"
#include "pair_accum.h"
#include "pair_store.h"
#include "periodic_cell.h"

/* Per-particle state the pair kernel reads (structure of arrays, borrowed). */
typedef struct {
    const vec3 *x, *v, *w;     /* positions (unwrapped), absolute velocities, spins */
    const double *r;           /* radii */
    const double *inv_i_share; /* 1/I times the number N >= 1 of pairs among which the body's
                                  inertia is shared by the stable roll/twist torque
                                  integration (0 for fixed bodies): lub_inertia_share() */
} lub_pair_bodies;

/* 1/I times the inertia share: share counts below 1 count as 1. */
static inline double lub_inertia_share(double inv_i, int share)
{
    return inv_i * (share > 1 ? share : 1);
}

/* The inverse inertia the law is given for body p. */
static inline double lub_pair_inv_inertia(const lub_pair_bodies *b, int p)
{
    return b->inv_i_share[p];
}

enum { LUB_PAIR_OUT = -1, LUB_PAIR_OK = 0, LUB_PAIR_NONFINITE = 1 };

/* The law's input for pair k (branch x2 + Hc - x1, the image velocity L H c, the inertia
 * shares) into *in, the centre gap into *un: LUB_PAIR_OK, or LUB_PAIR_OUT when the pair is
 * beyond cutoff*a or not allowed by the store's filter and not closer than its guard (*in then
 * holds only the branch). */
static inline int lub_pair_input_of(const lub_pairs *ps, size_t k, const lub_cell *cell,
                                    const lub_pair_bodies *b, double cutoff, double dt,
                                    lub_pair_input *in, double *un)
{
    const int i = ps->i[k], j = ps->j[k];
    const vec3 shift = lub_cell_shift(cell, &ps->c[3 * k]);
    const vec3 d = v3_sub(v3_add(b->x[j], shift), b->x[i]);
    const double ri = b->r[i], rj = b->r[j];
    in->branch = d;
    *un = v3_norm(d) - ri - rj;
    const double a = 0.5 * (ri + rj);
    if (*un > cutoff * a || (!ps->allow[k] && !(*un < ps->allow_guard * a)))
        return LUB_PAIR_OUT;
    in->v1 = b->v[i];
    in->v2 = v3_add(b->v[j], lub_mat_vec(cell->L, shift));
    in->w1 = b->w[i];
    in->w2 = b->w[j];
    in->r1 = ri;
    in->r2 = rj;
    in->inv_inertia1 = lub_pair_inv_inertia(b, i);
    in->inv_inertia2 = lub_pair_inv_inertia(b, j);
    in->dt = dt;
    return LUB_PAIR_OK;
}

/* Evaluates pair k: beyond cutoff*a (or not allowed by the store's filter and not closer than its
 * guard) it leaves the cut-off
 * (state dropped, nothing added) and LUB_PAIR_OUT is returned; otherwise it enters (fresh state if
 * new), the law is stepped with the image velocity L H c and the inertia share, the near flag is
 * stored and the force and torques are added to *acc. Returns LUB_PAIR_NONFINITE (nothing added) if
 * the law fails or a force/torque is not finite. *o, *branch and *un receive the law output, x2 +
 * Hc - x1 and the centre gap. */
static inline int lub_pair_eval(lub_pairs *ps, size_t k, const lub_cell *cell,
                                const lub_pair_bodies *b, const lub_law_params *law, double cutoff,
                                double dt, lub_pair_accum *acc, lub_pair_output *o, vec3 *branch,
                                double *un)
{
    lub_pair_input in;
    const int inside = lub_pair_input_of(ps, k, cell, b, cutoff, dt, &in, un);
    *branch = in.branch;
    if (inside == LUB_PAIR_OUT) {
        lub_pairs_leave(ps, k);
        return LUB_PAIR_OUT;
    }
    lub_pairs_enter(ps, k);
    if (lub_pair_step(law, &in, &ps->state[k], o) != 0 || !v3_isfinite(o->force1) ||
        !v3_isfinite(o->torque1) || !v3_isfinite(o->torque2))
        return LUB_PAIR_NONFINITE;
    const int near = o->delta < 0.0;
    ps->near[k] = (unsigned char)near;
    lub_pair_accum_add(acc, ps->i[k], ps->j[k], o->force1, o->torque1, o->torque2, near);
    return LUB_PAIR_OK;
}

/* Sums over the pairs of a range evaluated by lub_pair_eval_range. */
typedef struct {
    double syy;    /* sum of f1.y d.y (contact-law part of sigma_yy times the volume) */
    long contacts; /* pairs in contact (u < eps a) */
    long crushed;  /* contacts with u_n < -alpha eps a (asperities fully crushed) */
} lub_pair_range_sums;

/* Evaluates the pairs k0 <= k < k1 for a step that needs only forces and torques (no stress
 * sample): the cut-off life cycle and the image velocity per pair as in lub_pair_eval, the law
 * for the active pairs in batches of LUB_BATCH through lub_pair_step_batch (contact_batch.h),
 * and the lanes it declines through lub_pair_eval. Adds to *acc what calling lub_pair_eval for
 * every pair would add, to round-off. Pairs of two bodies both >= n_mobile (fixed floor
 * spheres) never interact: inactive, nothing added. batches[2] is scratch space owned by
 * the caller (pairs are split by their last near flag so that most vector groups are
 * uniform). *sums (zeroed by the caller) receives the range's sums.
 * Returns -1, or the index of the first pair whose law failed (LUB_PAIR_NONFINITE; later pairs
 * of the range are still evaluated), with its centre gap in *fail_un. No allocation. */
long lub_pair_eval_range(lub_pairs *ps, long k0, long k1, const lub_cell *cell,
                         const lub_pair_bodies *b, const lub_law_params *law, double cutoff,
                         double dt, int n_mobile, lub_pair_accum *acc, lub_pair_batch batches[2],
                         lub_pair_range_sums *sums, double *fail_un);

#endif

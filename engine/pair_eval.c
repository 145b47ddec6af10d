/* pair_eval.c — batched evaluation of a range of stored pairs (see pair_eval.h). */
#include "pair_eval.h"

#include "velocity_gradient.h"

#include <math.h>

#define LUB_PREFETCH_AHEAD 16 /* pairs */

/* Pair k through the scalar law (lub_pair_eval), its contributions added to *sums; the first
 * failing pair is recorded in *fail_k, *fail_un. */
static void eval_scalar(lub_pairs *ps, size_t k, const lub_cell *cell, const lub_pair_bodies *b,
                        const lub_law_params *law, double cutoff, double dt, lub_pair_accum *acc,
                        lub_pair_range_sums *sums, long *fail_k, double *fail_un)
{
    lub_pair_output o;
    vec3 d;
    double un;
    const int rc = lub_pair_eval(ps, k, cell, b, law, cutoff, dt, acc, &o, &d, &un);
    if (rc == LUB_PAIR_OK) {
        sums->syy += o.force1.y * d.y;
        sums->contacts += o.contact;
        sums->crushed += o.contact && /* crushed contacts, as the batched lanes count them */
                         un < -law->alpha * law->eps * 0.5 * (b->r[ps->i[k]] + b->r[ps->j[k]]);
    } else if (rc == LUB_PAIR_NONFINITE && *fail_k < 0) {
        *fail_k = (long)k;
        *fail_un = un;
    }
}

/* Stores the accepted lanes of the batch, evaluates the declined ones with the scalar law. */
static void flush_batch(lub_pairs *ps, const size_t *kk, const lub_cell *cell,
                        const lub_pair_bodies *b, const lub_law_params *law, double cutoff,
                        double dt, lub_pair_accum *acc, lub_pair_batch *bt,
                        lub_pair_range_sums *sums, long *fail_k, double *fail_un)
{
    lub_pair_step_batch(law, dt, bt);
    const double crush = law->alpha * law->eps; /* crushed: u_n < -alpha eps a */
    double sy = 0.0;
    long nc = 0, ncr = 0;
    for (int l = 0; l < bt->n; ++l) {
        const size_t k = kk[l];
        if (bt->done[l]) {
            ps->near[k] = bt->near[l];
            lub_pair_accum_add(acc, ps->i[k], ps->j[k], v3(bt->f1x[l], bt->f1y[l], bt->f1z[l]),
                               v3(bt->t1x[l], bt->t1y[l], bt->t1z[l]),
                               v3(bt->t2x[l], bt->t2y[l], bt->t2z[l]), bt->near[l]);
            sy += bt->f1y[l] * bt->by[l];
            if (bt->contact[l]) {
                nc++;
                const double dist =
                    sqrt(bt->bx[l] * bt->bx[l] + bt->by[l] * bt->by[l] + bt->bz[l] * bt->bz[l]);
                ncr += dist - bt->r1[l] - bt->r2[l] < -crush * 0.5 * (bt->r1[l] + bt->r2[l]);
            }
            continue;
        }
        eval_scalar(ps, k, cell, b, law, cutoff, dt, acc, sums, fail_k, fail_un);
    }
    sums->syy += sy;
    sums->contacts += nc;
    sums->crushed += ncr;
    bt->n = 0;
}

long lub_pair_eval_range(lub_pairs *ps, long k0, long k1, const lub_cell *cell,
                         const lub_pair_bodies *b, const lub_law_params *law, double cutoff,
                         double dt, int n_mobile, lub_pair_accum *acc, lub_pair_batch batches[2],
                         lub_pair_range_sums *sums, double *fail_un)
{
    long fail_k = -1;
    if (!lub_pair_batch_accelerated()) {
        /* kernel built without AVX2: the scalar law is faster */
        for (long kl = k0; kl < k1; ++kl) {
            if (ps->i[kl] >= n_mobile && ps->j[kl] >= n_mobile)
                lub_pairs_leave(ps, (size_t)kl);
            else
                eval_scalar(ps, (size_t)kl, cell, b, law, cutoff, dt, acc, sums, &fail_k, fail_un);
        }
        return fail_k;
    }
    /* two batches: pairs with u < a at their last evaluation (spin torques on) and the others,
     * so that most vector groups are uniform and the kernel can skip the torque block */
    size_t kk[2][LUB_BATCH];
    /* the 27 image shifts H c (c in {-1, 0, 1}^3) and their mean-flow velocities L H c, once
     * per call instead of a matrix product per candidate */
    vec3 sh[27], vsh[27];
    for (int ic = 0; ic < 27; ++ic) {
        const int c[3] = {ic / 9 - 1, ic / 3 % 3 - 1, ic % 3 - 1};
        sh[ic] = lub_cell_shift(cell, c);
        vsh[ic] = lub_mat_vec(cell->L, sh[ic]);
    }
    /* lane counts of the two batches, kept in registers (a count in memory would make every
     * pair wait for the previous pair's store: it was the hottest instruction of the loop) */
    int n_far = 0, n_near = 0;
    /* the array pointers in locals: the flag stores (unsigned char may alias anything) would
     * otherwise make the compiler reload every array pointer of ps and b for every pair.
     * restrict only on the arrays nothing writes during the loop (active, near and state are
     * written through ps and by the kernel) */
    const int32_t *restrict pi = ps->i, *restrict pj = ps->j;
    const unsigned char *restrict img = ps->img, *restrict allow = ps->allow;
    const double guard = ps->allow_guard;
    const unsigned char *active = ps->active, *near = ps->near;
    lub_pair_state *state = ps->state;
    const vec3 *restrict X = b->x, *restrict V = b->v, *restrict W = b->w;
    const double *restrict R = b->r, *restrict inv_share = b->inv_i_share;
    for (long kl = k0; kl < k1; ++kl) {
        const size_t k = (size_t)kl;
        const int i = pi[k], j = pj[k];
        if (kl + LUB_PREFETCH_AHEAD < k1) { /* large systems: hide the latency of the streams */
            const size_t kp = k + LUB_PREFETCH_AHEAD;
            __builtin_prefetch(&state[kp], 1);
            __builtin_prefetch(&X[pj[kp]], 0);
            __builtin_prefetch(&V[pj[kp]], 0);
            __builtin_prefetch(&W[pj[kp]], 0);
        }
        if (i >= n_mobile && j >= n_mobile) { /* two fixed bodies: never interact */
            lub_pairs_leave(ps, k);
            continue;
        }
        const unsigned ic = img[k];
        vec3 shift, vshift;
        if (__builtin_expect(ic < 27, 1)) {
            shift = sh[ic];
            vshift = vsh[ic];
        } else {
            shift = lub_cell_shift(cell, &ps->c[3 * k]);
            vshift = lub_mat_vec(cell->L, shift);
        }
        const vec3 d = v3_sub(v3_add(X[j], shift), X[i]);
        const double ri = R[i], rj = R[j];
        /* u_n <= cutoff a  <=>  |d|^2 <= (r_i + r_j + cutoff a)^2 (no square root here).
         * About a third of the candidates are outside: the lane is written either way and
         * kept only if inside, so that no branch depends on this unpredictable test; only
         * the rare crossings of the cut-off (state created or dropped) branch. */
        const double reach = ri + rj + cutoff * 0.5 * (ri + rj);
        const double guarded = ri + rj + guard * 0.5 * (ri + rj); /* the filter's guard */
        const double d2 = v3_norm2(d);
        const int inside = (d2 <= reach * reach) & (allow[k] | (d2 < guarded * guarded));
        if (inside != active[k]) {
            if (inside)
                lub_pairs_enter(ps, k);
            else
                lub_pairs_leave(ps, k);
        }
        const int which = near[k] != 0;
        lub_pair_batch *bt = &batches[which];
        const int l = which ? n_near : n_far;
        n_far += inside & !which;
        n_near += inside & which;
        const vec3 v2 = v3_add(V[j], vshift);
        kk[which][l] = k;
        bt->bx[l] = d.x, bt->by[l] = d.y, bt->bz[l] = d.z;
        bt->v1x[l] = V[i].x, bt->v1y[l] = V[i].y, bt->v1z[l] = V[i].z;
        bt->v2x[l] = v2.x, bt->v2y[l] = v2.y, bt->v2z[l] = v2.z;
        bt->w1x[l] = W[i].x, bt->w1y[l] = W[i].y, bt->w1z[l] = W[i].z;
        bt->w2x[l] = W[j].x, bt->w2y[l] = W[j].y, bt->w2z[l] = W[j].z;
        bt->r1[l] = ri, bt->r2[l] = rj;
        bt->inv_i1[l] = inv_share[i], bt->inv_i2[l] = inv_share[j]; /* lub_pair_inv_inertia */
        bt->state[l] = &state[k];
        if ((which ? n_near : n_far) == LUB_BATCH) {
            bt->n = LUB_BATCH;
            flush_batch(ps, kk[which], cell, b, law, cutoff, dt, acc, bt, sums, &fail_k, fail_un);
            if (which)
                n_near = 0;
            else
                n_far = 0;
        }
    }
    batches[0].n = n_far;
    batches[1].n = n_near;
    for (int w = 0; w < 2; ++w)
        if (batches[w].n > 0)
            flush_batch(ps, kk[w], cell, b, law, cutoff, dt, acc, &batches[w], sums, &fail_k,
                        fail_un);
    return fail_k;
}

/* pair_store.c — persistent pair states carried across neighbour-list rebuilds. */
#include "pair_store.h"

#include <stdlib.h>
#include <string.h>

void lub_pairs_init(lub_pairs *ps) { memset(ps, 0, sizeof *ps); }

void lub_pairs_free(lub_pairs *ps)
{
    free(ps->i);
    free(ps->j);
    free(ps->c);
    free(ps->img);
    free(ps->state);
    free(ps->active);
    free(ps->near);
    free(ps->allow);
    free(ps->oi);
    free(ps->oj);
    free(ps->ostate);
    free(ps->oactive);
    memset(ps, 0, sizeof *ps);
}

static int re(void **p, size_t count, size_t elem)
{
    void *q = realloc(*p, (count ? count : 1) * elem);
    if (!q)
        return -1;
    *p = q;
    return 0;
}

/* *p replaced by an uninitialised array of count elements on a 64-byte boundary (the old
 * contents are NOT kept). For the pair states: 64 bytes each, so that each sits in one cache
 * line (malloc aligns to 16 only, and a state across two lines costs two). */
static int re_lines(void **p, size_t count, size_t elem)
{
    size_t bytes = (count ? count : 1) * elem;
    bytes = (bytes + 63) / 64 * 64; /* aligned_alloc wants a multiple of the alignment */
    void *q = aligned_alloc(64, bytes);
    if (!q)
        return -1;
    free(*p);
    *p = q;
    return 0;
}

unsigned char lub_pairs_image_code(const int32_t *c)
{
    for (int d = 0; d < 3; ++d)
        if (c[d] < -1 || c[d] > 1)
            return LUB_PAIR_IMG_OTHER;
    return (unsigned char)(9 * (c[0] + 1) + 3 * (c[1] + 1) + (c[2] + 1));
}

/* Room for count pairs in the current (not the old) arrays and in the arrays that are not
 * double-buffered (those follow the largest capacity); contents are not kept where an array
 * grows. 0 or -1 (no memory). */
static int grow(lub_pairs *ps, size_t count)
{
    if (count > ps->cap || !ps->i) {
        const size_t cap = count + count / 4 + 64;
        if (re((void **)&ps->i, cap, sizeof *ps->i) || re((void **)&ps->j, cap, sizeof *ps->j) ||
            re_lines((void **)&ps->state, cap, sizeof *ps->state) ||
            re((void **)&ps->active, cap, sizeof *ps->active))
            return -1;
        ps->cap = cap;
    }
    const size_t fcap = ps->cap > ps->ocap ? ps->cap : ps->ocap;
    if (fcap > ps->fcap || !ps->near) {
        if (re((void **)&ps->c, 3 * fcap, sizeof *ps->c) ||
            re((void **)&ps->near, fcap, sizeof *ps->near) ||
            re((void **)&ps->img, fcap, sizeof *ps->img) ||
            re((void **)&ps->allow, fcap, sizeof *ps->allow))
            return -1;
        ps->fcap = fcap;
    }
    return 0;
}

int lub_pairs_adopt(lub_pairs *ps, const lub_nlist *nl, int n_particles)
{
    size_t nn = nl->npairs;
    /* move the current keys/states into the old buffers (swap pointers, no copy) */
    {
        int32_t *t;
        t = ps->oi;
        ps->oi = ps->i;
        ps->i = t;
        t = ps->oj;
        ps->oj = ps->j;
        ps->j = t;
        lub_pair_state *s = ps->ostate;
        ps->ostate = ps->state;
        ps->state = s;
        unsigned char *a = ps->oactive;
        ps->oactive = ps->active;
        ps->active = a;
        size_t c = ps->ocap;
        ps->ocap = ps->cap;
        ps->cap = c;
    }
    size_t nold = ps->n;
    if (grow(ps, nn)) /* the current arrays' contents are rewritten below */
        return -1;

    /* sorted merge: carry state of (i, j) present in the old list */
    size_t o = 0, carried = 0;
    for (size_t k = 0; k < nn; ++k) {
        int32_t a = nl->pi[k], b = nl->pj[k];
        ps->i[k] = a;
        ps->j[k] = b;
        ps->c[3 * k] = nl->pc[3 * k];
        ps->c[3 * k + 1] = nl->pc[3 * k + 1];
        ps->c[3 * k + 2] = nl->pc[3 * k + 2];
        ps->img[k] = lub_pairs_image_code(&ps->c[3 * k]);
        while (o < nold && (ps->oi[o] < a || (ps->oi[o] == a && ps->oj[o] < b)))
            ++o;
        if (o < nold && ps->oi[o] == a && ps->oj[o] == b) {
            ps->state[k] = ps->ostate[o];
            ps->active[k] = ps->oactive[o];
            carried += ps->oactive[o];
            ++o;
        } else {
            lub_pair_state_reset(&ps->state[k]);
            ps->active[k] = 0;
        }
        ps->near[k] = 0;
    }
    memset(ps->allow, 1, nn);
    ps->n = nn;
    ps->n_particles = n_particles;
    ps->carried = carried;
    /* active states of the old list whose pair the new list lacks: the skin rule makes this 0
     * (an active pair is inside the cut-off, the new list holds every pair inside the cut-off
     * plus the skin); a lost state would restart a contact without its history */
    size_t old_active = 0;
    for (size_t q = 0; q < nold; ++q)
        old_active += ps->oactive[q];
    ps->lost = old_active - carried;
    ps->nbounds = 0; /* the balanced split belongs to the old list */
    return 0;
}

int lub_pairs_reserve(lub_pairs *ps, size_t count, int n_particles)
{
    if (grow(ps, count)) {
        ps->n = 0;
        return -1;
    }
    ps->n = count;
    ps->n_particles = n_particles;
    ps->nbounds = 0;
    return 0;
}

size_t lub_pairs_count_active(const lub_pairs *ps)
{
    size_t c = 0;
    for (size_t k = 0; k < ps->n; ++k)
        c += ps->active[k];
    return c;
}

/* Relative costs per pair for lub_pairs_balance, from the batched loop at phi = 0.5 (bench
 * shear_bench, AVX-512): a candidate outside the cut-off costs its distance test (~1 unit),
 * an active pair the gather, the 8-lane law and the sums (~5), a pair with u < a also the
 * roll/twist block (~6). Only the ratios matter; errors here cost balance, not correctness. */
enum { COST_CANDIDATE = 1, COST_ACTIVE = 4, COST_NEAR = 1 };

void lub_pairs_balance(lub_pairs *ps, int parts)
{
    ps->nbounds = 0;
    if (parts < 1 || parts > LUB_PAIRS_MAX_PARTS)
        return;
    size_t total = 0;
    for (size_t k = 0; k < ps->n; ++k)
        total += COST_CANDIDATE + COST_ACTIVE * ps->active[k] + COST_NEAR * ps->near[k];
    ps->bounds[0] = 0;
    size_t acc = 0, k = 0;
    for (int t = 1; t < parts; ++t) {
        /* first pair whose cumulative cost reaches t/parts of the total */
        const size_t target =
            total / (size_t)parts * (size_t)t + total % (size_t)parts * (size_t)t / (size_t)parts;
        while (k < ps->n && acc < target) {
            acc += COST_CANDIDATE + COST_ACTIVE * ps->active[k] + COST_NEAR * ps->near[k];
            ++k;
        }
        ps->bounds[t] = k;
    }
    ps->bounds[parts] = ps->n;
    ps->nbounds = parts;
}

/* neighbor_list.c — cell-list construction of Verlet candidate pairs (see neighbor_list.h). */
#include "neighbor_list.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

void lub_nlist_init(lub_nlist *nl, double range, double skin)
{
    memset(nl, 0, sizeof *nl);
    nl->range = range;
    nl->skin = skin;
}

void lub_nlist_free(lub_nlist *nl)
{
    for (int t = 0; t < nl->nparts; ++t) {
        free(nl->parts[t].pi);
        free(nl->parts[t].pj);
        free(nl->parts[t].pc);
    }
    free(nl->parts);
    free(nl->split);
    free(nl->pi);
    free(nl->pj);
    free(nl->pc);
    free(nl->first);
    free(nl->bin_start);
    free(nl->bin_items);
    free(nl->bin_of);
    free(nl->frac);
    memset(nl, 0, sizeof *nl);
}

static int grow(void **p, size_t *cap, size_t need, size_t elem)
{
    (void)cap;
    void *q = realloc(*p, need * elem);
    if (!q)
        return -1;
    *p = q;
    return 0;
}

/* Grows the three pair arrays *pi, *pj, *pc (capacity *cap pairs) to hold need pairs. */
static int ensure_capacity(int32_t **pi, int32_t **pj, int32_t **pc, size_t *cap, size_t need)
{
    if (need <= *cap)
        return 0;
    size_t c = *cap ? *cap : 1024;
    while (c < need)
        c += c / 2;
    if (grow((void **)pi, NULL, c, sizeof **pi) || grow((void **)pj, NULL, c, sizeof **pj) ||
        grow((void **)pc, NULL, 3 * c, sizeof **pc))
        return -1;
    *cap = c;
    return 0;
}

/* lround(x) (nearest integer, halves away from zero) without the library call, which was
 * ~15 % of the search: the fractional part x - trunc(x) is exact, so the result is identical
 * for |x| < 2^31; larger |x| (never met with wrapped positions) go to lround. */
static inline int round_half_away(double x)
{
    if (!(fabs(x) < 2147483647.0))
        return (int)lround(x);
    int k = (int)x;
    const double r = x - (double)k;
    k += (r >= 0.5) - (r <= -0.5);
    return k;
}

/* Bins are at least 1/LUB_NLIST_BIN_SPLIT of the listing distance wide (in each fractional
 * direction) and the search visits LUB_NLIST_BIN_SPLIT bins on each side: with 2, the
 * 5 x 5 x 5 stencil spans 2.5 listing distances per direction where 3 x 3 x 3 bins one listing
 * distance wide span 3, (5/6)^3 = 0.58 of the volume (in the limit of many bins); and at
 * N = 1000 (about 4 listing distances across: 3 wide bins, 7 half-width ones) it no longer
 * visits every particle. */
#define LUB_NLIST_BIN_SPLIT 2
#define LUB_NLIST_STENCIL (2 * LUB_NLIST_BIN_SPLIT + 1)

static int wrap_index(int k, int n)
{
    k %= n;
    return k < 0 ? k + n : k;
}

typedef struct {
    lub_nlist *nl;
    const lub_cell *cell;
    const double *radius;
    double factor;
    int nx, ny, nz;
    int off[3][LUB_NLIST_STENCIL], noff[3];
} search_ctx;

/* Pairs (i, j > i) for i0 <= i < i1 into *out (from its start), sorted by (i, j); sets
 * nl->first[i + 1] to the number of pairs of out up to and including i. Returns 0 or -1 (no
 * memory). Reads the bins and fractional coordinates only: ranges can run concurrently. */
static int search_range(const search_ctx *sc, int i0, int i1, lub_nlist_part *out)
{
    lub_nlist *nl = sc->nl;
    const lub_cell *cell = sc->cell;
    const double *radius = sc->radius;
    const double factor = sc->factor;
    const int nx = sc->nx, ny = sc->ny, nz = sc->nz;
    const int(*off)[LUB_NLIST_STENCIL] = sc->off;
    const int *noff = sc->noff;
    size_t np = 0;
    for (int i = i0; i < i1; ++i) {
        int bin = nl->bin_of[i];
        int bx = bin % nx, by = (bin / nx) % ny, bz = bin / (nx * ny);
        vec3 si = nl->frac[i];
        double ri = radius[i];
        size_t start = np;
        for (int oz = 0; oz < noff[2]; ++oz)
            for (int oy = 0; oy < noff[1]; ++oy)
                for (int ox = 0; ox < noff[0]; ++ox) {
                    int cb =
                        (wrap_index(bz + off[2][oz], nz) * ny + wrap_index(by + off[1][oy], ny)) *
                            nx +
                        wrap_index(bx + off[0][ox], nx);
                    for (int t = nl->bin_start[cb]; t < nl->bin_start[cb + 1]; ++t) {
                        int j = nl->bin_items[t];
                        if (j <= i)
                            continue;
                        vec3 sj = nl->frac[j];
                        vec3 ds = v3(sj.x - si.x, sj.y - si.y, sj.z - si.z);
                        int c[3] = {-round_half_away(ds.x), -round_half_away(ds.y),
                                    -round_half_away(ds.z)};
                        vec3 dsc = v3(ds.x + c[0], ds.y + c[1], ds.z + c[2]);
                        vec3 d = lub_cell_to_cart(cell, dsc);
                        double lim = fmax((ri + radius[j]) * factor, nl->reach) + nl->skin;
                        if (v3_norm2(d) < lim * lim) {
                            if (np + 1 > out->cap &&
                                ensure_capacity(&out->pi, &out->pj, &out->pc, &out->cap, np + 1))
                                return -1;
                            out->pi[np] = i;
                            out->pj[np] = j;
                            out->pc[3 * np] = c[0];
                            out->pc[3 * np + 1] = c[1];
                            out->pc[3 * np + 2] = c[2];
                            ++np;
                        }
                    }
                }
        /* sort this particle's pairs by j (insertion sort: lists are short) */
        for (size_t a = start + 1; a < np; ++a) {
            int32_t jj = out->pj[a];
            int32_t c0 = out->pc[3 * a], c1 = out->pc[3 * a + 1], c2 = out->pc[3 * a + 2];
            size_t b = a;
            while (b > start && out->pj[b - 1] > jj) {
                out->pj[b] = out->pj[b - 1];
                out->pc[3 * b] = out->pc[3 * (b - 1)];
                out->pc[3 * b + 1] = out->pc[3 * (b - 1) + 1];
                out->pc[3 * b + 2] = out->pc[3 * (b - 1) + 2];
                --b;
            }
            out->pj[b] = jj;
            out->pc[3 * b] = c0;
            out->pc[3 * b + 1] = c1;
            out->pc[3 * b + 2] = c2;
        }
        nl->first[i + 1] = np;
    }
    out->n = np;
    return 0;
}

/* First i of range t when n indices are split into `team` equal ranges. */
static int equal_start(int n, int t, int team) { return (int)((long)n * t / team); }

/* split[0..nt]: the first i of each of nt ranges. With prev_pairs > 0, first[0..n] holds the
 * cumulative pair counts of the previous build and each range gets about prev_pairs/nt of
 * them; otherwise n/nt indices each. */
static void split_ranges(const size_t *first, int n, size_t prev_pairs, int nt, int *split)
{
    split[0] = 0;
    int i = 0;
    for (int t = 1; t < nt; ++t) {
        if (prev_pairs == 0) {
            split[t] = equal_start(n, t, nt);
            continue;
        }
        const size_t target = prev_pairs * (size_t)t / (size_t)nt;
        while (i < n && first[i] < target)
            ++i;
        split[t] = i;
    }
    split[nt] = n;
}

/* First i of range t of a team of `team` threads: split[] when the runtime gave the nt threads
 * asked for, equal ranges otherwise. */
static int range_start(const int *split, int n, int nt, int t, int team)
{
    return team == nt ? split[t] : equal_start(n, t, team);
}

int lub_nlist_build(lub_nlist *nl, const lub_cell *cell, const vec3 *pos, const double *radius,
                    int n)
{
    double rmax = 0.0;
    for (int i = 0; i < n; ++i)
        if (radius[i] > rmax)
            rmax = radius[i];
    double factor = 1.0 + 0.5 * nl->range;
    double dmax = fmax(2.0 * rmax * factor, nl->reach) + nl->skin;
    nl->max_dist = dmax;
    double w[3];
    lub_cell_widths(cell, w);
    for (int a = 0; a < 3; ++a)
        if (w[a] < 2.0 * dmax * (1.0 + 1e-12))
            return LUB_NLIST_CELL_TOO_SMALL;

    /* pairs of the previous build of the same n, the weights of the threads' ranges; first[]
     * is rewritten from here on */
    const size_t prev_pairs = nl->first_n == n ? nl->npairs : 0;
    nl->first_n = 0;
    size_t un = (size_t)n;
    if (un > nl->part_cap) {
        if (grow((void **)&nl->first, NULL, un + 1, sizeof *nl->first) ||
            grow((void **)&nl->bin_items, NULL, un, sizeof *nl->bin_items) ||
            grow((void **)&nl->bin_of, NULL, un, sizeof *nl->bin_of) ||
            grow((void **)&nl->frac, NULL, un, sizeof *nl->frac))
            return LUB_NLIST_NOMEM;
        nl->part_cap = un;
    }
    if (!nl->first) {
        if (grow((void **)&nl->first, NULL, 1, sizeof *nl->first))
            return LUB_NLIST_NOMEM;
    }
    size_t nb = 1;
    for (int a = 0; a < 3; ++a) {
        int k = (int)floor(LUB_NLIST_BIN_SPLIT * w[a] / dmax);
        if (k < 1)
            k = 1;
        if (k > 1024)
            k = 1024;
        nl->ncell[a] = k;
        nb *= (size_t)k;
    }
    if (nb + 1 > nl->bin_cap) {
        if (grow((void **)&nl->bin_start, NULL, nb + 1, sizeof *nl->bin_start))
            return LUB_NLIST_NOMEM;
        nl->bin_cap = nb + 1;
    }
    const int nx = nl->ncell[0], ny = nl->ncell[1], nz = nl->ncell[2];

    /* counting sort of the particles into bins of wrapped fractional coordinates */
    memset(nl->bin_start, 0, (nb + 1) * sizeof *nl->bin_start);
    for (int i = 0; i < n; ++i) {
        vec3 s = lub_cell_to_frac(cell, pos[i]);
        nl->frac[i] = s;
        double sw[3] = {s.x - floor(s.x), s.y - floor(s.y), s.z - floor(s.z)};
        int b[3];
        for (int a = 0; a < 3; ++a) {
            b[a] = (int)(sw[a] * nl->ncell[a]);
            if (b[a] >= nl->ncell[a])
                b[a] = nl->ncell[a] - 1;
            if (b[a] < 0)
                b[a] = 0;
        }
        int bin = (b[2] * ny + b[1]) * nx + b[0];
        nl->bin_of[i] = bin;
        nl->bin_start[bin + 1]++;
    }
    for (size_t b = 0; b < nb; ++b)
        nl->bin_start[b + 1] += nl->bin_start[b];
    for (int i = 0; i < n; ++i) {
        int bin = nl->bin_of[i];
        nl->bin_items[nl->bin_start[bin]++] = i;
    }
    for (size_t b = nb; b > 0; --b)
        nl->bin_start[b] = nl->bin_start[b - 1];
    nl->bin_start[0] = 0;

    /* stencil offsets per direction: -S..S (S = LUB_NLIST_BIN_SPLIT), or every bin once when
     * a direction has fewer than 2S + 1 bins */
    int off[3][LUB_NLIST_STENCIL], noff[3];
    for (int a = 0; a < 3; ++a) {
        const int k = nl->ncell[a];
        if (k >= LUB_NLIST_STENCIL) {
            for (int o = 0; o < LUB_NLIST_STENCIL; ++o)
                off[a][o] = o - LUB_NLIST_BIN_SPLIT;
            noff[a] = LUB_NLIST_STENCIL;
        } else {
            for (int o = 0; o < k; ++o)
                off[a][o] = o;
            noff[a] = k;
        }
    }

    /* pair search over contiguous ranges of i: thread 0 writes into the list's own arrays,
     * thread t > 0 into its buffer parts[t], appended in order afterwards (serial: no copy) */
    int nt = nl->threads > 1 ? nl->threads : 1;
    if (n < 256)
        nt = 1; /* not worth a team */
#ifndef _OPENMP
    nt = 1;
#endif
    if (nt > nl->nparts) {
        lub_nlist_part *q = realloc(nl->parts, (size_t)nt * sizeof *q);
        if (!q)
            return LUB_NLIST_NOMEM;
        memset(q + nl->nparts, 0, (size_t)(nt - nl->nparts) * sizeof *q);
        nl->parts = q;
        nl->nparts = nt;
    }
    if (nt + 1 > nl->split_cap) {
        if (grow((void **)&nl->split, NULL, (size_t)nt + 1, sizeof *nl->split))
            return LUB_NLIST_NOMEM;
        nl->split_cap = nt + 1;
    }
    split_ranges(nl->first, n, prev_pairs, nt, nl->split);
    search_ctx sc = {nl, cell, radius, factor, nx, ny, nz, {{0}}, {0}};
    memcpy(sc.off, off, sizeof off);
    memcpy(sc.noff, noff, sizeof noff);
    lub_nlist_part own = {nl->pi, nl->pj, nl->pc, 0, nl->pair_cap};
    int bad = 0, used = 1; /* threads the runtime gave the team (may be fewer than nt) */
    nl->first[0] = 0;
#pragma omp parallel num_threads(nt) reduction(| : bad) if (nt > 1)
    {
#ifdef _OPENMP
        const int t = omp_get_thread_num(), team = omp_get_num_threads();
#else
        const int t = 0, team = 1;
#endif
        if (t == 0)
            used = team;
        const int i0 = range_start(nl->split, n, nt, t, team);
        const int i1 = range_start(nl->split, n, nt, t + 1, team);
        bad |= search_range(&sc, i0, i1, t == 0 ? &own : &nl->parts[t]);
    }
    nl->pi = own.pi, nl->pj = own.pj, nl->pc = own.pc, nl->pair_cap = own.cap; /* may have moved */
    if (bad)
        return LUB_NLIST_NOMEM;
    size_t np = own.n;
    for (int t = 1; t < used; ++t)
        np += nl->parts[t].n;
    if (ensure_capacity(&nl->pi, &nl->pj, &nl->pc, &nl->pair_cap, np))
        return LUB_NLIST_NOMEM;
    size_t base = own.n;
    for (int t = 1; t < used; ++t) {
        const lub_nlist_part *pt = &nl->parts[t];
        if (pt->n > 0) { /* an empty part may have no buffers at all */
            memcpy(nl->pi + base, pt->pi, pt->n * sizeof *pt->pi);
            memcpy(nl->pj + base, pt->pj, pt->n * sizeof *pt->pj);
            memcpy(nl->pc + 3 * base, pt->pc, 3 * pt->n * sizeof *pt->pc);
        }
        const int i0 = range_start(nl->split, n, nt, t, used);
        const int i1 = range_start(nl->split, n, nt, t + 1, used);
        for (int i = i0; i < i1; ++i)
            nl->first[i + 1] += base; /* search_range stored counts relative to its buffer */
        base += pt->n;
    }
    nl->npairs = np;
    nl->first_n = n;
    return LUB_NLIST_OK;
}

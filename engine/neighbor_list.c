/* neighbor_list.c — cell-list construction of Verlet candidate pairs (see neighbor_list.h). */
#include "neighbor_list.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void lub_nlist_init(lub_nlist *nl, double range, double skin)
{
    memset(nl, 0, sizeof *nl);
    nl->range = range;
    nl->skin = skin;
}

void lub_nlist_free(lub_nlist *nl)
{
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

static int ensure_pairs(lub_nlist *nl, size_t need)
{
    if (need <= nl->pair_cap)
        return 0;
    size_t cap = nl->pair_cap ? nl->pair_cap : 1024;
    while (cap < need)
        cap += cap / 2;
    if (grow((void **)&nl->pi, NULL, cap, sizeof *nl->pi) ||
        grow((void **)&nl->pj, NULL, cap, sizeof *nl->pj) ||
        grow((void **)&nl->pc, NULL, 3 * cap, sizeof *nl->pc))
        return -1;
    nl->pair_cap = cap;
    return 0;
}

static int wrap_index(int k, int n)
{
    k %= n;
    return k < 0 ? k + n : k;
}

int lub_nlist_build(lub_nlist *nl, const lub_cell *cell, const vec3 *pos, const double *radius,
                    int n)
{
    double rmax = 0.0;
    for (int i = 0; i < n; ++i)
        if (radius[i] > rmax)
            rmax = radius[i];
    double factor = 1.0 + 0.5 * nl->range;
    double dmax = 2.0 * rmax * factor + nl->skin;
    nl->max_dist = dmax;
    double w[3];
    lub_cell_widths(cell, w);
    for (int a = 0; a < 3; ++a)
        if (w[a] < 2.0 * dmax * (1.0 + 1e-12))
            return LUB_NLIST_CELL_TOO_SMALL;

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
        int k = (int)floor(w[a] / dmax);
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

    /* stencil offsets per direction, de-duplicated when a direction has < 3 bins */
    int off[3][3], noff[3];
    for (int a = 0; a < 3; ++a) {
        int k = nl->ncell[a];
        if (k >= 3) {
            off[a][0] = -1;
            off[a][1] = 0;
            off[a][2] = 1;
            noff[a] = 3;
        } else if (k == 2) {
            off[a][0] = 0;
            off[a][1] = 1;
            noff[a] = 2;
        } else {
            off[a][0] = 0;
            noff[a] = 1;
        }
    }

    size_t np = 0;
    nl->first[0] = 0;
    for (int i = 0; i < n; ++i) {
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
                        int c[3] = {-(int)lround(ds.x), -(int)lround(ds.y), -(int)lround(ds.z)};
                        vec3 dsc = v3(ds.x + c[0], ds.y + c[1], ds.z + c[2]);
                        vec3 d = lub_cell_to_cart(cell, dsc);
                        double lim = (ri + radius[j]) * factor + nl->skin;
                        if (v3_norm2(d) < lim * lim) {
                            if (np + 1 > nl->pair_cap && ensure_pairs(nl, np + 1))
                                return LUB_NLIST_NOMEM;
                            nl->pi[np] = i;
                            nl->pj[np] = j;
                            nl->pc[3 * np] = c[0];
                            nl->pc[3 * np + 1] = c[1];
                            nl->pc[3 * np + 2] = c[2];
                            ++np;
                        }
                    }
                }
        /* sort this particle's pairs by j (insertion sort: lists are short) */
        for (size_t a = start + 1; a < np; ++a) {
            int32_t jj = nl->pj[a];
            int32_t c0 = nl->pc[3 * a], c1 = nl->pc[3 * a + 1], c2 = nl->pc[3 * a + 2];
            size_t b = a;
            while (b > start && nl->pj[b - 1] > jj) {
                nl->pj[b] = nl->pj[b - 1];
                nl->pc[3 * b] = nl->pc[3 * (b - 1)];
                nl->pc[3 * b + 1] = nl->pc[3 * (b - 1) + 1];
                nl->pc[3 * b + 2] = nl->pc[3 * (b - 1) + 2];
                --b;
            }
            nl->pj[b] = jj;
            nl->pc[3 * b] = c0;
            nl->pc[3 * b + 1] = c1;
            nl->pc[3 * b + 2] = c2;
        }
        nl->first[i + 1] = np;
    }
    nl->npairs = np;
    return LUB_NLIST_OK;
}

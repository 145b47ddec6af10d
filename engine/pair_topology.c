/* pair_topology.c — Delaunay (power-diagram) restriction of the lubricated pairs (see
 * pair_topology.h). */
#include "pair_topology.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

double lub_topology_reach(double r_min, double r_max, double range)
{
    return (r_min + r_max) * (1.0 + 0.5 * (range + LUB_TOPOLOGY_LIST_EXTRA));
}

void lub_topology_init(lub_topology *t, double range, double reach, double guard,
                       const double *radius, int n, int threads)
{
    memset(t, 0, sizeof *t);
    t->range = range;
    t->reach = reach;
    t->guard = guard;
    t->r_min = n > 0 ? radius[0] : 0.0;
    t->r_max = t->r_min;
    for (int p = 1; p < n; ++p) {
        t->r_min = radius[p] < t->r_min ? radius[p] : t->r_min;
        t->r_max = radius[p] > t->r_max ? radius[p] : t->r_max;
    }
    t->threads = threads < 1 ? 1 : threads;
}

void lub_topology_free(lub_topology *t)
{
    free(t->first);
    free(t->sites);
    memset(t, 0, sizeof *t);
}

/* every sphere within this centre distance of one of radius ri is in its list, whatever the
 * skin state */
static double known_distance(const lub_topology *t, double ri)
{
    return fmax((ri + t->r_min) * (1.0 + 0.5 * t->range), t->reach);
}

double lub_topology_certified_radius(const lub_topology *t, double ri)
{
    return lub_power_certified_radius(known_distance(t, ri), ri, t->r_max);
}

static int grow(lub_topology *t, int n, size_t nsites)
{
    if (n + 1 > t->n_cap) {
        size_t *f = realloc(t->first, ((size_t)n + 1) * sizeof *f);
        if (!f)
            return -1;
        t->first = f;
        t->n_cap = n + 1;
    }
    if (nsites > t->site_cap || !t->sites) {
        const size_t cap = nsites + nsites / 4 + 64;
        lub_power_site *s = realloc(t->sites, cap * sizeof *s);
        if (!s)
            return -1;
        t->sites = s;
        t->site_cap = cap;
    }
    return 0;
}

int lub_topology_update(lub_topology *t, lub_pairs *ps, const lub_cell *cell, const vec3 *x,
                        const double *r, int n, double cutoff)
{
    const size_t np = ps->n;
    if (grow(t, n, 2 * np)) {
        memset(ps->allow, 1, np);
        return -1;
    }
    const double rmax = t->r_max;
    /* CSR of both directions of every listed pair */
    size_t *first = t->first;
    memset(first, 0, ((size_t)n + 1) * sizeof *first);
    for (size_t k = 0; k < np; ++k) {
        first[ps->i[k] + 1]++;
        first[ps->j[k] + 1]++;
    }
    for (int p = 0; p < n; ++p)
        first[p + 1] += first[p];
    /* fill: pairs are sorted by (i, j), so a running cursor per sphere is first[] itself,
     * shifted back afterwards */
    for (size_t k = 0; k < np; ++k) {
        const int i = ps->i[k], j = ps->j[k];
        const vec3 d = v3_sub(v3_add(x[j], lub_cell_shift(cell, &ps->c[3 * k])), x[i]);
        t->sites[first[i]++] = (lub_power_site){d, r[j], 2 * (long)k + 1};
        t->sites[first[j]++] = (lub_power_site){v3_neg(d), r[i], 2 * (long)k};
    }
    for (int p = n; p > 0; --p)
        first[p] = first[p - 1];
    first[0] = 0;

    size_t inside = 0, allowed = 0, open = 0;
    const double guard = t->guard;
    lub_power_site *sites = t->sites;
#pragma omp parallel for schedule(dynamic, 16) num_threads(t->threads)                         \
    reduction(+ : inside, allowed, open)
    for (int i = 0; i < n; ++i) {
        lub_power_site *s = sites + first[i];
        const int m = (int)(first[i + 1] - first[i]);
        /* sites at the known distance or beyond (the list's skin and reach beyond it) neither
         * have a face within the ball nor cut one (the bound of lub_power_certified_radius, and
         * lub_power_face_area's stop): only the nearer ones are sorted and clipped with */
        const double known = known_distance(t, r[i]), known2 = known * known;
        int near = 0;
        for (int q = 0; q < m; ++q)
            if (v3_norm2(s[q].d) < known2) {
                const lub_power_site tmp = s[near];
                s[near++] = s[q];
                s[q] = tmp;
            }
        lub_power_sort(s, near);
        const double R = lub_power_certified_radius(known, r[i], rmax);
        for (int q = 0; q < m; ++q) {
            if (!(s[q].tag & 1))
                continue; /* decided from the other sphere's side */
            const size_t k = (size_t)(s[q].tag >> 1);
            const double a = 0.5 * (r[i] + s[q].r);
            const double un = v3_norm(s[q].d) - r[i] - s[q].r;
            int is_open = 0;
            int ok = un < guard * a;
            if (!ok && q < near)
                ok = lub_power_face_area(r[i], s, near, q, R, rmax, &is_open) > 1e-9 * a * a;
            ps->allow[k] = (unsigned char)ok;
            if (un <= cutoff * a) {
                inside++;
                allowed += ok;
                open += ok && is_open;
            }
        }
    }
    t->inside = inside;
    t->allowed = allowed;
    t->open = open;
    t->updates++;
    return 0;
}

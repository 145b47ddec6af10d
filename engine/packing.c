/* packing.c — random non-overlapping packings compressed to a target fraction. */
#include "packing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "neighbor_list.h"
#include "rng.h"

static double sphere_volume_sum(const double *r, int n)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i)
        s += r[i] * r[i] * r[i];
    return 4.0 / 3.0 * 3.14159265358979323846 * s;
}

/* bin of fractional coordinate f in [0, 1) among nb, clamped to 0..nb-1 */
static int clamped_bin(double f, int nb)
{
    const int b = (int)(f * nb);
    return b < 0 ? 0 : (b >= nb ? nb - 1 : b);
}

static vec3 min_image(const lub_cell *cell, vec3 d)
{
    vec3 s = lub_cell_to_frac(cell, d);
    s = v3(s.x - nearbyint(s.x), s.y - nearbyint(s.y), s.z - nearbyint(s.z));
    return lub_cell_to_cart(cell, s);
}

/* The gaps of a set of pairs: the smallest u_n = |d| - r_i - r_j (length), the smallest u_n/a_ij
 * (a_ij = (r_i + r_j)/2) and how many have u_n/a_ij < below. */
typedef struct {
    double min_u, min_ua;
    long long below;
} gap_tally;

static void tally_pair(gap_tally *t, vec3 d, double ri, double rj, double below)
{
    const double u = v3_norm(d) - ri - rj;
    const double ua = u / (0.5 * (ri + rj));
    t->min_u = fmin(t->min_u, u);
    t->min_ua = fmin(t->min_ua, ua);
    t->below += ua < below;
}

/* Over every pair, nearest images (O(n^2)). */
static gap_tally all_pair_gaps(const lub_cell *cell, const vec3 *pos, const double *radius, int n,
                               double below)
{
    gap_tally t = {INFINITY, INFINITY, 0};
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            tally_pair(&t, min_image(cell, v3_sub(pos[j], pos[i])), radius[i], radius[j], below);
    return t;
}

/* Over the pairs of a built list. */
static gap_tally listed_pair_gaps(const lub_nlist *nl, const lub_cell *cell, const vec3 *pos,
                                  const double *radius, double below)
{
    gap_tally t = {INFINITY, INFINITY, 0};
    for (size_t k = 0; k < nl->npairs; ++k) {
        const int i = nl->pi[k], j = nl->pj[k];
        tally_pair(&t, v3_sub(v3_add(pos[j], lub_cell_shift(cell, &nl->pc[3 * k])), pos[i]),
                   radius[i], radius[j], below);
    }
    return t;
}

double lub_packing_min_gap(const lub_cell *cell, const vec3 *pos, const double *radius, int n)
{
    return all_pair_gaps(cell, pos, radius, n, 0.0).min_u;
}

/* One relaxation pass over the candidate pairs; returns the largest relative overlap
 * (overlap / (r_i + r_j)) BEFORE the displacement. */
static double relax_sweep(const lub_nlist *nl, const lub_cell *cell, vec3 *pos, const double *r,
                          double infl, vec3 *disp, int n)
{
    double worst = 0.0;
    for (int i = 0; i < n; ++i)
        disp[i] = v3(0, 0, 0);
    for (size_t k = 0; k < nl->npairs; ++k) {
        int i = nl->pi[k], j = nl->pj[k];
        const int *c = &nl->pc[3 * k];
        vec3 d = v3_sub(v3_add(pos[j], lub_cell_shift(cell, c)), pos[i]);
        double dist = v3_norm(d);
        double sum = (r[i] + r[j]) * infl;
        double ov = sum - dist;
        if (ov <= 0.0)
            continue;
        double rel = ov / (r[i] + r[j]);
        if (rel > worst)
            worst = rel;
        vec3 nrm = dist > 0 ? v3_scale(d, 1.0 / dist) : v3(1, 0, 0);
        /* move both apart, weighted by the inverse volume ratio; 0.5 over-all damping */
        double wi = r[j] * r[j] * r[j] / (r[i] * r[i] * r[i] + r[j] * r[j] * r[j]);
        double step = 0.5 * ov;
        disp[i] = v3_axpy(disp[i], -step * wi, nrm);
        disp[j] = v3_axpy(disp[j], step * (1.0 - wi), nrm);
    }
    for (int i = 0; i < n; ++i)
        pos[i] = v3_add(pos[i], disp[i]);
    return worst;
}

/* The largest relative overlap of the inflated radii over the listed pairs, as relax_sweep
 * measures it, without moving anything. */
static double largest_overlap(const lub_nlist *nl, const lub_cell *cell, const vec3 *pos,
                              const double *r, double infl)
{
    double worst = 0.0;
    for (size_t k = 0; k < nl->npairs; ++k) {
        const int i = nl->pi[k], j = nl->pj[k];
        const vec3 d = v3_sub(v3_add(pos[j], lub_cell_shift(cell, &nl->pc[3 * k])), pos[i]);
        const double rel = ((r[i] + r[j]) * infl - v3_norm(d)) / (r[i] + r[j]);
        if (rel > worst)
            worst = rel;
    }
    return worst;
}

/* Renumbers the spheres along bins of ~2.5 a (x fastest, then y, then z) so that neighbours have
 * close indices (memory locality of the pair loops). Stable counting sort; uses the two work
 * arrays (n vec3 each) as scratch. */
static void spatial_sort(const lub_cell *cell, vec3 *pos, double *radius, vec3 *w1, vec3 *w2, int n)
{
    int nb[3];
    for (int a = 0; a < 3; ++a) {
        nb[a] = (int)(cell->h[a][a] / 2.5);
        if (nb[a] < 1)
            nb[a] = 1;
    }
    size_t nbins = (size_t)nb[0] * nb[1] * nb[2];
    size_t *start = calloc(nbins + 1, sizeof *start);
    int *key = malloc((size_t)n * sizeof *key);
    if (!start || !key) {
        free(start);
        free(key);
        return; /* ordering is an optimisation only */
    }
    for (int i = 0; i < n; ++i) {
        vec3 s = lub_cell_to_frac(cell, pos[i]);
        double f[3] = {s.x, s.y, s.z};
        int b[3];
        for (int a = 0; a < 3; ++a)
            b[a] = clamped_bin(f[a], nb[a]);
        key[i] = (b[2] * nb[1] + b[1]) * nb[0] + b[0];
        start[key[i] + 1]++;
    }
    for (size_t b = 0; b < nbins; ++b)
        start[b + 1] += start[b];
    /* w1 <- positions, w2.x <- radii, in the new order */
    for (int i = 0; i < n; ++i) {
        size_t d = start[key[i]]++;
        w1[d] = pos[i];
        w2[d].x = radius[i];
    }
    for (int i = 0; i < n; ++i) {
        pos[i] = w1[i];
        radius[i] = w2[i].x;
    }
    free(start);
    free(key);
}

/* Bins of the sequential placement: a cube of nb^3 bins at least `reach` wide (the largest
 * sum of radii times 1 + margin), each a linked list of the spheres placed in it, so that a
 * trial position is tested against the spheres of its 27 neighbouring bins instead of every
 * sphere placed (O(n) placement instead of O(n^2): 20 000 spheres took 16 s, 50 000 95 s).
 * With fewer than 3 bins per direction every sphere is tested, as before. The accept/reject
 * decisions, hence the packing, are the same either way: the distance test is the same
 * expression and the bins hold every sphere within reach. */
typedef struct {
    int nb; /* bins per direction; 0: test every sphere */
    double side;
    int *head; /* nb^3: first sphere of each bin, -1 if empty */
    int *next; /* n: next sphere of the same bin */
} placement_grid;

static int grid_init(placement_grid *g, double side, double reach, int all_pairs, int n)
{
    g->side = side;
    g->nb = (int)floor(side / reach);
    g->head = g->next = NULL;
    if (g->nb < 3 || all_pairs) {
        g->nb = 0;
        return 0;
    }
    if (g->nb > 512) /* 1.3e8 bins at most (n = 1e7 needs ~240 per direction); wider bins
                        are still correct */
        g->nb = 512;
    const size_t nbins = (size_t)g->nb * (size_t)g->nb * (size_t)g->nb;
    g->head = malloc(nbins * sizeof *g->head);
    g->next = malloc((size_t)n * sizeof *g->next);
    if (!g->head || !g->next) {
        free(g->head);
        free(g->next);
        return -1;
    }
    for (size_t b = 0; b < nbins; ++b)
        g->head[b] = -1;
    return 0;
}

static void grid_free(placement_grid *g)
{
    free(g->head);
    free(g->next);
}

static int grid_coord(const placement_grid *g, double x) { return clamped_bin(x / g->side, g->nb); }

static void grid_insert(placement_grid *g, vec3 x, int i)
{
    if (g->nb == 0)
        return;
    const size_t b =
        ((size_t)grid_coord(g, x.z) * g->nb + grid_coord(g, x.y)) * g->nb + grid_coord(g, x.x);
    g->next[i] = g->head[b];
    g->head[b] = i;
}

/* 1 if sphere i at x overlaps placed sphere j (radii times 1 + margin) */
static int overlaps(const lub_cell *cell, const vec3 *pos, const double *radius, int i, int j,
                    vec3 x, double margin)
{
    const vec3 d = min_image(cell, v3_sub(pos[j], x));
    const double s = (radius[i] + radius[j]) * (1.0 + margin);
    return v3_norm2(d) < s * s;
}

/* 1 if sphere i at x overlaps none of the spheres 0..i-1 */
static int placement_is_free(const placement_grid *g, const lub_cell *cell, const vec3 *pos,
                             const double *radius, int i, vec3 x, double margin)
{
    if (g->nb == 0) {
        for (int j = 0; j < i; ++j)
            if (overlaps(cell, pos, radius, i, j, x, margin))
                return 0;
        return 1;
    }
    const int c[3] = {grid_coord(g, x.x), grid_coord(g, x.y), grid_coord(g, x.z)};
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int bx = (c[0] + dx + g->nb) % g->nb, by = (c[1] + dy + g->nb) % g->nb,
                          bz = (c[2] + dz + g->nb) % g->nb;
                for (int j = g->head[((size_t)bz * g->nb + by) * g->nb + bx]; j >= 0;
                     j = g->next[j])
                    if (overlaps(cell, pos, radius, i, j, x, margin))
                        return 0;
            }
    return 1;
}

void lub_packing_radius_clip(double radius_std, double *lo, double *hi)
{
    *lo = fmax(1.0 - 3.0 * radius_std, 0.2);
    *hi = 1.0 + 3.0 * radius_std;
}

void lub_packing_radius_bounds(double radius_std, double *lo, double *hi)
{
    double c_lo, c_hi;
    lub_packing_radius_clip(radius_std, &c_lo, &c_hi);
    *lo = c_lo / c_hi;
    *hi = c_hi / c_lo;
}

/* 1. the radii: drawn from rng (seeded with p->seed), clipped, divided by their mean; returns
 * that mean */
static double draw_radii(const lub_packing_params *p, lub_rng *rng, double *radius)
{
    const int n = p->n;
    double lo, hi;
    lub_packing_radius_clip(p->radius_std, &lo, &hi);
    double mean = 0.0;
    for (int i = 0; i < n; ++i) {
        double r = 1.0 + p->radius_std * lub_rng_gauss(rng);
        radius[i] = fmin(fmax(r, lo), hi);
        mean += radius[i];
    }
    mean /= n;
    for (int i = 0; i < n; ++i)
        radius[i] /= mean;
    return mean;
}

double lub_packing_radii(const lub_packing_params *p, double *radius)
{
    lub_rng rng;
    lub_rng_seed(&rng, p->seed);
    draw_radii(p, &rng, radius);
    return cbrt(sphere_volume_sum(radius, p->n) / p->phi);
}

/* The smallest true gap u_n = |d| - r_i - r_j over all pairs (nearest images), from lists of
 * growing range (no skin): every pair with u_n < range a_ij, a_ij >= r_min, is listed, so the
 * smallest listed gap is the true one once it is below range r_min; until then (no pair that
 * close, or a listed pair of large spheres whose gap an unlisted pair of small ones may
 * undercut) the range grows 4-fold. When a list cannot be built (cell narrower than twice its
 * listing distance, out of memory) the O(n^2) search. Until 2026-12-07 a single list of range
 * 0.2 was read: INFINITY (reported as null) when no pair had u_n < 0.2 a_ij, and with radius
 * spread possibly not the smallest gap. */
static double final_min_gap(lub_nlist *nl, const lub_cell *cell, const vec3 *pos,
                            const double *radius, int n)
{
    double rmin = INFINITY;
    for (int i = 0; i < n; ++i)
        rmin = fmin(rmin, radius[i]);
    nl->skin = 0.0;
    for (double range = 0.2;; range *= 4.0) {
        nl->range = range;
        if (lub_nlist_build(nl, cell, pos, radius, n) != LUB_NLIST_OK)
            return lub_packing_min_gap(cell, pos, radius, n);
        const double g = listed_pair_gaps(nl, cell, pos, radius, 0.0).min_u;
        if (g < range * rmin)
            return g;
    }
}

int lub_packing_gap_census(const lub_cell *cell, const vec3 *pos, const double *radius, int n,
                           double below, lub_packing_gaps *out)
{
    out->min_gap_a = INFINITY;
    out->below = 0;
    lub_nlist nl;
    lub_nlist_init(&nl, 0.0, 0.0);
    int rc = 0;
    /* a pair with u_n < range a_ij is listed: the count at the first range (> below), the
     * smallest gap once one is below the range (otherwise the range grows 4-fold) */
    for (double range = fmax(0.2, 2.0 * below);; range *= 4.0) {
        nl.range = range;
        const int b = lub_nlist_build(&nl, cell, pos, radius, n);
        if (b == LUB_NLIST_NOMEM) {
            rc = -1;
            break;
        }
        /* a cell too small for the list: every pair, nearest image */
        const gap_tally t = b != LUB_NLIST_OK ? all_pair_gaps(cell, pos, radius, n, below)
                                              : listed_pair_gaps(&nl, cell, pos, radius, below);
        if (range == fmax(0.2, 2.0 * below))
            out->below = t.below;
        if (b != LUB_NLIST_OK || t.min_ua < range) {
            out->min_gap_a = t.min_ua;
            break;
        }
    }
    lub_nlist_free(&nl);
    return rc;
}

int lub_packing_generate(const lub_packing_params *p, double *radius, vec3 *pos, lub_cell *cell,
                         lub_packing_info *info)
{
    const int n = p->n;
    if (info) /* what a failure before any sweep reports */
        *info = (lub_packing_info){.phi = 0.0, .min_gap = NAN, .sweeps = 0};
    /* the spheres grown by margin/2 must not overlap: beyond every random packing's fraction */
    if (p->phi * pow(1.0 + 0.5 * p->margin, 3) > LUB_PACKING_GROWN_PHI_MAX)
        return -2;
    lub_rng rng;
    lub_rng_seed(&rng, p->seed);
    double lo, hi;
    lub_packing_radius_clip(p->radius_std, &lo, &hi);
    const double mean = draw_radii(p, &rng, radius);
    double vs = sphere_volume_sum(radius, n);

    /* 2. random sequential placement in a dilute cube */
    double phi0 = fmin(p->phi, 0.25);
    double side = cbrt(vs / phi0);
    lub_cell_init_box(cell, side, side, side);
    placement_grid grid;
    if (grid_init(&grid, side, 2.0 * hi / mean * (1.0 + p->margin), p->placement_all_pairs, n))
        return -1;
    for (int i = 0; i < n; ++i) {
        if ((i & 4095) == 4095 && p->stop && *p->stop) {
            grid_free(&grid);
            return -3;
        }
        for (long attempt = 0;; ++attempt) {
            vec3 x = v3(side * lub_rng_uniform(&rng), side * lub_rng_uniform(&rng),
                        side * lub_rng_uniform(&rng));
            const int ok = placement_is_free(&grid, cell, pos, radius, i, x, p->margin);
            if (ok || attempt > 100000) {
                pos[i] = x; /* overlaps left (extremely unlikely) are relaxed below */
                grid_insert(&grid, x, i);
                break;
            }
        }
    }
    grid_free(&grid);

    /* 3. compression + relaxation */
    lub_nlist nl;
    lub_nlist_init(&nl, 0.0, 0.0);
    vec3 *disp = malloc((size_t)n * sizeof *disp);
    vec3 *ref = malloc((size_t)n * sizeof *ref);
    if (!disp || !ref) {
        free(disp);
        free(ref);
        return -1;
    }
    /* Large packings are renumbered along bins before the compression: the relaxation
     * sweeps (about 1000 at phi 0.5, whatever n) then walk memory in order instead of at
     * random. 400 000 spheres at phi 0.5 took 100 s, now 45 s (1 thread). The result is the same
     * packing to round-off (positions within 3e-13 a, same sweeps and smallest gap), but not
     * bit for bit, so smaller packings keep their order and every run below the threshold
     * stays bit for bit what earlier versions gave (the gain is below 10 % there). */
    if (p->presort > 0 || (p->presort == 0 && n > LUB_PACKING_SORT_MIN_N))
        spatial_sort(cell, pos, radius, disp, ref, n);
    const double infl = 1.0 + p->margin;
    const double skin = 0.3;
    nl.skin = skin;
    double phi = phi0;
    int sweeps = 0, rc = 0;
    double target_side = cbrt(vs / p->phi);
    for (;;) {
        double new_phi = fmin(p->phi, phi * 1.03);
        double new_side = (new_phi >= p->phi) ? target_side : cbrt(vs / new_phi);
        double f = new_side / cell->h[0][0];
        for (int i = 0; i < n; ++i)
            pos[i] = v3_scale(pos[i], f);
        lub_cell_init_box(cell, new_side, new_side, new_side);
        phi = new_phi;
        int need_build = 1;
        double worst = INFINITY;
        /* the stage's smallest worst overlap, and its value at the last stall check */
        double best = INFINITY, best_checked = INFINITY;
        int stage_sweeps = 0;
        for (;;) {
            const int relaxed = !(worst > 0.5 * p->margin);
            if (relaxed && phi < p->phi)
                break;
            if (need_build || relaxed) {
                for (int i = 0; i < n; ++i)
                    lub_cell_wrap(cell, &pos[i], NULL, NULL);
                int b = lub_nlist_build(&nl, cell, pos, radius, n);
                if (b == LUB_NLIST_CELL_TOO_SMALL) {
                    /* tiny systems: fall back to a thinner listing distance, the inflated
                     * contact distance itself (no skin: rebuilt every sweep). Until 2026-12-07
                     * it was the true contact distance, and overlaps of the inflated radii
                     * went unseen: gaps of 0.03 of the promised margin/2 (r_i + r_j) */
                    nl.skin = 0.0;
                    nl.range = 2.0 * p->margin;
                    b = lub_nlist_build(&nl, cell, pos, radius, n);
                }
                if (b != LUB_NLIST_OK) {
                    /* a cube narrower than twice even that distance: too few spheres for the
                     * pair search (packing.h). Until 2026-12-07 reported as -2, "phi too
                     * high" */
                    rc = (b == LUB_NLIST_NOMEM) ? -1 : -4;
                    goto done;
                }
                memcpy(ref, pos, (size_t)n * sizeof *ref);
                need_build = 0;
            }
            if (relaxed) {
                /* the last sweep measured the overlaps before its displacement: the packing is
                 * done when they hold after it too (they always did on the packings tried;
                 * otherwise the sweeps go on) */
                worst = largest_overlap(&nl, cell, pos, radius, infl);
                if (!(worst > 0.5 * p->margin))
                    break;
            }
            worst = relax_sweep(&nl, cell, pos, radius, infl, disp, n);
            ++sweeps;
            if (sweeps > p->max_sweeps) {
                rc = -2;
                goto done;
            }
            /* stalled: a jammed packing keeps its worst overlap above margin/2 for good */
            best = fmin(best, worst);
            if (++stage_sweeps % LUB_PACKING_STALL_SWEEPS == 0) {
                if (!(best < best_checked * (1.0 - LUB_PACKING_STALL_GAIN))) {
                    rc = -2;
                    goto done;
                }
                best_checked = best;
            }
            if (p->stop && *p->stop) {
                rc = -3;
                goto done;
            }
            double dm = 0.0;
            for (int i = 0; i < n; ++i) {
                double d2 = v3_norm2(v3_sub(pos[i], ref[i]));
                if (d2 > dm)
                    dm = d2;
            }
            if (2.0 * sqrt(dm) > 0.9 * nl.skin)
                need_build = 1;
        }
        if (phi >= p->phi)
            break;
    }
    for (int i = 0; i < n; ++i)
        lub_cell_wrap(cell, &pos[i], NULL, NULL);
    spatial_sort(cell, pos, radius, disp, ref, n);
    {
        const double g = final_min_gap(&nl, cell, pos, radius, n);
        if (info) {
            info->min_gap = g;
            info->phi = vs / cell->volume;
            info->sweeps = sweeps;
        }
        if (!(g > 0.0))
            rc = -2;
    }
done:
    if (rc && rc != -1 && info) {
        info->phi = phi;
        info->sweeps = sweeps;
        info->min_gap = NAN;
        if (rc == -2) { /* the overlap left (a negative gap); not when asked to stop */
            for (int i = 0; i < n; ++i)
                lub_cell_wrap(cell, &pos[i], NULL, NULL);
            info->min_gap = final_min_gap(&nl, cell, pos, radius, n);
        }
    }
    lub_nlist_free(&nl);
    free(disp);
    free(ref);
    return rc;
}

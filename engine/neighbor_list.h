/* neighbor_list.h — Verlet candidate pairs from a cell list in a (sheared) periodic cell.
 *
 * A pair (i < j) is listed when the centre distance to the nearest image of j is below
 *   (r_i + r_j)(1 + range/2) + skin,   i.e. u_n < range * a_ij + skin,  a_ij = (r_i + r_j)/2,
 * where `range` is the lubrication cut-off in units of a_ij (e.g. 2), or, when the owner sets
 * `reach` (a centre distance, 0 after lub_nlist_init), when it is below
 *   max((r_i + r_j)(1 + range/2), reach) + skin
 * (the Delaunay set's candidates, pair_topology.h). Each pair carries the
 * integer image shift c such that the branch vector is d = x_j + H c - x_i. Positions may be
 * anywhere (not necessarily wrapped): the cell list bins their wrapped fractional coordinates
 * and c accounts for the unwrapped positions.
 *
 * Output order: sorted by (i, j), so first[i] .. first[i+1] are the pairs whose body 1 is i.
 *
 * Validity: the nearest image is found exactly when the listing distance is below half of
 * every perpendicular cell width (lub_nlist_build returns LUB_NLIST_CELL_TOO_SMALL
 * otherwise). Cells are searched in fractional space (works for any tilt), each bin at least
 * half a listing distance wide and the search two bins to each side (5 x 5 x 5); when a
 * direction has fewer than 5 bins every bin of it is visited once.
 *
 * Memory: all arrays are owned by the lub_nlist and grow (realloc) only inside
 * lub_nlist_build; repeated builds with similar sizes do not allocate. Free with
 * lub_nlist_free. Not thread-safe per instance.
 *
 * Threads: with `threads` > 1 (set by the owner after lub_nlist_init) and OpenMP, the pair
 * search runs on that many threads over contiguous ranges of i; the first range is written
 * into the result arrays, the others into per-thread buffers appended in order: the result is
 * identical to the serial build. The ranges hold about equal numbers of pairs of the previous
 * build of the same n (particle indices are the same from build to build), equal numbers of i
 * at the first: i lists only j > i, so equal ranges of i load the first thread more (3/4 of
 * the pairs in the first half of a random order, tests/shear/test_nlist.c; measured effect on
 * the shear benchmark: tests/bench/README.md, "Balanced neighbour search").
 */

#ifndef LUBDEM_NEIGHBOR_LIST_H
#define LUBDEM_NEIGHBOR_LIST_H

#include <stddef.h>
#include <stdint.h>

#include "periodic_cell.h"

typedef struct {
    int32_t *pi, *pj, *pc; /* one thread's pairs, in (i, j) order */
    size_t n, cap;
} lub_nlist_part;

enum { LUB_NLIST_OK = 0, LUB_NLIST_NOMEM = -1, LUB_NLIST_CELL_TOO_SMALL = -2 };

typedef struct {
    double range; /* cut-off in units of a_ij (>= 0) */
    double skin;  /* extra listing distance, length units (>= 0) */
    double reach; /* smallest listing distance before the skin, length units (0: none) */

    /* result */
    size_t npairs;
    int32_t *pi, *pj; /* [npairs] */
    int32_t *pc;      /* [3 * npairs] image shifts */
    size_t *first;    /* [n + 1] */
    double max_dist;  /* the largest listing distance used (length) */

    /* internal buffers (grown at build time only) */
    size_t pair_cap, part_cap, bin_cap;
    int ncell[3];
    int *bin_start;        /* [nbins + 1] */
    int *bin_items;        /* [n] particle ids sorted by bin */
    int *bin_of;           /* [n] */
    vec3 *frac;            /* [n] unwrapped fractional coordinates */
    int threads;           /* pair-search threads (<= 1: serial); set by the owner */
    lub_nlist_part *parts; /* [nparts] buffers of threads 1.. of the parallel search ([0] unused) */
    int nparts;
    int *split; /* [split_cap] first i of each thread's range; split[threads asked for] = n */
    int split_cap;
    int first_n; /* n of the last successful build (first[] counts its pairs), 0: none */
} lub_nlist;

void lub_nlist_init(lub_nlist *nl, double range, double skin);
void lub_nlist_free(lub_nlist *nl);

/* Builds the list for n particles. Returns LUB_NLIST_OK, LUB_NLIST_NOMEM or
 * LUB_NLIST_CELL_TOO_SMALL (cell narrower than twice the listing distance). */
int lub_nlist_build(lub_nlist *nl, const lub_cell *cell, const vec3 *pos, const double *radius,
                    int n);

#endif

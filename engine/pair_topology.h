/* pair_topology.h — restricts the lubricated pairs of a pair store to the neighbours of the
 * regular (weighted Delaunay) triangulation, the interaction set of the seed's rheology
 * article (seed 000 l.908; physics-reference §2 comes from that model).
 *
 * lub_topology_update sets ps->allow[k] for every candidate pair k of the store:
 *   allow = 1  the two spheres' power cells share a face of positive area (power_faces.h),
 *              or their gap is below guard * a_ij (contacts are never dropped, even between
 *              updates; a touching pair is a power neighbour anyway unless a third sphere
 *              overlaps the contact point);
 *   allow = 0  otherwise: the pair loop treats the pair as outside the cut-off (no force, its
 *              state dropped), so it re-enters with a fresh state when allowed again, or
 *              when its gap falls below the guard before the next update (the pair store's
 *              allow_guard, which the owner sets to the same guard: until 2026-12-07 such a
 *              pair could close into contact without a force until the next update).
 * The faces are computed from the candidate list itself. A Verlet list built with listing
 * distance (r_i + r_j)(1 + range/2) + skin still holds every pair closer than that distance
 * minus the skin consumed since the build (`margin` = skin - consumed, the owner's skin
 * criterion), so each sphere's known neighbours certify faces within the radius of
 * lub_power_certified_radius. The allowed pairs are therefore exactly the power neighbours
 * whose face meets that ball (at cut-off 2a and skin 0.5a the radius is ~1.8-2.1 a, so
 * neighbours much farther than ~3.6 a centre to centre can be missed; the seed's article
 * quotes a maximum interaction distance of ~1.5 a gap). A face that still touches the ball is
 * counted in `open`.
 * The triangulation is a function of the positions at the update; the caller decides how often
 * to update (the neighbour list changes at rebuilds, so an update must follow every
 * lub_pairs_adopt).
 *
 * Memory: the per-sphere site lists are owned here and grow only when the pair count grows
 * (call after lub_pairs_adopt, i.e. at neighbour-list rebuilds: nothing is allocated when the
 * pair count has not grown). Free with lub_topology_free.
 * Threads: OpenMP over spheres with `threads` threads (pure per-sphere work, one writer per
 * pair): the result does not depend on the thread count.
 * Errors: lub_topology_update returns 0 or -1 (no memory; allow is then all ones).
 */
#ifndef LUBDEM_PAIR_TOPOLOGY_H
#define LUBDEM_PAIR_TOPOLOGY_H

#include <stddef.h>

#include "pair_store.h"
#include "periodic_cell.h"
#include "power_faces.h"

typedef struct {
    double range;        /* the neighbour list's cut-off in units of a_ij */
    double guard;        /* pairs with u_n < guard * a_ij are always allowed */
    double r_min, r_max; /* smallest and largest radius of the packing (fixed) */
    int threads;
    /* per-sphere candidate lists, CSR */
    size_t *first;         /* [n + 1] */
    lub_power_site *sites; /* [2 * npairs]; tag = 2 k + (sphere is body 1 of pair k) */
    size_t site_cap;
    int n_cap;
    /* statistics of the last update (pairs inside the cut-off only) */
    size_t inside, allowed, open;
    long updates;
} lub_topology;

/* radius[n]: the packing's radii (only their range is kept). */
void lub_topology_init(lub_topology *t, double range, double guard, const double *radius, int n,
                       int threads);
void lub_topology_free(lub_topology *t);

/* Radius of the ball around a sphere of radius ri within which its faces are exact (margin as
 * in lub_topology_update). */
double lub_topology_certified_radius(const lub_topology *t, double ri, double margin);

/* Recomputes ps->allow from the positions x (unwrapped; the image shifts of the store give
 * the branch vectors), radii r of n spheres (those given to lub_topology_init) and the cell.
 * cutoff: the lubrication cut-off (units of a_ij) used for the statistics; margin: the part of the
 * list's skin not yet consumed (length, >= 0; the full skin right after a rebuild). */
int lub_topology_update(lub_topology *t, lub_pairs *ps, const lub_cell *cell, const vec3 *x,
                        const double *r, int n, double cutoff, double margin);

#endif

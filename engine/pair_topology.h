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
 * The faces are computed from the candidate list itself. The list must hold, at every update,
 * every pair closer than max((r_i + r_j)(1 + range/2), reach) centre to centre (`range` and
 * `reach` of lub_topology_init; a Verlet list built with that listing distance and any skin
 * does, as long as its skin criterion holds: neighbor_list.h, `reach`). Each sphere's known
 * neighbours then certify its faces within the ball of radius lub_topology_certified_radius,
 * which depends on the radii, `range` and `reach` only, not on how much of the list's skin is
 * left: the allowed pairs are exactly the power neighbours whose face meets that ball, a
 * function of the positions (until 2026-12-07 the ball grew with the unconsumed skin, so the
 * set shrank between list rebuilds and jumped back at each one). The sheared system lists the
 * Delaunay set's candidates to reach = lub_topology_reach(r_min, r_max, cutoff): every sphere
 * then knows its neighbours at least as far as it did right after a rebuild with the old
 * skin-dependent ball and the default skin 0.5 a (the ball is ~2.0-2.2 a at cut-off 2a), and
 * the largest listing distance, hence the smallest cell, is unchanged at radius_std >= 0.042
 * (2 r_max (1 + cutoff/2) >= reach there).
 * Neighbours whose whole face lies beyond the ball are missed: long edges, but a face can sit
 * off to the side of the line of centres, so misses were seen at 3.0-3.2 a centre to centre,
 * not only beyond ~3.6 a (the seed's article quotes a maximum interaction distance of ~1.5 a
 * gap). A face that still touches the ball is counted in `open`.
 * Degenerate (lattice) configurations: a face of area below 1e-9 a_ij^2 counts as no face, so
 * in an fcc crystal the set is the 12 touching neighbours, without the octahedron diagonals
 * that a triangulation must add to split the octahedra.
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

/* Extra range of lub_topology_reach (units of a_ij): for radii of mean a, (r_min + r_max)
 * LUB_TOPOLOGY_LIST_EXTRA / 2 ~ 0.5 a, the default skin. */
#define LUB_TOPOLOGY_LIST_EXTRA 0.5

typedef struct {
    double range;        /* the list holds every pair with u_n < range * a_ij ... */
    double reach;        /* ... and every pair closer than reach centre to centre */
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

/* The reach of the sheared system's Delaunay candidates for radii in [r_min, r_max] and
 * cut-off `range` (units of a_ij): the centre distance of a pair (r_min, r_max) at u_n =
 * (range + LUB_TOPOLOGY_LIST_EXTRA) a_ij. Pure. */
double lub_topology_reach(double r_min, double r_max, double range);

/* range, reach: the candidate list holds every pair with u_n < range * a_ij or centre distance
 * < reach at every update (units of a_ij; length); radius[n]: the packing's radii (only their
 * range is kept). */
void lub_topology_init(lub_topology *t, double range, double reach, double guard,
                       const double *radius, int n, int threads);
void lub_topology_free(lub_topology *t);

/* Radius of the ball around a sphere of radius ri within which its faces are exact and
 * examined. */
double lub_topology_certified_radius(const lub_topology *t, double ri);

/* Recomputes ps->allow from the positions x (unwrapped; the image shifts of the store give
 * the branch vectors), radii r of n spheres (those given to lub_topology_init) and the cell.
 * cutoff: the lubrication cut-off (units of a_ij) used for the statistics. The result depends
 * on the positions and radii only (and on range and reach), not on the list's skin state. */
int lub_topology_update(lub_topology *t, lub_pairs *ps, const lub_cell *cell, const vec3 *x,
                        const double *r, int n, double cutoff);

#endif

/* pair_store.h — persistent per-pair storage (structure of arrays) for a particle system.
 *
 * Holds the current Verlet candidate pairs (i < j, sorted by (i, j)), their image shifts, the
 * persistent lub_pair_state of the contact law and an `active` flag:
 *   active = 1  the pair is inside the lubrication cut-off and its state carries history;
 *   active = 0  candidate only (outside the cut-off): no force, state meaningless.
 * The life cycle (notes §5): a candidate becomes active, with a fresh state (reset: new),
 * the first step its gap u_n <= cutoff*a; an active pair whose u_n exceeds cutoff*a is
 * deactivated (history erased). Candidates are listed with a Verlet skin, so pairs are created
 * with a positive gap well before they touch.
 *
 * lub_pairs_adopt() replaces the candidate list by a new neighbour list and CARRIES the state
 * and active flag of every pair (i, j) present in both (sorted-key merge, O(old + new)).
 * A pair whose `allow` flag is 0 is treated as outside the cut-off (an interaction-set filter
 * such as the Delaunay neighbours of pair_topology.h; adopt resets every flag to 1), unless its
 * gap is below allow_guard * a: a pair refused while its gap was wider, which closes before
 * the filter's next update, still meets its lubrication and contact forces.
 *
 * Forces and torques are not stored per pair: the pair loops add them to per-particle sums
 * (pair_accum.h).
 *
 * Memory: everything is owned here; arrays grow (realloc) only inside lub_pairs_adopt (i.e. at
 * neighbour-list rebuilds), never during a time step. Free with lub_pairs_free.
 */
#ifndef LUBDEM_PAIR_STORE_H
#define LUBDEM_PAIR_STORE_H

#include <stddef.h>
#include <string.h>
#include <stdint.h>

#include "contact_law.h"
#include "neighbor_list.h"

enum { LUB_PAIRS_MAX_PARTS = 256 }; /* largest team lub_pairs_balance splits for */
enum { LUB_PAIR_IMG_OTHER = 255 };  /* img code of a shift with a component outside {-1,0,1} */

typedef struct {
    size_t n, cap;
    int n_particles;
    int32_t *i, *j, *c;    /* c: [3n] image shifts */
    unsigned char *img;    /* [n] 9 (c0 + 1) + 3 (c1 + 1) + (c2 + 1) when every component of c is
                              in {-1, 0, 1} (the 27 shifts of a pair kernel's table), else
                              LUB_PAIR_IMG_OTHER */
    lub_pair_state *state; /* [n] */
    unsigned char *active; /* [n] */
    unsigned char *near;   /* [n] 1 if the last evaluation had u < a (spin torques on) */
    unsigned char *allow;  /* [n] 0: the pair may not interact even inside the cut-off (an
                              interaction-set filter, pair_topology.h); lub_pairs_adopt sets 1 */
    double allow_guard;    /* a pair with u_n < allow_guard * a interacts whatever its allow
                              flag: the filter's contacts guard (pair_topology.h), also between
                              its updates; 0 (init) when there is no filter */
    size_t fcap;           /* capacity of c, near and allow */
    /* double buffer for the merge */
    int32_t *oi, *oj;
    lub_pair_state *ostate;
    unsigned char *oactive;
    size_t ocap;
    size_t carried; /* statistics of the last adopt: active states carried over */
    size_t lost;    /* statistics of the last adopt: active states of the old list whose pair
                       is missing from the new list (0 unless the Verlet skin rule failed) */
    /* cost-balanced split of the pairs over the threads (lub_pairs_balance): part t is
     * [bounds[t], bounds[t + 1]); valid for nbounds parts, 0 = not computed for this list */
    int nbounds;
    size_t bounds[LUB_PAIRS_MAX_PARTS + 1];
} lub_pairs;

void lub_pairs_init(lub_pairs *ps);
void lub_pairs_free(lub_pairs *ps);

/* Adopts the pairs of nl for n_particles particles, carrying states. Returns 0 or -1 (no memory).
 */
int lub_pairs_adopt(lub_pairs *ps, const lub_nlist *nl, int n_particles);

/* Makes room for `count` pairs of n_particles particles and sets ps->n = count, with the
 * contents undefined: the caller fills i, j, c, img, state, active, near and allow (a checkpoint
 * being reloaded, shear_checkpoint.h). The balanced split is marked stale. 0 or -1 (no memory:
 * the store is then empty). */
int lub_pairs_reserve(lub_pairs *ps, size_t count, int n_particles);
/* The img code (above) of the image shift c[3]. */
unsigned char lub_pairs_image_code(const int32_t *c);
/* Pair k is inside the cut-off this step: an inactive pair becomes active with a fresh law
 * state (lub_pair_state_reset, notes §5 life cycle); an active pair keeps its history. */
static inline void lub_pairs_enter(lub_pairs *ps, size_t k)
{
    if (!ps->active[k]) {
        lub_pair_state_reset(&ps->state[k]);
        ps->active[k] = 1;
    }
}

/* Pair k is beyond the cut-off: it loses its state and contributes nothing. */
static inline void lub_pairs_leave(lub_pairs *ps, size_t k)
{
    ps->active[k] = 0;
    ps->near[k] = 0;
}

/* Number of active pairs. */
size_t lub_pairs_count_active(const lub_pairs *ps);

/* Splits the current list into `parts` contiguous ranges of about equal estimated cost, from
 * the active and near flags of the last evaluation (an inactive candidate costs only the
 * cut-off test, an active pair the law, a near pair also the roll/twist torques), so that a
 * static partition over threads does not leave one thread waiting. Deterministic (flags
 * only, never timings), O(n); nothing is allocated. parts outside [1, LUB_PAIRS_MAX_PARTS]
 * leave the split undefined (lub_pairs_range then splits by count). lub_pairs_adopt marks the
 * split stale. */
void lub_pairs_balance(lub_pairs *ps, int parts);

/* Range [*k0, *k1) of part `part` of `parts`: the balanced split when it was computed for
 * this list and this number of parts, otherwise equal pair counts. */
static inline void lub_pairs_range(const lub_pairs *ps, int part, int parts, long *k0, long *k1)
{
    if (ps->nbounds == parts) {
        *k0 = (long)ps->bounds[part];
        *k1 = (long)ps->bounds[part + 1];
    } else {
        const long n = (long)ps->n;
        *k0 = n * part / parts;
        *k1 = n * (part + 1) / parts;
    }
}

#endif

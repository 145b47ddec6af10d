/* pair_network.h — the interaction network of a system of lubricated spheres (a sheared
 * periodic cell, a resuspending bed): every interacting pair with its gaps, contact state and
 * the parts of its force and torques.
 *
 * The forces are those the system's next step applies: each pair inside the cut-off (and
 * allowed by the interaction set) is put through the contact law on a COPY of its persistent
 * state, from the current positions, half-step velocities and spins (a pair entering the
 * cut-off with a fresh state), exactly as the step evaluates it; the system's pair states are
 * not changed. lub_pair_network_build does this for any system's pairs (its list complete);
 * lub_shear_pair_network completes the list of a sheared system first
 * (lub_shear_complete_list; the resuspension scene calls lub_rs_complete_list): the
 * positions may move by cell vectors and the cell matrix by a flip, so that a particle
 * snapshot written after this call shows the positions and box the branch vectors and image
 * shifts refer to: branch = x_j + H image - x_i. That rebuild is the one the next step would
 * do (which then does none): it counts in s->rebuilds (and a flip in s->flips) like any
 * other, and the step control must see it; after the last step the scenes leave it out of
 * their summary.
 *
 * Units: those of the system (the simple_shear scene: a = 1, eta = 1, gd = 1 or P = 1).
 * Signs: forces and torques act on body i (body j receives minus the force and minus the roll
 * and twist torques; the torque of the shear force on j follows from j's own lever arm);
 * normal parts are components along n = branch/|branch|, negative when repulsive.
 * Memory: lub_pair_network_build sizes the arrays to the interacting pairs (a quarter more
 * when it allocates) and keeps them for the next call when they are large enough, so that a
 * network at every snapshot allocates only when the network grows; lub_pair_network_free
 * frees them (also after a failure).
 * Threads: serial (two passes over the pairs: count, then evaluate).
 */
#ifndef LUBDEM_PAIR_NETWORK_H
#define LUBDEM_PAIR_NETWORK_H

#include <stddef.h>
#include <stdint.h>

#include "pair_eval.h"
#include "shear_system.h"

typedef struct {
    size_t n;             /* interacting pairs */
    size_t cap;           /* pairs the arrays have room for */
    int64_t *i, *j;       /* [n] particle indices, i < j */
    int64_t *image;       /* [3n] cell image c of j: branch = x_j + H c - x_i */
    double *branch;       /* [3n] centre of i to centre of the image of j */
    double *centre_gap;   /* [n] u_n = |branch| - r_i - r_j (< 0: nominal spheres overlap) */
    double *gap;          /* [n] u, the lubricated gap of the law's state (> 0) */
    int8_t *contact;      /* [n] 1 when the asperities touch (u < eps a_ij) */
    int8_t *sliding;      /* [n] 1 when the contact slides (|F_s,contact| = mu |F_c|) */
    double *fn_contact;   /* [n] normal contact force along n */
    double *fn_lub;       /* [n] normal lubrication force along n */
    double *fs_contact;   /* [3n] tangential contact (friction) force */
    double *fs_lub;       /* [3n] tangential lubrication force */
    double *torque_roll;  /* [3n] rolling lubrication torque on i */
    double *torque_twist; /* [3n] twisting lubrication torque on i */
} lub_pair_network;

/* What a network is built from: the persistent pairs of a system, its cell and bodies (the
 * half-step velocities and spins), its law, cut-off (in units of the pair mean radius) and
 * step. Pairs of two bodies both >= n_free (fixed floor spheres) never interact and are left
 * out. Borrowed, not kept. */
typedef struct {
    const lub_pairs *pairs;
    const lub_cell *cell;
    lub_pair_bodies bodies;
    const lub_law_params *law;
    double cutoff, dt;
    int n_free;
    long step; /* for the failure message */
} lub_pair_network_source;

enum { LUB_PAIR_NETWORK_OK = 0, LUB_PAIR_NETWORK_NOMEM = -1, LUB_PAIR_NETWORK_NONFINITE = -2 };

/* The network of every listed pair inside the cut-off (the list must be complete: the
 * caller rebuilds it first when due) into *net (zeroed, or from an earlier call; arrays kept
 * as below). Returns LUB_PAIR_NETWORK_OK, _NOMEM (the arrays freed) or _NONFINITE (fail_msg[len]
 * names the pair); on failure net->n is 0. The system is not changed. */
int lub_pair_network_build(const lub_pair_network_source *src, lub_pair_network *net,
                           char *fail_msg, size_t len);

/* Fills *net (zeroed, or from an earlier call) with the network of s at its current state.
 * Returns LUB_SHEAR_OK; LUB_SHEAR_NOMEM (the arrays freed); LUB_SHEAR_CELL_TOO_SMALL (from the
 * list completion, s->fail_msg set); or LUB_SHEAR_NONFINITE when the law fails for a pair
 * (s->fail_msg names it). On failure net->n is 0. */
int lub_shear_pair_network(lub_shear_system *s, lub_pair_network *net);

/* Frees the arrays and empties *net (safe on an empty or zeroed network). */
void lub_pair_network_free(lub_pair_network *net);

/* Heap bytes per pair of a network. */
#define LUB_PAIR_NETWORK_PAIR_BYTES (24 * 8 + 2)

#endif

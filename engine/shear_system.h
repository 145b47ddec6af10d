/* shear_system.h — a tri-periodic, homogeneously sheared system of lubricated spheres.
 *
 * Owns the particle arrays (structure of arrays), the deforming cell (periodic_cell.h), the
 * Verlet list (neighbor_list.h) and the persistent pair states (pair_store.h), and advances
 * them with a leap-frog scheme:
 *   1. if the Verlet skin may be exhausted (or at the first step): flip the cell if tilted
 *      by more than 1/2, wrap particles into the cell (absolute velocities: v -= L H k), rebuild
 *      the list and carry the pair states;
 *      and, with the Delaunay interaction set, recompute the allowed pairs (pair_topology.h;
 *      also every topology_interval steps);
 *   2. pair forces from x^n and the half-step velocities v^{n-1/2}, w^{n-1/2}
 *      (lub_pair_step; pairs beyond cutoff*a are deactivated, pairs coming inside are created
 *      new — always with a positive gap thanks to the skin). Steps that sample no stress use
 *      the batched law (contact_batch.h), which gives the same forces to round-off;
 *   3. per-particle sums: each thread adds its pairs' forces and torques into its own
 *      per-particle arrays (pair_accum.h), which are then added in thread order (race-free;
 *      bit-identical for a given thread count, round-off differences between thread counts);
 *   4. v += dt (F/m + L v)   (convective term: the affine flow v = L x needs no force),
 *      w += dt T/I, x += dt v; with drag_viscosity eta_d > 0 the velocity update also carries
 *      the Stokes drag -6 pi eta_d r (v - L x) towards the affine flow, implicitly:
 *      v <- (v + dt (F/m + L v) + c L x)/(1 + c), c = 6 pi eta_d r dt/m (no time-step bound);
 *   5. H <- (I + dt L) H; t += dt.
 * Spin-torque stabilisation: the law integrates each pair's roll/twist damping exactly for an
 * isolated pair (contact_torque.h), but a sphere with d close neighbours (u < a) receives d
 * such torques in the same explicit step, which overshoots (Jacobi-type instability, observed
 * at phi = 0.55, St = 1e-2: blow-up within 300 steps). The system therefore passes each pair
 * the inverse inertias multiplied by the number of close neighbours of each body (from the
 * previous step), so that the summed damping of one step never exceeds the particle's own
 * spin (Gershgorin bound). Where the explicit scheme is stable (k << 1) the torques are
 * unchanged.
 * Skin rule: with A = H H_ref^-1 (affine map since the last rebuild) and u_max the largest
 * non-affine displacement |x - A x_ref|, the list stays valid while
 *   2 u_max + ||A - I||_F * d_list <= skin   (d_list = largest listing distance).
 *
 * Units: whatever the caller uses (the scene uses a = 1, eta = 1, and gd = 1 or P = 1).
 * Memory: lub_shear_init allocates all particle arrays; pair arrays grow only at rebuilds
 * (step 1); lub_shear_step never allocates otherwise. Free with lub_shear_free.
 * Threads: OpenMP over pairs and particles with `threads` threads (1 = serial).
 */
#ifndef LUBDEM_SHEAR_SYSTEM_H
#define LUBDEM_SHEAR_SYSTEM_H

#include <stddef.h>

#include "contact_law.h"
#include "microstructure.h"
#include "neighbor_list.h"
#include "pair_accum.h"
#include "pair_store.h"
#include "pair_topology.h"
#include "periodic_cell.h"
#include "step_stiffness.h"
#include "stress.h"

/* Per-thread pair counts of a stress sample (lub_shear_system.tcount). */
enum { LUB_COUNT_ACTIVE, LUB_COUNT_CONTACT, LUB_COUNT_CRUSHED, LUB_COUNT_SLIDING, LUB_COUNT_N };

enum {
    LUB_SHEAR_OK = 0,
    LUB_SHEAR_NOMEM = -1,
    LUB_SHEAR_CELL_TOO_SMALL = -2, /* the cell is narrower than twice the listing distance */
    LUB_SHEAR_NONFINITE = -3,      /* a pair law or a particle became non-finite */
    LUB_SHEAR_DEGENERATE = -4,     /* det H <= 0 */
    LUB_SHEAR_RUNAWAY = -5 /* a particle moved more than half the cell's width in one step */
};

enum {
    LUB_SAMPLE_STRESS = 1u << 0, /* full stress decomposition + pair counts */
    LUB_SAMPLE_SYY = 1u << 1,    /* only sigma_yy (total), cheap, for the pressure servo */
    LUB_SAMPLE_PDF = 1u << 2     /* microstructure snapshot into sys->pdf (read on copies of
                                    the pair states: the step is the one without it) */
};

typedef struct {
    lub_stress stress; /* divided by the volume */
    double syy;        /* total sigma_yy (LUB_SAMPLE_SYY or LUB_SAMPLE_STRESS) */
    size_t n_active;   /* pairs inside the cut-off */
    size_t n_contacts; /* pairs in contact (u < eps a) */
    size_t n_crushed; /* contacts with u_n < -alpha eps a: asperities crushed, the bulk spring and a
                         persistent lubrication force carry the load (notes §11 P5); a non-zero
                         count means the stiffness is too low for the stress level */
    size_t n_sliding; /* contacts sliding at the Coulomb limit (|F_s,contact| = mu |F_c|) */
} lub_shear_sample;

typedef struct {
    int n;
    vec3 *x, *v, *w, *f, *t, *x_ref;
    double *r, *m, *inv_m, *inv_i;
    double *inv_i_share; /* lub_inertia_share(inv_i, close (u < a) neighbours at the last
                            step): the inverse inertia the pair law is given */
    double *row_scratch; /* [2n] Gershgorin row sums of lub_shear_step_control */
    int *img;            /* [3n] cell images removed by wrapping so far, in the current cell
                            vectors (unwrapped x + H img; carried through flips) */
    lub_cell cell;
    double h_ref[3][3];
    lub_nlist nl;
    lub_nlist bond_nl; /* lub_shear_bond_order_q6's own list, built only where the pair list
                          does not reach its bonds (empty otherwise) */
    lub_pairs pairs;
    lub_law_params law;
    double cutoff; /* lubrication cut-off, units of the pair mean radius */
    double dt, time;
    long step;
    int threads;
    int batch_law; /* 1 (default): steps without a stress sample evaluate the law 4 or 8 pairs
                      per vector operation (lub_pair_eval_range, contact_batch.h); 0: the scalar
                      lub_pair_step for every pair. Results agree to round-off. */
    double drag_viscosity; /* eta_d >= 0 of the drag towards the affine flow (step 4); 0 after
                              init (no drag); the resuspension scene's gradient-orientation
                              shear drag, for comparisons */
    int need_rebuild;
    long rebuilds, flips;
    long lost_pairs; /* sum over rebuilds of lub_pairs.lost: active pair states dropped while
                        the pair was still listed as inside the cut-off (0 in a correct run) */
    /* interaction set: topology_interval > 0 restricts the lubricated pairs to the neighbours
     * of the regular triangulation (pair_topology.h), recomputed at every rebuild and every
     * topology_interval steps; 0 (after init): every pair inside the cut-off */
    int topology_interval;
    long topology_step; /* the step whose positions the interaction set was last computed from
                           (a rebuild or an update), -1 before the first: a step whose set a
                           network frame has just brought up to date does not recompute it */
    lub_topology topo;
    double skin_used; /* skin consumed since the last rebuild (the skin criterion's left side) */
    /* per-thread scratch (allocated at init) */
    lub_stress *tstress;
    double *tsyy;
    size_t *tcount;      /* [LUB_COUNT_N * threads], indexed by LUB_COUNT_* */
    lub_pair_accum *acc; /* [threads] per-particle pair sums of each thread (pair_accum.h) */
    int team;            /* threads of the last step's team (accumulators in use) */
    int team_min;        /* smallest team of the steps since init (0: no step yet): below
                            `threads` when OpenMP gave fewer (OMP_THREAD_LIMIT, OMP_DYNAMIC) */
    lub_pdf pdf;         /* accumulated snapshots (if enabled) */
    lub_pdf *tpdf;       /* [threads] or NULL */
    /* failure report */
    long fail_pair; /* pair index or -1 */
    char fail_msg[256];
} lub_shear_system;

/* Copies n radii and positions; density rho gives m = 4/3 pi r^3 rho, I = 2/5 m r^2.
 * Velocities are set to the affine flow L x of `cell` and spins to the mean vorticity.
 * pdf_theta/pdf_phi > 0 enable the microstructure accumulators. Returns LUB_SHEAR_*. */
int lub_shear_init(lub_shear_system *s, int n, const double *radius, const vec3 *pos,
                   const lub_cell *cell, const lub_law_params *law, double rho, double cutoff,
                   double skin, double dt, int threads, int pdf_theta, int pdf_phi);
void lub_shear_free(lub_shear_system *s);

/* Restricts the lubricated pairs to the Delaunay (power-diagram) neighbours, updated at every
 * neighbour-list rebuild and every `interval` steps (>= 1); pairs closer than guard*a are always
 * allowed. The neighbour list then lists every pair closer than lub_topology_reach(r_min,
 * r_max, cutoff) + skin too (the faces' certification, pair_topology.h), so the cell must hold
 * twice that listing distance. Call after lub_shear_init, before the first step. */
void lub_shear_use_delaunay(lub_shear_system *s, int interval, double guard);

/* For packings of radius_std (their radii taken in lub_packing_radius_clip's bounds,
 * before the packing divides them by their mean): the listing range of mean-size pairs in units of
 * a (they are listed at u_n < range a + skin: the cut-off, or the Delaunay set's reach), for the
 * memory estimate; and the largest listing distance (length, skin included), which half the cell's
 * width must exceed. Pure. */
double lub_shear_list_range(double cutoff, double radius_std, int delaunay);
double lub_shear_listing_distance(double cutoff, double radius_std, double skin, int delaunay);

/* Changes the velocity gradient to Lnew, adding (Lnew - L) x to every velocity (and the
 * change of mean spin to every spin), as for a homogeneous change of the imposed flow. */
void lub_shear_set_gradient(lub_shear_system *s, const double Lnew[3][3]);

/* One step. `flags` selects the sampling (LUB_SAMPLE_*); out may be NULL when flags == 0. */
int lub_shear_step(lub_shear_system *s, unsigned flags, lub_shear_sample *out);

/* Makes the pair list hold every pair inside the cut-off of the current positions: the
 * rebuild (flip, wrap, list, Delaunay flags) that the next step would do first when the last
 * step found the Verlet skin possibly used up, or else the Delaunay update the next step
 * would do first (it then does it again, with the same result); nothing otherwise. The
 * physical state is
 * unchanged (positions move by cell vectors, the cell matrix by a flip). Returns LUB_SHEAR_OK,
 * LUB_SHEAR_NOMEM or LUB_SHEAR_CELL_TOO_SMALL (fail_msg set). */
int lub_shear_complete_list(lub_shear_system *s);

/* Forces a rebuild (and flip/wrap) at the next step. */
static inline void lub_shear_request_rebuild(lub_shear_system *s) { s->need_rebuild = 1; }

/* Elastic time-step bound sqrt(min(m/g, I/(k_t r^2))) over the particles (viscosity-free,
 * notes §7). */
double lub_shear_elastic_dt(const lub_shear_system *s);

/* lub_step_control_at_rebuild (step_stiffness.h) for this system's pairs, bodies and scratch:
 * after a step, 1 when a rebuild since the last call changed c->dt (set s->dt to it and
 * reschedule). Serial, a few passes over the pairs at a rebuild, no allocation. */
int lub_shear_step_control(lub_shear_system *s, lub_step_control *c);

/* Heap bytes held by the system (particle arrays, neighbour list, pair store, scratch). */
size_t lub_shear_memory_bytes(const lub_shear_system *s);

/* Expected pairs per particle in the neighbour list (u_n < cutoff a_ij + skin) of a random
 * packing at solid fraction phi with Gaussian radii (mean 1, relative std radius_std), for an
 * uncorrelated pair distribution beyond contact: measured lists hold 1.0-1.1 times it at
 * cut-off 2 a and more at small cut-offs (contacts; tests/shear/test_memory_estimate.c). Pure. */
double lub_shear_listed_pairs_estimate(double phi, double radius_std, double cutoff, double skin);

/* Lower bound of the heap bytes a system of n spheres holds after its first neighbour-list
 * rebuild (lub_shear_memory_bytes then): particle arrays, per-thread sums, and the neighbour
 * list and one buffer of the pair store for 0.9 times the estimated pairs; with `rebuilt`,
 * after its second rebuild, when the store's second buffer holds them too. A run's peak is
 * higher (capacity margins, growth: ~5 kB per particle at phi 0.5 against a bound of 3.6).
 * Pure; n as a double so that no size overflows. */
double lub_shear_min_bytes(double n, double phi, double radius_std, double cutoff, double skin,
                           int threads, int rebuilt);

/* A shear strain after which the neighbour list has certainly been rebuilt again: the affine
 * part of the skin rule alone, strain * d_list > skin, with d_list >= (2 + cutoff) a + skin
 * (mean radius a). Pure. */
double lub_shear_rebuild_strain(double cutoff, double skin);

/* Solid fraction (sum of sphere volumes / cell volume). */
double lub_shear_phi(const lub_shear_system *s);
/* Global bond-orientational order Q6 (bond_order.h) of the pairs whose centre distance (nearest
 * image) is below bond_factor (r_i + r_j), from the current positions; NaN without such a pair.
 * *bonds (may be NULL) gets the number of such pairs: random bond directions give Q6 of about
 * 1/sqrt(bonds). Every such pair counts: the pair list (and its image shifts) is read when it
 * holds them all, i.e. when its guaranteed reach (2 + cutoff) a_ij + skin - skin_used covers
 * bond_factor (r_i + r_j) for the largest pair (at cut-off >= 2 (bond_factor - 1), 0.4 a for
 * the scene's 1.2, whenever the skin is not overspent); otherwise a list of its own is built
 * (bond_nl: range 2 (bond_factor - 1), no skin; it allocates at its first build, made before the
 * time loop by lub_shear_bond_order_prepare, and later only if its pairs outgrow the first
 * build's headroom), or, where that cannot be built (cell narrower than twice its listing
 * distance, no memory), every pair is searched (O(n^2)). Until 2026-12-07 only the pair list was
 * read, which at small cut-off and skin misses bonds (cut-off 0.1, skin 0.05: 803 of 1081 bonds
 * at N 300, phi 0.5). Serial; the physical state is unchanged. */
double lub_shear_bond_order_q6(lub_shear_system *s, double bond_factor, long *bonds);

/* Builds bond_nl now (so that it allocates before the time loop, not at the first sample of
 * lub_shear_bond_order_q6 that needs it) when the pair list cannot hold every bond once its skin
 * is spent (cut-off below 2 (bond_factor - 1) r_max); otherwise does nothing. Returns
 * LUB_NLIST_OK, LUB_NLIST_NOMEM or LUB_NLIST_CELL_TOO_SMALL (then lub_shear_bond_order_q6
 * searches every pair, without allocating). */
int lub_shear_bond_order_prepare(lub_shear_system *s, double bond_factor);

#endif

/* packing.h — random dense packings of polydisperse spheres in a periodic cube.
 *
 * Algorithm (documented in the README section of the simple_shear scene):
 *  1. radii r_i = 1 + std * N(0,1), clipped to [1 - 3 std, 1 + 3 std] (and > 0.2), then scaled
 *     so that their mean is exactly 1 (the length unit a);
 *  2. random sequential placement without overlap in a dilute cube (phi_0 = min(phi, 0.25)),
 *     each trial position tested against the spheres in the neighbouring bins of a grid;
 *  3. compression by affine rescaling in volume steps of at most 3 %, each followed by an
 *     overlap-removal relaxation (Jacobi displacement iterations on radii inflated by `margin`),
 *     until phi is reached and every inflated overlap is below margin/2 of the pair radius sum,
 *     measured both before and after the last sweep's displacement: so every true gap is
 *     >= margin/2 * (r_i + r_j) = margin * a_ij, a_ij = (r_i + r_j)/2 (to round-off, ~1e-15 a,
 *     from the final wrapping; the smallest ratio over ~100 packings at phi 0.5-0.62 was
 *     0.50002 margin (r_i + r_j)). Until 2026-12-07 the overlaps were measured only before the
 *     displacement and the end checked only that every gap was positive.
 * Finally the spheres are renumbered along spatial bins (memory locality of pair loops); above
 * LUB_PACKING_SORT_MIN_N spheres also before step 3 (its sweeps' locality).
 * Reproducible: a pure function of (n, phi, std, seed, margin).
 *
 * Memory: allocates its work arrays on entry and frees them on exit (setup only, not used
 * in time loops). Outputs are caller-owned arrays of length n.
 */
#ifndef LUBDEM_PACKING_H
#define LUBDEM_PACKING_H

#include <signal.h>
#include <stdint.h>

#include "periodic_cell.h"

typedef struct {
    int n;             /* number of spheres (>= 2) */
    double phi;        /* target solid fraction, > 0; see LUB_PACKING_GROWN_PHI_MAX */
    double radius_std; /* relative standard deviation of radii, [0, 0.3] */
    uint64_t seed;
    double margin;           /* relative radius inflation during relaxation (e.g. 0.01), > 0 */
    int max_sweeps;          /* safety cap on relaxation sweeps in total (e.g. 200000); a
                                jammed compression usually stops earlier (stall rule below) */
    int placement_all_pairs; /* 0 (default): step 2 tests a trial position against the spheres
                                of its neighbouring bins, O(n); 1: against every sphere placed,
                                O(n^2). Same packing either way (tests compare them) */
    int presort;             /* renumbering before step 3: 0 (default) above LUB_PACKING_SORT_MIN_N
                                spheres, 1 always, -1 never. Same packing to round-off either way (tests
                                compare them), not bit for bit */
    const volatile sig_atomic_t *stop; /* optional (NULL: never): once *stop is non-zero the
                                          placement gives up within 4096 spheres, the
                                          compression at its next relaxation sweep
                                          (SIGTERM during a large packing) */
} lub_packing_params;

/* Filled on success and on failure (not out of memory: -1). On failure: phi the fraction of the
 * compression stage reached (0 if refused before packing), sweeps those done, min_gap the
 * smallest gap then (negative: an overlap; NaN if refused before packing or stopped, -3). */
typedef struct {
    double phi;     /* achieved solid fraction (equal to the target up to round-off) */
    double min_gap; /* smallest surface gap u_n = |d| - r_i - r_j found (> 0 on success) */
    int sweeps;     /* relaxation sweeps used */
} lub_packing_info;

/* Solid fractions. The gaps promised (>= margin a_ij) make the spheres grown by margin/2 a
 * packing of its own, of fraction phi (1 + margin/2)^3: above LUB_PACKING_GROWN_PHI_MAX
 * (random close packing of near-equal spheres is ~0.64) lub_packing_generate returns -2 at
 * once. Reliably reached (every seed tried): phi (1 + margin/2)^3 <= 0.62 (the scenes:
 * simple_shear /phi <= 0.6 with /initial_gap up to its bound, resuspension layers <= 0.55 with
 * margin 0.01); at phi 0.62, margin 0.01 (0.629) about half the seeds fail (11 of 24 at n 300,
 * 19 of 40 in an audit). A failing compression jams: its worst overlap stops decreasing, and
 * once the smallest worst overlap of a compression stage has not fallen by
 * LUB_PACKING_STALL_GAIN of itself over LUB_PACKING_STALL_SWEEPS sweeps the packing gives up
 * (-2). At n 300, phi 0.62, margin 0.01 (24 seeds) checks every 50 000 sweeps would have
 * stopped 2 of the 13 successes, every 100 000 none, and they stop the 11 failures after
 * 207 000-309 000 sweeps (5-8 s); packings at phi <= 0.6 never went 4000 sweeps without such a
 * gain. Until 2026-12-07 a jammed compression went on to max_sweeps (2e6 in the scenes: 45-63 s
 * at n 300, phi 0.62-0.66). */
#define LUB_PACKING_GROWN_PHI_MAX 0.66
#define LUB_PACKING_STALL_SWEEPS 100000
#define LUB_PACKING_STALL_GAIN 1e-6

/* Fills radius[n] and pos[n] (wrapped in the cube) and initialises *cell to the cube.
 * Returns 0 on success, -1 if out of memory, -2 if the target could not be reached without
 * overlaps within max_sweeps (phi too high), -3 if *p->stop was set, -4 if the cube becomes
 * narrower than twice the inflated contact distance 2 r_max (1 + margin), where the pair search
 * cannot run: too few spheres for their size (with radius std 0.05: n <= 5 at phi 0.3, n <= 9
 * at phi 0.5; more with a wider spread, whose r_max is larger). The scenes refuse such sizes
 * before packing. Until 2026-12-07 this was -2. Outputs unusable unless 0. */
int lub_packing_generate(const lub_packing_params *p, double *radius, vec3 *pos, lub_cell *cell,
                         lub_packing_info *info);
/* The radii lub_packing_generate gives for *p (the same draw, into radius[p->n]) and the side
 * of the cube it packs them into, cbrt(sum of volumes / p->phi): what a caller checks before
 * paying for the packing. Pure; no allocation. */
double lub_packing_radii(const lub_packing_params *p, double *radius);
/* The clip [*lo, *hi] = [max(1 - 3 radius_std, 0.2), 1 + 3 radius_std] of the radii
 * lub_packing_generate draws, before it divides them by their mean. Pure. */
void lub_packing_radius_clip(double radius_std, double *lo, double *hi);
/* Every radius lub_packing_generate gives lies in [*lo, *hi]: it draws radii from a normal of
 * mean 1 and standard deviation radius_std clipped to [c_lo, c_hi] = [max(1 - 3 radius_std,
 * 0.2), 1 + 3 radius_std] and divides them by their mean (itself in [c_lo, c_hi]), so
 * lo = c_lo/c_hi and hi = c_hi/c_lo. */
void lub_packing_radius_bounds(double radius_std, double *lo, double *hi);

/* Above this many spheres the placement is renumbered spatially before the compression
 * (memory locality; see packing.c). */
#define LUB_PACKING_SORT_MIN_N 65536

/* The gaps of a packing (or any state) against a contact threshold: over all pairs (listed
 * images; a cell too small for the list: nearest images), the smallest surface gap in units of
 * a_ij = (r_i + r_j)/2 and the number of pairs with u_n < below a_ij (the pairs a roughness
 * eps = below counts as contacts). O(n) with neighbour lists of growing range. Returns 0, -1
 * out of memory. */
typedef struct {
    double min_gap_a; /* smallest u_n / a_ij */
    long long below;  /* pairs with u_n < below a_ij */
} lub_packing_gaps;
int lub_packing_gap_census(const lub_cell *cell, const vec3 *pos, const double *radius, int n,
                           double below, lub_packing_gaps *out);

/* Smallest gap over all pairs (brute force O(n^2), for tests and checks). */
double lub_packing_min_gap(const lub_cell *cell, const vec3 *pos, const double *radius, int n);

#endif

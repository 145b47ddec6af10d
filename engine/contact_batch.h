/* contact_batch.h — the lubricated contact law (contact_law.h) evaluated for a batch of pairs
 * at once, 4 or 8 pairs per vector operation (simd_math.h), for the common regime of a
 * many-particle time step.
 *
 * What it computes: exactly the step of lub_pair_step() (same equations, same branches, taken
 * lane by lane with masks) for the lanes it accepts, and only the outputs a time step needs
 * (force on body 1, torques on both bodies, contact and u < a flags) plus the state update.
 * Results agree with lub_pair_step to round-off (the transcendental functions are those of
 * simd_math.h, within 2 ulp of libm; tests/law/test_contact_batch.c checks every output and
 * the state against the scalar law over all regimes).
 *
 * Lanes it declines (done[l] = 0; their state is NOT touched) must be evaluated by the
 * caller with lub_pair_step, which handles them exactly:
 *  - a new pair (lub_pair_state_is_new), coincident centres, non-finite input;
 *  - a deep gap: stored x = u/a outside [e^-700, e^700] (delta outside [-700, 700]), or a
 *    result x+ = u/a not a normal double
 *    (permanently compressed contacts, notes §11 P5), or either closed-form term underflowing
 *    (the cases contact_normal.c sends to its bracketed solve);
 *  - u/a > 8 without shear-lubrication log form (only with cut-offs beyond 8a);
 *  - the antiparallel-normal corner of the shear-force rotation, a non-finite result;
 *  - a stored shear force with 0 < |F_s|^2 < 1e-200 or > 1e200, or a spin about the normal with
 *    (dt (w1 + w2).n / 2)^2 / 4 > 1e50 (the kernel's shared reciprocal must stay normal).
 * The whole batch is declined when normal lubrication is off or eta <= 0 (the quasi-static
 * branch of the law).
 *
 * Units: those of contact_law.h. No allocation, no global state; the batch is owned by the
 * caller (typically on its stack, about 10 kB). Safe to call concurrently on distinct batches
 * whose states are distinct.
 */
#ifndef LUBDEM_CONTACT_BATCH_H
#define LUBDEM_CONTACT_BATCH_H

#include "contact_law.h"

#define LUB_BATCH 32 /* lanes per call; a multiple of the vector width (4 or 8) */

typedef struct {
    int n; /* lanes in use, 0..LUB_BATCH */
    /* inputs, lane l < n (same meaning as lub_pair_input; v2 includes the image shift) */
    double bx[LUB_BATCH], by[LUB_BATCH], bz[LUB_BATCH];
    double v1x[LUB_BATCH], v1y[LUB_BATCH], v1z[LUB_BATCH];
    double v2x[LUB_BATCH], v2y[LUB_BATCH], v2z[LUB_BATCH];
    double w1x[LUB_BATCH], w1y[LUB_BATCH], w1z[LUB_BATCH];
    double w2x[LUB_BATCH], w2y[LUB_BATCH], w2z[LUB_BATCH];
    double r1[LUB_BATCH], r2[LUB_BATCH];
    double inv_i1[LUB_BATCH], inv_i2[LUB_BATCH]; /* as lub_pair_input.inv_inertia1/2 */
    lub_pair_state *state[LUB_BATCH];            /* borrowed; updated for accepted lanes */
    /* outputs, valid where done[l] = 1. The kernel may overwrite the force and torque
     * entries of the other lanes, and it writes the inputs and outputs of the padding lanes
     * n..(n rounded up to the vector width) - 1: their values carry no meaning. */
    double f1x[LUB_BATCH], f1y[LUB_BATCH], f1z[LUB_BATCH]; /* force on body 1 */
    double t1x[LUB_BATCH], t1y[LUB_BATCH], t1z[LUB_BATCH]; /* torque on body 1 */
    double t2x[LUB_BATCH], t2y[LUB_BATCH], t2z[LUB_BATCH]; /* torque on body 2 */
    unsigned char contact[LUB_BATCH];                      /* u < eps a after the step */
    unsigned char near[LUB_BATCH];                         /* u < a (delta < 0) after the step */
    unsigned char done[LUB_BATCH]; /* 1: evaluated here; 0: caller must use lub_pair_step */
} lub_pair_batch;

/* Steps lanes 0..b->n-1 with time step dt. Returns the number of accepted lanes. */
int lub_pair_step_batch(const lub_law_params *p, double dt, lub_pair_batch *b);

/* Lanes per vector operation of the kernel (LUB_VW of simd_math.h: 4 or 8). */
int lub_pair_batch_width(void);

/* 1 if the kernel was compiled for AVX2+FMA or AVX-512, where it is faster than the scalar law;
 * 0 for the SSE2 build (correct, but slower than lub_pair_step: callers use the scalar law). */
int lub_pair_batch_accelerated(void);

/* The vector exp and log of simd_math.h as compiled into this kernel: lub_pair_batch_width()
 * values from x into y (for tests: the vector types cannot cross into files compiled for
 * another instruction set). */
void lub_pair_batch_exp(const double *x, double *y);
void lub_pair_batch_log(const double *x, double *y);

/* Name of the instruction set the batch kernel was compiled for ("avx512", "avx2+fma", "avx" or
 * "sse2"). */
const char *lub_pair_batch_isa(void);

#endif

/* bench_law.c — cost of one lub_pair_step on random realistic pairs (LABELS bench).
 * 65536 pairs (gaps 1e-6 a ... 1.5 a, ~30 % created in contact for eps = 1e-3, random spins
 * and velocities). Prints ns/pair for a hot-cache loop over 1024 pairs (the cost of the law)
 * and ns/pair_streaming for sweeps over all 65536 pairs (memory traffic included). The state
 * evolves between sweeps, so every branch is exercised. Also prints ns/pair_batched: the same
 * 1024 hot pairs through lub_pair_step_batch (contact_batch.h) in batches of LUB_BATCH, with
 * the declined lanes (if any) through lub_pair_step, and batch_declined_fraction. */
#include "contact_batch.h"
#include "contact_law.h"
#include "law_rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define NP 65536

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts); /* CPU time: robust to a loaded machine */
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(void)
{
    lub_pair_input *in = malloc(NP * sizeof *in);
    lub_pair_state *st = calloc(NP, sizeof *st);
    lub_pair_output *out = malloc(NP * sizeof *out);
    if (!in || !st || !out)
        return 2;
    law_rng r = {2024};
    const lub_law_params p = {.eta = 1.0,
                              .k_bulk = 1e4,
                              .alpha = 1.0,
                              .k_t = 5e3,
                              .eps = 1e-3,
                              .mu = 0.5,
                              .terms = LUB_TERM_ALL};
    for (int i = 0; i < NP; ++i) {
        double r1 = law_rng_range(&r, 0.95, 1.05), r2 = law_rng_range(&r, 0.95, 1.05);
        double a = 0.5 * (r1 + r2);
        vec3 n = v3(law_rng_range(&r, -1, 1), law_rng_range(&r, -1, 1), law_rng_range(&r, -1, 1));
        n = v3_scale(n, 1.0 / v3_norm(n));
        double un = (law_rng_uniform(&r) < 0.3) ? -a * law_rng_range(&r, 0.0, 1e-3)
                                                : a * law_rng_logrange(&r, 1e-6, 1.5);
        in[i] = (lub_pair_input){.branch = v3_scale(n, r1 + r2 + un),
                                 .v1 = v3(law_rng_range(&r, -1, 1), 0.1, 0),
                                 .v2 = v3(0, law_rng_range(&r, -1, 1), 0.2),
                                 .w1 = v3(0.1, law_rng_range(&r, -1, 1), 0),
                                 .w2 = v3(0, 0, law_rng_range(&r, -1, 1)),
                                 .r1 = r1,
                                 .r2 = r2,
                                 .inv_inertia1 = 6.0,
                                 .inv_inertia2 = 6.0,
                                 .dt = 1e-4};
        lub_pair_state_reset(&st[i]);
    }
    int bad = 0;
    for (int i = 0; i < NP; ++i) /* warm-up: create the pairs */
        bad |= lub_pair_step(&p, &in[i], &st[i], &out[i]);
    /* streaming: all NP pairs per sweep (~37 MB of pair data, memory-bound like a real sweep) */
    const int sweeps = 40;
    double t0 = now();
    for (int k = 0; k < sweeps; ++k)
        for (int i = 0; i < NP; ++i)
            bad |= lub_pair_step(&p, &in[i], &st[i], &out[i]);
    double t1 = now();
    /* hot cache: the first 1024 pairs (~0.6 MB) over and over: the cost of the law itself */
    const int hot = 1024, hsweeps = 2560;
    double t2 = now();
    for (int k = 0; k < hsweeps; ++k)
        for (int i = 0; i < hot; ++i)
            bad |= lub_pair_step(&p, &in[i], &st[i], &out[i]);
    double t3 = now();
    /* the same hot pairs through the batched kernel (inputs transposed once, outside the
     * timing: in the engine the pre-pass that fills the lanes is timed with the system) */
    static lub_pair_batch batches[1024 / LUB_BATCH];
    for (int g = 0; g < hot / LUB_BATCH; ++g) {
        lub_pair_batch *b = &batches[g];
        b->n = LUB_BATCH;
        for (int l = 0; l < LUB_BATCH; ++l) {
            const lub_pair_input *q = &in[g * LUB_BATCH + l];
            b->bx[l] = q->branch.x, b->by[l] = q->branch.y, b->bz[l] = q->branch.z;
            b->v1x[l] = q->v1.x, b->v1y[l] = q->v1.y, b->v1z[l] = q->v1.z;
            b->v2x[l] = q->v2.x, b->v2y[l] = q->v2.y, b->v2z[l] = q->v2.z;
            b->w1x[l] = q->w1.x, b->w1y[l] = q->w1.y, b->w1z[l] = q->w1.z;
            b->w2x[l] = q->w2.x, b->w2y[l] = q->w2.y, b->w2z[l] = q->w2.z;
            b->r1[l] = q->r1, b->r2[l] = q->r2;
            b->inv_i1[l] = q->inv_inertia1, b->inv_i2[l] = q->inv_inertia2;
            b->state[l] = &st[g * LUB_BATCH + l];
        }
    }
    long declined = 0;
    double tb0 = now();
    for (int k = 0; k < hsweeps; ++k)
        for (int g = 0; g < hot / LUB_BATCH; ++g) {
            lub_pair_batch *b = &batches[g];
            if (lub_pair_step_batch(&p, 1e-4, b) == LUB_BATCH)
                continue;
            for (int l = 0; l < LUB_BATCH; ++l)
                if (!b->done[l]) {
                    declined++;
                    bad |= lub_pair_step(&p, &in[g * LUB_BATCH + l], b->state[l],
                                         &out[g * LUB_BATCH + l]);
                }
        }
    double tb1 = now();
    /* calibration on the same machine state: cost of one libm exp() */
    volatile double sink = 0.0;
    double acc = 0.0;
    const int ncal = 4000000;
    double t4 = now();
    for (int i = 0; i < ncal; ++i)
        acc += exp(-1e-7 * i);
    double t5 = now();
    sink = acc;
    (void)sink;
    long contacts = 0;
    for (int i = 0; i < NP; ++i)
        contacts += out[i].contact;
    printf("bench_pairs=%d\nbench_sweeps=%d\n", NP, sweeps);
    printf("bench_contact_fraction=%.3f\n", (double)contacts / NP);
    printf("ns/pair=%.1f\n", 1e9 * (t3 - t2) / ((double)hsweeps * hot));
    printf("ns/pair_streaming_65536_pairs=%.1f\n", 1e9 * (t1 - t0) / ((double)sweeps * NP));
    printf("ns/pair_batched=%.1f\nbatch_isa=%s\n", 1e9 * (tb1 - tb0) / ((double)hsweeps * hot),
           lub_pair_batch_isa());
    printf("batch_declined_fraction=%.4f\n", (double)declined / ((double)hsweeps * hot));
    printf("bench_libm_exp_ns=%.1f\n", 1e9 * (t5 - t4) / ncal);
    printf("bench_nonfinite=%d\n", bad);
    free(in);
    free(st);
    free(out);
    return bad ? 1 : 0;
}

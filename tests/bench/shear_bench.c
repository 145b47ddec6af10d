/* shear_bench.c — throughput of the sheared-suspension time step (issue 3 benchmark).
 * Dense random packing at phi = 0.50, radii 5 % std, cut-off 2a, skin 0.5a, all law terms,
 * stiffness 1e4, St = 1e-2 (units a = eta = gd = 1), 200 warm-up steps then `steps` timed steps
 * with a full stress sample every 50 steps (as the scene does). Prints name=value lines:
 *   shear_particle_steps_per_s (wall), shear_particle_steps_per_cpu_s (CPU time: meaningful
 *   on a loaded machine), shear_ns_per_active_pair, shear_ns_per_candidate_pair,
 *   shear_active_pairs_per_particle, shear_bytes_per_particle, shear_rebuild_every_steps
 *   shear_law_isa (instruction set of the batched law), shear_batch_law (1 batched, 0 scalar),
 *   shear_host_ghz_before/after (the rate of a chain of dependent integer adds, one per cycle:
 *   the clock the host gives this process just before and after the timed steps) and
 *   shear_cycles_per_particle_step (CPU seconds of all threads times their mean, per particle
 *   step: the cost of the code in cycles, which drifts far less than the host's speed)
 * usage: shear_bench N THREADS STEPS [scalar] [warmup=K]
 *   "scalar": every step with lub_pair_step; warmup=K: K untimed steps before the timed ones
 *   (default 200; the strain they cover is printed as shear_warmup_strain) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "contact_batch.h"
#include "packing.h"
#include "progress.h"
#include "shear_system.h"

static double cpu_seconds(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
           (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
}

/* Effective clock in GHz: 2e8 dependent integer adds (latency 1 cycle each on x86-64 and
 * AArch64), timed on the wall clock. On a shared virtual machine it falls when the host
 * throttles or shares the core; a hypervisor that hides the hardware counters leaves no better
 * gauge. */
static double host_ghz(void)
{
    const long iters = 200000000L;
    unsigned long x = 0;
    const double t0 = lub_wall_seconds();
    for (long k = 0; k < iters; ++k) {
        x += 1;
        __asm__ volatile("" : "+r"(x)); /* keeps the chain: no folding, no vectorising */
    }
    const double t = lub_wall_seconds() - t0;
    return (double)iters / t * 1e-9;
}

int main(int argc, char **argv)
{
    int n = argc > 1 ? atoi(argv[1]) : 1000;
    int threads = argc > 2 ? atoi(argv[2]) : 1;
    int steps = argc > 3 ? atoi(argv[3]) : 500;
    int batch_law = 1;
    long warmup = 200;
    for (int a = 4; a < argc; ++a) {
        const char *arg = argv[a];
        if (strcmp(arg, "scalar") == 0) {
            batch_law = 0;
            continue;
        }
        if (strncmp(arg, "warmup=", 7) == 0) {
            char *end = NULL;
            const long k = strtol(arg + 7, &end, 10);
            if (end != arg + 7 && *end == '\0' && k >= 0) {
                warmup = k;
                continue;
            }
        }
        fprintf(stderr, "shear_bench: bad argument '%s' (expected scalar or warmup=K, K >= 0)\n",
                arg);
        return 2;
    }
    double *r = malloc((size_t)n * sizeof *r);
    vec3 *x = malloc((size_t)n * sizeof *x);
    lub_cell c;
    lub_packing_params pp = {
        .n = n, .phi = 0.5, .radius_std = 0.05, .seed = 5, .margin = 0.01, .max_sweeps = 5000000};
    if (!r || !x || lub_packing_generate(&pp, r, x, &c, NULL)) {
        fprintf(stderr, "packing failed\n");
        return 1;
    }
    c.L[0][1] = 1.0;
    lub_law_params law = {.eta = 1,
                          .k_bulk = 1e4,
                          .alpha = 1,
                          .k_t = 5e3,
                          .eps = 0.02,
                          .mu = 0.5,
                          .terms = LUB_TERM_ALL};
    lub_shear_system s;
    if (lub_shear_init(&s, n, r, x, &c, &law, 1e-2, 2.0, 0.5, 1.0, threads, 0, 0)) {
        fprintf(stderr, "init failed\n");
        return 1;
    }
    s.dt = 0.3 * lub_shear_elastic_dt(&s);
    s.batch_law = batch_law;
    for (long k = 0; k < warmup; ++k)
        if (lub_shear_step(&s, 0, NULL)) {
            fprintf(stderr, "%s\n", s.fail_msg);
            return 1;
        }
    long rb0 = s.rebuilds;
    const double ghz0 = host_ghz();
    double t0 = lub_wall_seconds(), c0 = cpu_seconds();
    lub_shear_sample smp;
    double active = 0;
    int nsamp = 0;
    for (int k = 0; k < steps; ++k) {
        unsigned fl = (k % 50 == 0) ? LUB_SAMPLE_STRESS : 0u;
        if (lub_shear_step(&s, fl, &smp)) {
            fprintf(stderr, "%s\n", s.fail_msg);
            return 1;
        }
        if (fl) {
            active += (double)smp.n_active;
            nsamp++;
        }
    }
    double wall = lub_wall_seconds() - t0, cpu = cpu_seconds() - c0;
    const double ghz1 = host_ghz();
    active /= nsamp;
    double ps = (double)n * steps / wall;
    printf("shear_n=%d\nshear_threads=%d\nshear_steps=%d\nshear_wall_s=%.3f\n", n, threads, steps,
           wall);
    printf("shear_batch_law=%d\nshear_law_isa=%s\n", batch_law, lub_pair_batch_isa());
    printf("shear_warmup_steps=%ld\nshear_warmup_strain=%.3f\n", warmup, (double)warmup * s.dt);
    printf("shear_particle_steps_per_s=%.4g\n", ps);
    printf("shear_cpu_s=%.3f\n", cpu);
    printf("shear_particle_steps_per_cpu_s=%.4g\n", (double)n * steps / cpu);
    printf("shear_host_ghz_before=%.2f\nshear_host_ghz_after=%.2f\n", ghz0, ghz1);
    printf("shear_cycles_per_particle_step=%.0f\n",
           0.5 * (ghz0 + ghz1) * 1e9 * cpu / ((double)n * steps));
    printf("shear_ns_per_active_pair=%.1f\n", wall * 1e9 / (steps * active));
    printf("shear_cpu_ns_per_active_pair=%.1f\n", cpu * 1e9 / (steps * active));
    printf("shear_ns_per_candidate_pair=%.1f\n", wall * 1e9 / (steps * (double)s.pairs.n));
    printf("shear_active_pairs_per_particle=%.2f\n", active / n);
    printf("shear_bytes_per_particle=%.0f\n", (double)lub_shear_memory_bytes(&s) / n);
    long rb = s.rebuilds - rb0;
    printf("shear_rebuild_every_steps=%.1f\n", rb > 0 ? (double)steps / rb : (double)steps);
    lub_shear_free(&s);
    free(r);
    free(x);
    return 0;
}

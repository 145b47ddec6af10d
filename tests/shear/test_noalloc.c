/* test_noalloc.c — the time loop of the sheared system does not allocate (issue 3 item 4).
 *
 * The program counts every malloc, calloc and realloc of the process (its own definitions
 * interpose glibc's and forward to __libc_malloc and friends, so the OpenMP runtime's and libc's
 * own allocations are counted too). Each case builds a system, runs a warm-up of 1500 steps
 * (the pair arrays and the neighbour list grow to their working size, with headroom), then
 * 3000 more steps with the scene's sampling pattern (sigma_yy every step, a full stress sample
 * every 50 steps, a microstructure snapshot every 100) and asserts that these steps
 * allocated nothing, and that they crossed at least 10 neighbour-list rebuilds, so the
 * rebuilds, the pair-state carry-over, (Delaunay case) the triangulation updates and the
 * scene's step control after each rebuild (lub_shear_step_control) are inside the measured
 * window. Cases: cut-off 2a at phi 0.50 on 1 and 2 threads; the Delaunay set on
 * 2 threads; a cell whose gradient dimension breathes by +-2 % (a stand-in for the imposed-
 * pressure servo, which moves L_yy), so the bin grid and the pair count change; cut-off 0.1a
 * with the scene's bond order (lub_shear_bond_order_q6) at each full stress sample of the
 * measured steps, whose own bond list (the pair list does not reach 1.2 (r_i + r_j) once the
 * skin is partly spent) must have been built before them (lub_shear_bond_order_prepare).
 *
 * Under AddressSanitizer the allocator is the sanitizer's, which these definitions would
 * bypass: the sanitizer build does not build this test (tests/shear/CMakeLists.txt). */
#include <math.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#if defined(__SANITIZE_ADDRESS__)
#error "test_noalloc replaces the allocator: build it without AddressSanitizer"
#endif

#include "shear_fixture.h"
#include "shear_system.h"
#include "shear_test.h"

static atomic_long alloc_calls;

extern void *__libc_malloc(size_t n);
extern void *__libc_calloc(size_t n, size_t size);
extern void *__libc_realloc(void *p, size_t n);

void *malloc(size_t n)
{
    atomic_fetch_add_explicit(&alloc_calls, 1, memory_order_relaxed);
    return __libc_malloc(n);
}
void *calloc(size_t n, size_t size)
{
    atomic_fetch_add_explicit(&alloc_calls, 1, memory_order_relaxed);
    return __libc_calloc(n, size);
}
void *realloc(void *p, size_t n)
{
    atomic_fetch_add_explicit(&alloc_calls, 1, memory_order_relaxed);
    return __libc_realloc(p, n);
}

enum { CASE_CUTOFF, CASE_DELAUNAY, CASE_BREATHING, CASE_BOND_LIST };

/* the scene's bond factor of bond_order_q6 (scene_simple_shear.c) */
#define BOND_FACTOR 1.2

/* One case; its failures are recorded by ST_CHECK (a set-up or step failure ends it). */
static void run_case(const char *name, int kind, int threads)
{
    const lub_law_params law = shear_fixture_law(1e4);
    lub_shear_system s;
    const long at_start = atomic_load(&alloc_calls);
    /* N = 400 at phi 0.50, cut-off 2a (the bond-list case: 0.1a, below the bonds' 0.4a),
     * packing seed 3, St 1e-2, microstructure accumulators of 13 x 9 bins (the scene's
     * default) */
    const double cutoff = kind == CASE_BOND_LIST ? 0.1 : 2.0;
    const int rc = shear_fixture_make_pdf(&s, 400, 0.50, &law, cutoff, threads, 3, 1e-2, 13, 9);
    /* the counter sees the allocations of the set-up: the interposition works */
    ST_CHECK(atomic_load(&alloc_calls) - at_start >= 10, "%s: set-up counted %ld allocations", name,
             atomic_load(&alloc_calls) - at_start);
    ST_CHECK(rc == 0, "%s: setup rc %d", name, rc);
    if (rc != 0)
        return;
    if (kind == CASE_DELAUNAY)
        lub_shear_use_delaunay(&s, 10, 0.0);
    /* as the scene does before its time loop */
    ST_CHECK(lub_shear_bond_order_prepare(&s, BOND_FACTOR) == LUB_NLIST_OK, "%s: bond list", name);
    long bond_list_builds = 0; /* samples whose bond list differs from the previous one */
    size_t bond_pairs_before = s.bond_nl.npairs;
    ST_CHECK(s.tpdf != NULL, "%s: microstructure accumulators off", name);
    const int warm = 1500, measured = 3000;
    long before = 0, rebuilds0 = 0;
    lub_shear_sample smp;
    lub_step_control control;
    lub_step_control_init(&control, s.dt, 1.0);
    int failed = 0;
    for (int k = 0; k < warm + measured && !failed; ++k) {
        if (k == warm) {
            before = atomic_load(&alloc_calls);
            rebuilds0 = s.rebuilds;
        }
        if (kind == CASE_BREATHING) {
            /* H_yy(t) = H_yy(0) (1 + A sin(2 pi k/P)): L_yy = A (2 pi/(P dt)) cos(2 pi k/P) */
            const double amp = 0.02, period = 400.0, w = 2.0 * 3.14159265358979323846 / period;
            double L[3][3];
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    L[a][b] = s.cell.L[a][b];
            L[1][1] = amp * w / s.dt * cos(w * k);
            lub_shear_set_gradient(&s, L);
        }
        unsigned flags = LUB_SAMPLE_SYY;
        if (k % 50 == 0)
            flags |= LUB_SAMPLE_STRESS;
        if (k % 100 == 0)
            flags |= LUB_SAMPLE_PDF;
        const int src = lub_shear_step(&s, flags, &smp);
        if (src != LUB_SHEAR_OK) {
            ST_CHECK(src == LUB_SHEAR_OK, "%s: step %d rc %d (%s)", name, k, src, s.fail_msg);
            failed = 1;
        }
        /* the scene's bond order at each full stress sample, first in the measured steps, so
         * that a bond list built there for the first time would be counted */
        if (kind == CASE_BOND_LIST && k >= warm && (flags & LUB_SAMPLE_STRESS)) {
            long bonds = 0;
            const double q6 = lub_shear_bond_order_q6(&s, BOND_FACTOR, &bonds);
            ST_CHECK(bonds > 0 && q6 > 0.0 && q6 < 1.0, "%s: q6 %g of %ld bonds", name, q6, bonds);
            bond_list_builds += s.bond_nl.npairs != bond_pairs_before;
            bond_pairs_before = s.bond_nl.npairs;
        }
        /* the scene's step control at each rebuild (step_stiffness.h; here it keeps the step) */
        (void)lub_shear_step_control(&s, &control);
    }
    const long allocs = atomic_load(&alloc_calls) - before;
    const long rebuilds = s.rebuilds - rebuilds0;
    printf("noalloc_%s_setup_and_warmup_allocations=%ld\n", name, before - at_start);
    printf("noalloc_%s_allocations=%ld\n", name, allocs);
    printf("noalloc_%s_rebuilds=%ld\n", name, rebuilds);
    printf("noalloc_%s_pairs=%zu\n", name, s.pairs.n);
    if (kind == CASE_BOND_LIST) {
        printf("noalloc_%s_bond_list_builds=%ld\n", name, bond_list_builds);
        /* the pair list stopped holding the bonds at some samples: the bond list was rebuilt */
        ST_CHECK(bond_list_builds >= 3, "%s: the bond list was rebuilt at %ld samples", name,
                 bond_list_builds);
    }
    ST_CHECK(rebuilds >= 10, "%s: only %ld rebuilds in the measured steps", name, rebuilds);
    ST_CHECK(allocs == 0, "%s: %ld allocations in %d steps", name, allocs, measured);
    lub_shear_free(&s);
}

int main(void)
{
    run_case("cutoff_t1", CASE_CUTOFF, 1);
    run_case("cutoff_t2", CASE_CUTOFF, 2);
    run_case("delaunay_t2", CASE_DELAUNAY, 2);
    run_case("breathing_t1", CASE_BREATHING, 1);
    run_case("bond_list_t1", CASE_BOND_LIST, 1);
    ST_DONE();
}
